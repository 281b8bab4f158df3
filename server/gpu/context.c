/*
 * context.c - EGL device enumeration and the GL 4.5 core context.
 *
 * What it is: the start-up path that finds a GPU through EGL's device platform and
 * reports precisely what it saw when it cannot. What it is not: a window-system
 * integration (there is none) or a GL loader (glvnd's libOpenGL dispatches for us).
 */
#include "context.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include "../core/log.h"
#include "gl.h"

#define MAX_DEVICES 16

struct gpu_context {
    EGLDisplay display;
    EGLContext context;
    struct gpu_context_info info;
};

struct egl_fns {
    PFNEGLQUERYDEVICESEXTPROC query_devices;
    PFNEGLQUERYDEVICESTRINGEXTPROC query_device_string;
    PFNEGLGETPLATFORMDISPLAYEXTPROC get_platform_display;
};

int gpu_device_pref_parse(const char *name)
{
    if (strcmp(name, "auto") == 0)
        return GPU_DEVICE_AUTO;
    if (strcmp(name, "hardware") == 0)
        return GPU_DEVICE_HARDWARE;
    if (strcmp(name, "software") == 0)
        return GPU_DEVICE_SOFTWARE;
    return -1;
}

static bool has_extension(const char *list, const char *name)
{
    if (list == NULL)
        return false;
    size_t n = strlen(name);
    for (const char *p = list; (p = strstr(p, name)) != NULL; p += n) {
        bool starts = (p == list) || p[-1] == ' ';
        bool ends = p[n] == '\0' || p[n] == ' ';
        if (starts && ends)
            return true;
    }
    return false;
}

static bool load_egl_fns(struct egl_fns *f, struct err *e)
{
    const char *client_ext = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!has_extension(client_ext, "EGL_EXT_device_enumeration") ||
        !has_extension(client_ext, "EGL_EXT_platform_device")) {
        err_set(e, REFRACT_E_GPU_ERROR,
                "EGL lacks device enumeration (client extensions: %s). To fix this issue "
                "install glvnd's EGL and a vendor driver: `apt-get install libegl1 "
                "libegl-mesa0 libgl1-mesa-dri` (deploy/install-deps.sh does this)",
                client_ext ? client_ext : "none");
        return false;
    }
    f->query_devices = (PFNEGLQUERYDEVICESEXTPROC)eglGetProcAddress("eglQueryDevicesEXT");
    f->query_device_string =
        (PFNEGLQUERYDEVICESTRINGEXTPROC)eglGetProcAddress("eglQueryDeviceStringEXT");
    f->get_platform_display =
        (PFNEGLGETPLATFORMDISPLAYEXTPROC)eglGetProcAddress("eglGetPlatformDisplayEXT");
    if (!f->query_devices || !f->query_device_string || !f->get_platform_display) {
        err_set(e, REFRACT_E_GPU_ERROR, "EGL device functions are advertised but not found");
        return false;
    }
    return true;
}

static bool device_is_software(const struct egl_fns *f, EGLDeviceEXT dev)
{
    const char *ext = f->query_device_string(dev, EGL_EXTENSIONS);
    return has_extension(ext, "EGL_MESA_device_software");
}

/* Picks a device index by preference, or -1 with e filled. */
static int choose_device(const struct egl_fns *f, const EGLDeviceEXT *devs, int count,
                         enum gpu_device_pref pref, int forced_index, const char *devices_seen,
                         struct err *e)
{
    if (forced_index >= 0) {
        if (forced_index < count)
            return forced_index;
        err_set(e, REFRACT_E_GPU_ERROR, "--gpu-device %d: only %d EGL devices exist:\n%s",
                forced_index, count, devices_seen);
        return -1;
    }
    int first_hw = -1, first_sw = -1;
    for (int i = 0; i < count; i++) {
        if (device_is_software(f, devs[i])) {
            if (first_sw < 0)
                first_sw = i;
        } else if (first_hw < 0) {
            first_hw = i;
        }
    }
    if (pref == GPU_DEVICE_HARDWARE && first_hw < 0) {
        err_set(e, REFRACT_E_GPU_ERROR,
                "a hardware GPU was required (--gpu hardware or REFRACT_GPU=hardware) but EGL "
                "found none among %d devices:\n%s\nTo fix this issue install the GPU's EGL "
                "driver (e.g. NVIDIA's libnvidia-egl), or use --gpu software",
                count, devices_seen);
        return -1;
    }
    if (pref == GPU_DEVICE_SOFTWARE && first_sw < 0) {
        err_set(e, REFRACT_E_GPU_ERROR,
                "Mesa's software device was required but EGL found none among %d devices:\n%s\n"
                "To fix this issue: apt-get install libegl-mesa0 libgl1-mesa-dri",
                count, devices_seen);
        return -1;
    }
    if (pref == GPU_DEVICE_SOFTWARE)
        return first_sw;
    if (first_hw >= 0)
        return first_hw;
    if (first_sw >= 0)
        return first_sw;
    err_set(e, REFRACT_E_GPU_ERROR, "EGL found no usable device");
    return -1;
}

static void describe_devices(const struct egl_fns *f, const EGLDeviceEXT *devs, int count,
                             char *out, size_t size)
{
    size_t used = 0;
    out[0] = '\0';
    for (int i = 0; i < count && used < size; i++) {
        const char *ext = f->query_device_string(devs[i], EGL_EXTENSIONS);
        const char *drm = has_extension(ext, "EGL_EXT_device_drm")
                              ? f->query_device_string(devs[i], EGL_DRM_DEVICE_FILE_EXT)
                              : NULL;
        int n = snprintf(out + used, size - used, "  device %d: %s%s%s [%s]\n", i,
                         device_is_software(f, devs[i]) ? "software" : "hardware", drm ? " " : "",
                         drm ? drm : "", ext ? ext : "");
        if (n < 0)
            break;
        used += (size_t)n;
    }
}

static void GLAPIENTRY debug_callback(GLenum source, GLenum type, GLuint id, GLenum severity,
                                      GLsizei length, const GLchar *message, const void *user)
{
    (void)source;
    (void)id;
    (void)length;
    (void)user;
    if (severity == GL_DEBUG_SEVERITY_NOTIFICATION)
        return;
    log_warn("gl", "KHR_debug type 0x%x: %s", type, message);
}

static bool create_gl_context(struct gpu_context *c, const struct gpu_context_desc *desc,
                              struct err *e)
{
    EGLint major = 0, minor = 0;
    if (!eglInitialize(c->display, &major, &minor)) {
        err_set(e, REFRACT_E_GPU_ERROR, "eglInitialize failed (0x%x) on device %d", eglGetError(),
                c->info.device_index);
        return false;
    }
    if (!eglBindAPI(EGL_OPENGL_API)) {
        err_set(e, REFRACT_E_GPU_ERROR, "eglBindAPI(EGL_OPENGL_API) failed (0x%x)", eglGetError());
        return false;
    }
    const char *dpy_ext = eglQueryString(c->display, EGL_EXTENSIONS);
    if (!has_extension(dpy_ext, "EGL_KHR_surfaceless_context") ||
        !has_extension(dpy_ext, "EGL_KHR_no_config_context")) {
        err_set(e, REFRACT_E_GPU_ERROR,
                "EGL display lacks surfaceless/no-config contexts (extensions: %s)",
                dpy_ext ? dpy_ext : "none");
        return false;
    }
    EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                        4,
                        EGL_CONTEXT_MINOR_VERSION,
                        5,
                        EGL_CONTEXT_OPENGL_PROFILE_MASK,
                        EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                        EGL_CONTEXT_OPENGL_DEBUG,
                        desc->debug ? EGL_TRUE : EGL_FALSE,
                        EGL_NONE};
    c->context = eglCreateContext(c->display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attribs);
    if (c->context == EGL_NO_CONTEXT) {
        err_set(e, REFRACT_E_GPU_ERROR,
                "eglCreateContext for OpenGL 4.5 core failed (0x%x) on device %d (EGL "
                "%d.%d). The driver may not support GL 4.5: Mesa >= 20 (llvmpipe) and "
                "NVIDIA drivers do",
                eglGetError(), c->info.device_index, major, minor);
        return false;
    }
    if (!eglMakeCurrent(c->display, EGL_NO_SURFACE, EGL_NO_SURFACE, c->context)) {
        err_set(e, REFRACT_E_GPU_ERROR, "eglMakeCurrent failed (0x%x)", eglGetError());
        return false;
    }
    return true;
}

static void read_gl_info(struct gpu_context *c)
{
    struct gpu_context_info *info = &c->info;
    snprintf(info->vendor, sizeof info->vendor, "%s", (const char *)glGetString(GL_VENDOR));
    snprintf(info->renderer, sizeof info->renderer, "%s", (const char *)glGetString(GL_RENDERER));
    snprintf(info->version, sizeof info->version, "%s", (const char *)glGetString(GL_VERSION));
    glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &info->max_3d_texture_size);
    glGetIntegerv(GL_MAX_COMPUTE_WORK_GROUP_INVOCATIONS, &info->max_compute_work_group_invocations);
}

static enum gpu_device_pref effective_pref(enum gpu_device_pref pref)
{
    const char *env = getenv("REFRACT_GPU");
    if (pref == GPU_DEVICE_AUTO && env != NULL && gpu_device_pref_parse(env) >= 0)
        return (enum gpu_device_pref)gpu_device_pref_parse(env);
    return pref;
}

struct gpu_context *gpu_context_create(const struct gpu_context_desc *desc, struct err *e)
{
    struct egl_fns f;
    if (!load_egl_fns(&f, e))
        return NULL;
    EGLDeviceEXT devs[MAX_DEVICES];
    EGLint count = 0;
    if (!f.query_devices(MAX_DEVICES, devs, &count) || count <= 0) {
        err_set(e, REFRACT_E_GPU_ERROR,
                "EGL enumerated no devices (0x%x). To fix this issue install Mesa's software "
                "driver (apt-get install libegl-mesa0 libgl1-mesa-dri) or a GPU driver",
                eglGetError());
        return NULL;
    }
    struct gpu_context *c = calloc(1, sizeof *c);
    if (c == NULL) {
        err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory creating the GPU context");
        return NULL;
    }
    c->info.device_count = count;
    describe_devices(&f, devs, count, c->info.devices_seen, sizeof c->info.devices_seen);
    enum gpu_device_pref pref = effective_pref(desc->device);
    int index = choose_device(&f, devs, count, pref, desc->device_index, c->info.devices_seen, e);
    if (index < 0) {
        free(c);
        return NULL;
    }
    c->info.device_index = index;
    snprintf(c->info.device_kind, sizeof c->info.device_kind, "%s",
             device_is_software(&f, devs[index]) ? "software" : "hardware");
    const char *ext = f.query_device_string(devs[index], EGL_EXTENSIONS);
    snprintf(c->info.device_ext, sizeof c->info.device_ext, "%s", ext ? ext : "");
    c->display = f.get_platform_display(EGL_PLATFORM_DEVICE_EXT, devs[index], NULL);
    if (c->display == EGL_NO_DISPLAY) {
        err_set(e, REFRACT_E_GPU_ERROR, "eglGetPlatformDisplayEXT failed for device %d (0x%x)",
                index, eglGetError());
        free(c);
        return NULL;
    }
    if (!create_gl_context(c, desc, e)) {
        gpu_context_destroy(c);
        return NULL;
    }
    read_gl_info(c);
    if (desc->debug) {
        glEnable(GL_DEBUG_OUTPUT);
        glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
        glDebugMessageCallback(debug_callback, NULL);
    }
    log_info("gpu", "EGL device %d of %d (%s): %s | %s | %s", index, count, c->info.device_kind,
             c->info.vendor, c->info.renderer, c->info.version);
    return c;
}

void gpu_context_destroy(struct gpu_context *c)
{
    if (c == NULL)
        return;
    if (c->display != EGL_NO_DISPLAY) {
        eglMakeCurrent(c->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        if (c->context != EGL_NO_CONTEXT)
            eglDestroyContext(c->display, c->context);
        /* No eglTerminate: terminating the display makes Mesa dlclose its driver, after
         * which LeakSanitizer can no longer name (and tests/lsan.supp no longer suppress)
         * the driver's own small leaks at exit. The display is per-device and process-wide;
         * the next gpu_context_create on it simply initialises it again. */
    }
    eglReleaseThread();
    free(c);
}

const struct gpu_context_info *gpu_context_info(const struct gpu_context *c)
{
    return &c->info;
}
