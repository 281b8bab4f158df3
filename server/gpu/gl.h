/*
 * gl.h - the one place GL headers are included. refractd links glvnd's libOpenGL
 * (GL without GLX) and libEGL, so GL 4.5 entry points resolve through glvnd to the
 * vendor of the current EGL context; no extension loader is needed.
 */
#ifndef REFRACT_GL_H
#define REFRACT_GL_H

#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>

#endif
