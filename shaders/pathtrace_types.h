/*
 * pathtrace_types.h - what the GPU path tracer (pathtrace_render.comp) and its host
 * (server/render/pathtrace_gpu.c) share: valid C (with REFRACT_HOST_C, after
 * shared_types.h) and GLSL. vec4/ivec4 only, std430.
 */
#ifndef REFRACT_PATHTRACE_TYPES_H
#define REFRACT_PATHTRACE_TYPES_H

#include "bindings.h"

#define PT_MAX_LIGHTS 8 /* = PATHTRACE_MAX_LIGHTS */
#define PT_LOCAL_X 64

#ifdef REFRACT_HOST_C
typedef struct pt_light pt_light;
typedef struct pt_medium pt_medium;
#endif

/* core/pathtrace.h struct pathtrace_light */
struct pt_light {
    ivec4 kind;     /* x: PATHTRACE_LIGHT_*; y: 1 = seen by camera rays; z: photon_trace.comp:
                       the inside set where its photons start */
    vec4 position;  /* xyz; w: sphere radius */
    vec4 direction; /* xyz: unit, the way light travels; w: cos of the spot's half angle */
    vec4 value;     /* rgb: I, E or L_e */
};

/* core/pathtrace.h struct pathtrace_medium, one per surface (the ambient one last) */
struct pt_medium {
    vec4 sigma_a; /* rgb; w: ior */
    vec4 sigma_s; /* rgb; w: Henyey-Greenstein g */
};

/* The whole problem but the surfaces' geometry (BIND_SSBO_SURFACES). */
struct pt_params {
    vec4 eye;        /* xyz; w: tan(fov_y / 2) */
    vec4 forward;    /* xyz: unit; w: aspect */
    vec4 right;      /* xyz: unit */
    vec4 up;         /* xyz: unit */
    ivec4 image;     /* x: width, y: height, z: samples this dispatch, w: first sample index */
    ivec4 counts;    /* x: surfaces, y: lights, z: seed, w: the eye's inside set */
    vec4 receiver;   /* x: enabled (1/0), y: height, z: half size (-1: infinite); w: world
                        x of the square's centre */
    vec4 albedo;     /* rgb: the receiver's; w: world z of its square's centre */
    vec4 env;        /* rgb: uniform environment radiance */
    pt_light lights[PT_MAX_LIGHTS];
    pt_medium media[MAX_SURFACES + 1];
};

#endif
