/*
 * program.c - compiling and linking the compute kernels; see program.h.
 */
#include "program.h"

#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../core/log.h"
#include "queue.h"
#include "shader_source.h"

static const char *const kernel_files[GPU_KERNEL_COUNT] = {
    [GPU_KERNEL_SMOOTH_IOR] = "smooth_ior.comp",
    [GPU_KERNEL_GRADIENT_IOR] = "gradient_ior.comp",
    [GPU_KERNEL_RENDER_VIEW] = "render_view.comp",
    [GPU_KERNEL_TRACE_RAYS] = "trace_rays.comp",
};

/* The variant bits that matter for a kernel. */
static unsigned variant_mask(enum gpu_kernel kernel)
{
    switch (kernel) {
    case GPU_KERNEL_RENDER_VIEW:
        return GPU_VARIANT_COUNT - 1;
    case GPU_KERNEL_TRACE_RAYS:
        return GPU_VARIANT_STEPPER_BITS | GPU_VARIANT_ATTENUATION | GPU_VARIANT_OPAQUE |
               GPU_VARIANT_SCATTERING | GPU_VARIANT_SKIP | GPU_VARIANT_IOR_TRICUBIC |
               GPU_VARIANT_SURFACES;
    default:
        return 0;
    }
}

/* Compiled on first use: the rare bits (GPU_VARIANT_LAZY), and skipping off where the
 * kernel has the skip bit (the default renders skip; only comparisons switch it off). */
static bool variant_is_lazy(unsigned v, unsigned mask)
{
    return (v & GPU_VARIANT_LAZY) != 0 || ((mask & GPU_VARIANT_SKIP) && !(v & GPU_VARIANT_SKIP));
}

static char *info_log(GLuint object, bool is_program)
{
    GLint len = 0;
    if (is_program)
        glGetProgramiv(object, GL_INFO_LOG_LENGTH, &len);
    else
        glGetShaderiv(object, GL_INFO_LOG_LENGTH, &len);
    char *log = calloc((size_t)len + 1, 1);
    if (log == NULL)
        return NULL;
    if (is_program)
        glGetProgramInfoLog(object, len, NULL, log);
    else
        glGetShaderInfoLog(object, len, NULL, log);
    return log;
}

GLuint gpu_program_create(const struct gpu_program_desc *desc, const char *shader_dir,
                          struct err *e)
{
    struct shader_source src;
    if (shader_source_expand(desc->main, shader_dir, desc->preamble, &src, e) != REFRACT_E_OK)
        return 0;
    GLuint shader = glCreateShader(GL_COMPUTE_SHADER);
    const char *text = src.text;
    glShaderSource(shader, 1, &text, NULL);
    glCompileShader(shader);
    GLint ok = 0;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char *log = info_log(shader, false);
        char *mapped = log ? shader_source_map_log(&src, log) : NULL;
        err_set(e, REFRACT_E_GPU_ERROR, "compiling %s failed:\n%s", desc->main,
                mapped ? mapped : "(no log)");
        free(mapped);
        free(log);
        glDeleteShader(shader);
        shader_source_fini(&src);
        return 0;
    }
    GLuint program = glCreateProgram();
    glAttachShader(program, shader);
    glLinkProgram(program);
    glDetachShader(program, shader);
    glDeleteShader(shader);
    glGetProgramiv(program, GL_LINK_STATUS, &ok);
    if (!ok) {
        char *log = info_log(program, true);
        char *mapped = log ? shader_source_map_log(&src, log) : NULL;
        err_set(e, REFRACT_E_GPU_ERROR, "linking %s failed:\n%s", desc->main,
                mapped ? mapped : "(no log)");
        free(mapped);
        free(log);
        glDeleteProgram(program);
        shader_source_fini(&src);
        return 0;
    }
    glObjectLabel(GL_PROGRAM, program, -1, desc->label);
    shader_source_fini(&src);
    return program;
}

struct gpu_programs_lazy {
    char *shader_dir; /* NULL: embedded shaders */
    /* The programs array lives in the const struct; variants built later are written
     * through this pointer to it (GPU thread only). */
    GLuint (*program)[GPU_VARIANT_COUNT];
};

static const char *stepper_define(unsigned v)
{
    switch (v & GPU_VARIANT_STEPPER_BITS) {
    case GPU_VARIANT_RK4:
        return "STEPPER_RK4";
    case GPU_VARIANT_RK2:
        return "STEPPER_RK2";
    case GPU_VARIANT_ADAPTIVE:
        return "STEPPER_ADAPTIVE";
    default:
        return "STEPPER_EULER";
    }
}

static GLuint build_variant(enum gpu_kernel k, unsigned v, const char *shader_dir, struct err *e)
{
    unsigned mask = variant_mask(k);
    char preamble[512], label[96];
    snprintf(preamble, sizeof preamble,
             "#define MARCH_STEPPER %s\n#define MARCH_IOR_FILTER %s\n"
             "#define MARCH_ATTENUATION %d\n"
             "#define MARCH_EMISSION %d\n#define MARCH_OPAQUE %d\n"
             "#define MARCH_SCATTERING %d\n#define MARCH_LIGHTS %d\n#define MARCH_SKIP %d\n"
             "#define MARCH_SURFACES %d",
             stepper_define(v),
             (v & GPU_VARIANT_IOR_TRICUBIC) ? "IOR_FILTER_TRICUBIC" : "IOR_FILTER_TRILINEAR",
             (v & GPU_VARIANT_ATTENUATION) ? 1 : 0, (v & GPU_VARIANT_EMISSION) ? 1 : 0,
             (v & GPU_VARIANT_OPAQUE) ? 1 : 0, (v & GPU_VARIANT_SCATTERING) ? 1 : 0,
             (v & GPU_VARIANT_LIGHTS) ? 1 : 0, (v & GPU_VARIANT_SKIP) ? 1 : 0,
             (v & GPU_VARIANT_SURFACES) ? 1 : 0);
    snprintf(label, sizeof label, "%s variant %u", kernel_files[k], v);
    struct gpu_program_desc desc = {
        .label = label, .main = kernel_files[k], .preamble = mask ? preamble : NULL};
    return gpu_program_create(&desc, shader_dir, e);
}

enum refract_code gpu_programs_build(struct gpu_programs *p, const char *shader_dir, struct err *e)
{
    memset(p, 0, sizeof *p);
    p->lazy = calloc(1, sizeof *p->lazy);
    if (p->lazy == NULL || (shader_dir && (p->lazy->shader_dir = strdup(shader_dir)) == NULL)) {
        gpu_programs_destroy(p);
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory building GPU programs");
    }
    p->lazy->program = p->program;
    int built = 0;
    for (int k = 0; k < GPU_KERNEL_COUNT; k++) {
        unsigned mask = variant_mask((enum gpu_kernel)k);
        for (unsigned v = 0; v < GPU_VARIANT_COUNT; v++) {
            if ((v & ~mask) != 0)
                continue;
            /* Lazy variants wait for their first use, except the one with every bit,
             * which proves the shaders compile. */
            if (variant_is_lazy(v, mask) && v != mask)
                continue;
            p->program[k][v] = build_variant((enum gpu_kernel)k, v, shader_dir, e);
            if (p->program[k][v] == 0) {
                gpu_programs_destroy(p);
                return e->code;
            }
            built++;
        }
    }
    log_info("gpu",
             "compiled %d compute programs (kernels x variants) from %s; variants with "
             "scattering, lights, rk2, adaptive, tricubic or surfaces, or without empty-space "
             "skipping, "
             "compile on first use",
             built, shader_dir ? shader_dir : "embedded shaders");
    return REFRACT_E_OK;
}

void gpu_programs_destroy(struct gpu_programs *p)
{
    for (int k = 0; k < GPU_KERNEL_COUNT; k++) {
        for (int v = 0; v < GPU_VARIANT_COUNT; v++) {
            if (p->program[k][v])
                glDeleteProgram(p->program[k][v]);
            p->program[k][v] = 0;
        }
    }
    if (p->lazy) {
        free(p->lazy->shader_dir);
        free(p->lazy);
        p->lazy = NULL;
    }
}

GLuint gpu_program_get_e(const struct gpu_programs *p, enum gpu_kernel kernel, unsigned variant,
                         struct err *e)
{
    unsigned v = variant & variant_mask(kernel);
    if (p->program[kernel][v] != 0 || p->lazy == NULL)
        return p->program[kernel][v];
    double t0 = gpu_time_ms();
    GLuint prog = build_variant(kernel, v, p->lazy->shader_dir, e);
    if (prog != 0) {
        p->lazy->program[kernel][v] = prog;
        log_info("gpu", "compiled %s variant %u on first use in %.0f ms", kernel_files[kernel], v,
                 gpu_time_ms() - t0);
    }
    return prog;
}

GLuint gpu_program_get(const struct gpu_programs *p, enum gpu_kernel kernel, unsigned variant)
{
    struct err e = {0};
    GLuint prog = gpu_program_get_e(p, kernel, variant, &e);
    if (prog == 0)
        log_error("gpu", "%s", e.msg);
    return prog;
}
