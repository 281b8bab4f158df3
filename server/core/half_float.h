/*
 * half_float.h - rounding to IEEE 754 half precision (binary16), for the float16 index
 * atlas (render.ior_texture "float16", docs/tracing.md "Precision").
 *
 * Both the GPU build (server/render/scene_gpu.c) and the CPU reference
 * (scene/scene_reference.c) round with this one function, so they hold the same values.
 * The GPU build cannot leave the rounding to the driver: Mesa llvmpipe (22.3.6) truncates
 * floats towards zero when it converts an upload to RGBA16F, which biases n low by half an
 * ulp on average (5e-4 at n = 1.4) and moved exit points by 1e-3 in
 * tests/gpu/test_steppers_vs_ref.c. Values that are already halves convert exactly.
 */
#ifndef REFRACT_HALF_FLOAT_H
#define REFRACT_HALF_FLOAT_H

#define HALF_FLOAT_MAX 65504.0

/* The nearest half to x (ties away from zero), subnormals included; beyond
 * +-HALF_FLOAT_MAX clamped to it (an index gradient never becomes infinite); NaN stays
 * NaN. Pure. */
double half_float_round(double x);

#endif
