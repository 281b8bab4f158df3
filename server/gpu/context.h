/*
 * context.h - the EGL device context refractd renders with.
 *
 * EGL's device platform only (EGL_EXT_platform_device): no X11, no GLX, no window.
 * Devices are enumerated; a hardware GPU is preferred and Mesa's software device
 * (EGL_MESA_device_software, llvmpipe) is the fallback, so refractd runs on any
 * machine. OpenGL 4.5 core profile; only compute shaders are used.
 *
 * Thread: gpu_context_create makes the context current on the calling thread, which
 * must be the GPU thread (gpu/queue.c); every GL call happens there.
 */
#ifndef REFRACT_GPU_CONTEXT_H
#define REFRACT_GPU_CONTEXT_H

#include <stdbool.h>

#include "../core/err.h"

enum gpu_device_pref {
    GPU_DEVICE_AUTO = 0,     /* hardware if any, else software */
    GPU_DEVICE_HARDWARE = 1, /* fail if no hardware device */
    GPU_DEVICE_SOFTWARE = 2, /* Mesa's software device only */
};

struct gpu_context_desc {
    enum gpu_device_pref device; /* 0 = AUTO; env REFRACT_GPU=hardware|software overrides AUTO */
    int device_index;            /* >= 0 picks that EGL device; -1 (or 0 with AUTO) = by preference */
    bool debug;                  /* install a KHR_debug callback that logs GL messages */
};

struct gpu_context_info {
    char vendor[128];
    char renderer[256];
    char version[128];
    char device_kind[16];      /* "hardware" or "software" */
    char device_ext[512];      /* the chosen EGL device's extension string */
    int device_index;
    int device_count;
    char devices_seen[1024];   /* one line per device: index, kind, DRM node, extensions */
    int max_3d_texture_size;
    int max_compute_work_group_invocations;
};

struct gpu_context;

/* Creates the display and a GL 4.5 core context on the chosen device and makes it
 * current on this thread. Returns a new context (destroy with gpu_context_destroy on the
 * same thread) or NULL with e filled: what was tried, what was found and what to install
 * or set to fix it. */
struct gpu_context *gpu_context_create(const struct gpu_context_desc *desc, struct err *e);
void gpu_context_destroy(struct gpu_context *c);
const struct gpu_context_info *gpu_context_info(const struct gpu_context *c);

/* Parses "auto|hardware|software"; -1 when unknown. */
int gpu_device_pref_parse(const char *name);

#endif
