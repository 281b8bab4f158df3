/*
 * test_lightsim_gpu_scan.c - the light simulator's exclusive prefix sum on the GPU
 * (lightsim_scan.comp's three stages via lightsim_gpu_scan_record, dispatched indirectly
 * from the control buffer as in a run) against a CPU scan: random per-patch output
 * counts (0, 1 or 4, as the step writes them, and arbitrary 0..1000), for sizes 1, just
 * below, at and above one block, many blocks, and a full block of blocks
 * (LS_MAX_PATCHES = 1,048,576, the largest max_patches). The total must land in
 * control.counts.y. Integer sums: exact.
 */
#include <stdint.h>

#include "lightsim/gpu/lightsim_gpu_programs.h"
#include "lightsim/gpu/lightsim_gpu_wavefront.h" /* shared_types.h for the host */
#include "test_lightsim_gpu_support.h"

struct scan_work {
    struct gpu_work work;
    int n;
    const uint32_t *counts;
    uint32_t *offsets;  /* out */
    ls_control control; /* out */
};

static void scan_run(struct gpu_work *w, struct gpu *gpu)
{
    struct scan_work *s = w->user;
    if (lightsim_gpu_init(gpu, &w->err) != REFRACT_E_OK)
        return;
    size_t n = (size_t)s->n;
    size_t blocks = (n + LS_SCAN_BLOCK - 1) / LS_SCAN_BLOCK;
    ls_control control;
    memset(&control, 0, sizeof control);
    control.dispatch_blocks = (ivec4){(int)blocks, 1, 1, 0};
    control.counts = (ivec4){s->n, -1, 0, 0};
    struct gpu_buffer counts = {0}, offsets = {0}, sums = {0}, ctl = {0};
    if (gpu_buffer_create("scan test counts", n * 4, s->counts, &counts, &w->err) == REFRACT_E_OK &&
        gpu_buffer_create("scan test offsets", n * 4, NULL, &offsets, &w->err) == REFRACT_E_OK &&
        gpu_buffer_create("scan test block sums", blocks * 4, NULL, &sums, &w->err) ==
            REFRACT_E_OK &&
        gpu_buffer_create("scan test control", sizeof control, &control, &ctl, &w->err) ==
            REFRACT_E_OK) {
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SSBO_LS_COUNTS, counts.buf);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SSBO_LS_OFFSETS, offsets.buf);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SSBO_LS_BLOCK_SUMS, sums.buf);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SSBO_LS_CONTROL, ctl.buf);
        glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, ctl.buf);
        lightsim_gpu_scan_record(lightsim_gpu_programs());
        if (gpu_check("scan test", &w->err) == REFRACT_E_OK &&
            gpu_buffer_read(&offsets, s->offsets, n * 4, &w->err) == REFRACT_E_OK)
            gpu_buffer_read(&ctl, &s->control, sizeof s->control, &w->err);
    }
    gpu_buffer_destroy(&counts);
    gpu_buffer_destroy(&offsets);
    gpu_buffer_destroy(&sums);
    gpu_buffer_destroy(&ctl);
}

/* xorshift32: reproducible counts */
static uint32_t next_random(uint32_t *state)
{
    uint32_t x = *state;
    x ^= x << 13;
    x ^= x >> 17;
    x ^= x << 5;
    return *state = x;
}

static void scan_case(struct gpu *gpu, int n, bool patch_counts, uint32_t seed)
{
    uint32_t *counts = malloc((size_t)n * 4), *offsets = malloc((size_t)n * 4);
    uint32_t state = seed;
    for (int i = 0; i < n; i++) {
        uint32_t r = next_random(&state);
        counts[i] = patch_counts ? (uint32_t[]){0, 1, 1, 4}[r % 4] : r % 1001;
    }
    struct scan_work s = {.n = n, .counts = counts, .offsets = offsets};
    s.work.priority = GPU_PRIORITY_INTERACTIVE;
    s.work.label = "scan test";
    s.work.run = scan_run;
    s.work.user = &s;
    CHECK_INT(gpu_run_sync(gpu, &s.work), REFRACT_E_OK);
    uint64_t run = 0;
    int wrong = 0, first_wrong = -1;
    for (int i = 0; i < n; i++) {
        if (offsets[i] != (uint32_t)run) {
            if (first_wrong < 0)
                first_wrong = i;
            wrong++;
        }
        run += counts[i];
    }
    CHECK_MSG(wrong == 0, "n = %d (%s counts): %d wrong offsets, first at %d", n,
              patch_counts ? "0/1/4" : "0..1000", wrong, first_wrong);
    CHECK_MSG((uint64_t)s.control.counts.y == run, "n = %d: total %d, expected %llu", n,
              s.control.counts.y, (unsigned long long)run);
    printf("scan n = %7d (%s): %s, total %llu\n", n, patch_counts ? "0/1/4   " : "0..1000",
           wrong == 0 ? "exact" : "WRONG", (unsigned long long)run);
    free(counts);
    free(offsets);
}

int main(void)
{
    struct gpu *gpu = test_start_gpu("test_lightsim_gpu_scan");
    const int sizes[] = {
        1, 2, 255, 1023, 1024, 1025, 4097, 100003, LS_MAX_PATCHES - 1, LS_MAX_PATCHES};
    for (size_t i = 0; i < sizeof sizes / sizeof sizes[0]; i++) {
        scan_case(gpu, sizes[i], true, 0x9e3779b9u + (uint32_t)i);
        scan_case(gpu, sizes[i], false, 0x7f4a7c15u + (uint32_t)i);
    }
    gpu_destroy(gpu, NULL);
    return test_summary("test_lightsim_gpu_scan");
}
