/*
 * gpu_test_util.h - what the GPU tests share, header-only: the GPU thread on the machine's
 * preferred device (hardware, else llvmpipe), or the test reported as not set up (a skip
 * with its reason, tests/test.h) when no EGL/GL 4.5 context can be made.
 */
#ifndef REFRACT_TEST_GPU_UTIL_H
#define REFRACT_TEST_GPU_UTIL_H

#include <stdio.h>

#include "gpu/queue.h"
#include "test.h"

static inline struct gpu *test_gpu_create(const char *test_name)
{
    struct gpu_desc desc = {.context = {.device_index = -1}};
    struct err e = {0};
    struct gpu *gpu = gpu_create(&desc, &e);
    if (gpu == NULL) {
        fprintf(stderr, "%s\n", e.msg);
        test_setup_failed(test_name, "no EGL/GL 4.5 context could be made");
    }
    return gpu;
}

#endif
