/*
 * lightsim_gpu_programs.c - compiling the light simulator's kernels, and the prefix sum;
 * see lightsim_gpu_programs.h.
 */
#include "lightsim_gpu_programs.h"

#include <stddef.h>
#include <string.h>

#include "../../core/log.h"
#include "../../gpu/program.h"
#include "lightsim_gpu.h"
#include "lightsim_gpu_wavefront.h" /* shared_types.h with the host's vector types */

static struct lightsim_gpu_programs programs;
static bool built;

const struct lightsim_gpu_programs *lightsim_gpu_programs(void)
{
    return built ? &programs : NULL;
}

enum refract_code lightsim_gpu_init(struct gpu *gpu, struct err *e)
{
    (void)gpu; /* the programs come from the embedded sources, as gpu_create's do */
    if (built)
        return REFRACT_E_OK;
    struct {
        GLuint *out;
        const char *label, *main, *preamble;
    } table[] = {
        {&programs.step, "lightsim step", "lightsim_step.comp", NULL},
        {&programs.emit, "lightsim emit", "lightsim_emit.comp", NULL},
        {&programs.scan[0], "lightsim scan blocks", "lightsim_scan.comp",
         "#define LS_SCAN_STAGE 0"},
        {&programs.scan[1], "lightsim scan sums", "lightsim_scan.comp", "#define LS_SCAN_STAGE 1"},
        {&programs.scan[2], "lightsim scan add", "lightsim_scan.comp", "#define LS_SCAN_STAGE 2"},
        {&programs.args, "lightsim args", "lightsim_args.comp", NULL},
        {&programs.finish, "lightsim finish", "lightsim_finish.comp", NULL},
    };
    for (size_t i = 0; i < sizeof table / sizeof table[0]; i++) {
        struct gpu_program_desc desc = {
            .label = table[i].label, .main = table[i].main, .preamble = table[i].preamble};
        *table[i].out = gpu_program_create(&desc, NULL, e);
        if (*table[i].out == 0) {
            lightsim_gpu_shutdown();
            return e->code;
        }
    }
    built = true;
    log_info("lightsim", "compiled %zu light simulator programs", sizeof table / sizeof table[0]);
    return REFRACT_E_OK;
}

void lightsim_gpu_shutdown(void)
{
    GLuint *all[] = {&programs.step,    &programs.emit, &programs.scan[0], &programs.scan[1],
                     &programs.scan[2], &programs.args, &programs.finish};
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
