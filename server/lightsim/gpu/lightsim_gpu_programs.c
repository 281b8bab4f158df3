/*
 * lightsim_gpu_programs.c - compiling the light simulator's kernels, and the prefix sum;
 * see lightsim_gpu_programs.h.
 */
#include "lightsim_gpu_programs.h"

#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../../core/log.h"
#include "../../gpu/program.h"
#include "lightsim_gpu.h"
#include "lightsim_gpu_wavefront.h" /* shared_types.h with the host's vector types */

static struct lightsim_gpu_programs programs;
static bool built;
static bool built_with_cas;

const struct lightsim_gpu_programs *lightsim_gpu_programs(void)
{
    return built ? &programs : NULL;
}

enum refract_code lightsim_gpu_init(struct gpu *gpu, struct err *e)
{
    (void)gpu; /* the programs come from the embedded sources, as gpu_create's do */
    if (built)
        return REFRACT_E_OK;
    /* REFRACT_LIGHTSIM_CAS_ATOMICS=1: float atomics by compare-and-swap even where
     * GL_NV_shader_atomic_float exists (the path of GPUs without it; for tests). */
    const char *cas_env = getenv("REFRACT_LIGHTSIM_CAS_ATOMICS");
    bool cas = cas_env != NULL && strcmp(cas_env, "1") == 0;
    const char *atomics = cas ? "#define LS_CAS_ATOMICS 1\n" : "";
    struct {
        GLuint *out;
        const char *label, *main, *preamble;
    } table[] = {
        {&programs.step, "lightsim step", "lightsim_step.comp", NULL},
        {&programs.emit, "lightsim emit", "lightsim_emit.comp", NULL},
        {&programs.step_surfaces, "lightsim step (surfaces)", "lightsim_step.comp",
         "#define LS_SURFACES 1"},
        {&programs.emit_surfaces, "lightsim emit (surfaces)", "lightsim_emit.comp",
         "#define LS_SURFACES 1"},
        {&programs.step_meshes, "lightsim step (meshes)", "lightsim_step.comp",
         "#define LS_SURFACES 1\n#define LS_MESHES 1"},
        {&programs.emit_meshes, "lightsim emit (meshes)", "lightsim_emit.comp",
         "#define LS_SURFACES 1\n#define LS_MESHES 1"},
        {&programs.scan[0], "lightsim scan blocks", "lightsim_scan.comp",
         "#define LS_SCAN_STAGE 0"},
        {&programs.scan[1], "lightsim scan sums", "lightsim_scan.comp", "#define LS_SCAN_STAGE 1"},
        {&programs.scan[2], "lightsim scan add", "lightsim_scan.comp", "#define LS_SCAN_STAGE 2"},
        {&programs.args, "lightsim args", "lightsim_args.comp", NULL},
        {&programs.finish, "lightsim finish", "lightsim_finish.comp", NULL},
    };
    for (size_t i = 0; i < sizeof table / sizeof table[0]; i++) {
        char preamble[128];
        snprintf(preamble, sizeof preamble, "%s%s", atomics,
                 table[i].preamble ? table[i].preamble : "");
        struct gpu_program_desc desc = {
            .label = table[i].label, .main = table[i].main, .preamble = preamble};
        *table[i].out = gpu_program_create(&desc, NULL, e);
        if (*table[i].out == 0) {
            lightsim_gpu_shutdown();
            return e->code;
        }
    }
    built = true;
    built_with_cas = cas;
    log_info("lightsim", "compiled %zu light simulator programs (float atomics: %s)",
             sizeof table / sizeof table[0], cas ? "compare-and-swap" : "native where available");
    return REFRACT_E_OK;
}

bool lightsim_gpu_programs_use_cas(void)
{
    return built && built_with_cas;
}

void lightsim_gpu_shutdown(void)
{
    GLuint *all[] = {&programs.step,          &programs.emit,        &programs.step_surfaces,
                     &programs.emit_surfaces, &programs.step_meshes, &programs.emit_meshes,
                     &programs.scan[0],       &programs.scan[1],     &programs.scan[2],
                     &programs.args,          &programs.finish};
    for (size_t i = 0; i < sizeof all / sizeof all[0]; i++) {
        if (*all[i])
            glDeleteProgram(*all[i]);
        *all[i] = 0;
    }
    built = false;
}

void lightsim_gpu_scan_record(const struct lightsim_gpu_programs *p)
{
    const GLintptr blocks = (GLintptr)offsetof(ls_control, dispatch_blocks);
    glUseProgram(p->scan[0]);
    glDispatchComputeIndirect(blocks);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    glUseProgram(p->scan[1]);
    glDispatchCompute(1, 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    glUseProgram(p->scan[2]);
    glDispatchComputeIndirect(blocks);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
}
