/*
 * env.h - the environment at infinity (tevs2007 eq. 5.3's L_bg) and the camera, in
 * double precision. Twins of shaders/environment.glsl and shaders/camera.glsl; the
 * formulas are fixed by docs/tracing.md ("Camera", "Environment"). Tests compare
 * rendered background pixels against these.
 */
#ifndef REFRACT_ENV_H
#define REFRACT_ENV_H

#include "vec3.h"

/* Radiance of the procedural sky/ground environment in unit direction d (intensity 1). */
vec3 env_procedural(vec3 d);

/* Equirectangular lookup coordinates for direction d and a rotation about +y in
 * degrees: u in [0, 1) wrapping, v in [0, 1] with v = 0 at the zenith. */
void env_equirect_uv(vec3 d, double rotation_deg, double *u, double *v);

/* The view ray through the centre of pixel (col, row) (row 0 at the top). */
void camera_ray(vec3 eye, vec3 look_at, vec3 up, double fov_y_deg, int width, int height,
                double col, double row, vec3 *origin, vec3 *dir);

#endif
