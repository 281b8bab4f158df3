// march_bindings.glsl - the resources of the marching kernels (render_view, trace_rays):
// the march_params uniform block and the channel atlases. Binding numbers come from
// bindings.h only.
#include "bindings.h"
#include "shared_types.h"

// Variant switches, set by the program's preamble (server/gpu/program.c): the stepper
// (STEPPER_*), the index filter (IOR_FILTER_*) and which optional channels the scene
// uses. A channel compiled out is never sampled.
#ifndef MARCH_STEPPER
#define MARCH_STEPPER STEPPER_RK4
#endif
#ifndef MARCH_IOR_FILTER
#define MARCH_IOR_FILTER IOR_FILTER_TRILINEAR
#endif
#ifndef MARCH_ATTENUATION
#define MARCH_ATTENUATION 1
#endif
#ifndef MARCH_EMISSION
#define MARCH_EMISSION 1
#endif
#ifndef MARCH_OPAQUE
#define MARCH_OPAQUE 1
#endif
#ifndef MARCH_SCATTERING
#define MARCH_SCATTERING 1
#endif
#ifndef MARCH_LIGHTS
#define MARCH_LIGHTS 1
#endif
#ifndef MARCH_SKIP
#define MARCH_SKIP 1
#endif
#ifndef MARCH_SURFACES
#define MARCH_SURFACES 1 // exact surfaces (docs/tracing.md "Surfaces")
#endif
#ifndef MARCH_MESHES
#define MARCH_MESHES MARCH_SURFACES // triangle-mesh surfaces (shaders/geom/mesh.glsl)
#endif

layout(std140, binding = BIND_UBO_RENDER) uniform march_params_block
{
    march_params params;
};

// The empty-space map (docs/tracing.md "Empty space"): one uint per macro cell of every
// object, 1 where the cell is empty; object i's cells start at params.skip_cells[i].w.
layout(std430, binding = BIND_SSBO_SKIP_CELLS) readonly buffer skip_cells_block
{
    uint skip_empty[];
};

layout(binding = UNIT_IOR_GRAD) uniform sampler3D ior_grad_atlas;
layout(binding = UNIT_ATTENUATION) uniform sampler3D attenuation_atlas;
layout(binding = UNIT_EMISSION) uniform sampler3D emission_atlas;
layout(binding = UNIT_OPAQUE) uniform sampler3D opaque_atlas;
layout(binding = UNIT_ENVIRONMENT) uniform sampler2D environment_map;

// Lights (tevs2007 eqs. 5.4-5.8): the scattering atlas, the lights' irradiance and
// direction volumes (one texture unit each, MAX_LIGHTS of each) and their parameters.
layout(binding = UNIT_SCATTERING) uniform sampler3D scattering_atlas;
// One sampler per light rather than a sampler3D array: with the array indexed by the light
// loop, llvmpipe (Mesa 22.3.6) rendered wrong radiance even with every light's scale 0
// (tests/gpu/test_render_lights.c found it; not isolated further, so treat it as a driver
// problem to avoid).
layout(binding = UNIT_IRRADIANCE0 + 0) uniform sampler3D irradiance_volume0;
layout(binding = UNIT_IRRADIANCE0 + 1) uniform sampler3D irradiance_volume1;
layout(binding = UNIT_IRRADIANCE0 + 2) uniform sampler3D irradiance_volume2;
layout(binding = UNIT_IRRADIANCE0 + 3) uniform sampler3D irradiance_volume3;
layout(binding = UNIT_LIGHT_DIR0 + 0) uniform sampler3D light_direction_volume0;
layout(binding = UNIT_LIGHT_DIR0 + 1) uniform sampler3D light_direction_volume1;
layout(binding = UNIT_LIGHT_DIR0 + 2) uniform sampler3D light_direction_volume2;
layout(binding = UNIT_LIGHT_DIR0 + 3) uniform sampler3D light_direction_volume3;

layout(std140, binding = BIND_UBO_LIGHTS) uniform march_lights_block
{
    march_lights lights;
};
