/*
 * bindings.h - binding points, local sizes and fixed limits shared by C and GLSL.
 *
 * Valid C and valid GLSL: only #defines. C includes it to compute dispatch group
 * counts from the same local sizes the shaders declare; no binding number appears
 * anywhere else (STYLE.md, "Shaders").
 */
#ifndef REFRACT_BINDINGS_H
#define REFRACT_BINDINGS_H

/* ---- local sizes ---- */
#define RENDER_LOCAL_X 8
#define RENDER_LOCAL_Y 8
#define TRACE_LOCAL_X 64
#define VOLUME_LOCAL_X 4
#define VOLUME_LOCAL_Y 4
#define VOLUME_LOCAL_Z 4

/* ---- fixed limits ---- */
#define MAX_OBJECTS 8 /* objects per scene the renderer handles in one pass */
#define MESH_RT_MAX_DEPTH 64 /* nodes on a mesh BVH's root-to-leaf path (the builder
                                guarantees it); the GLSL traversal's stack size */

/* ---- ray statuses (server/core/ray_status.h gives their names) ---- */
#define RAY_STATUS_EXITED 0
#define RAY_STATUS_ABSORBED 1
#define RAY_STATUS_MAX_STEPS 2
#define RAY_STATUS_MISSED 3
#define RAY_STATUS_RUNNING 4 /* internal to the march; never reported */

/* ---- steppers ---- */
#define STEPPER_EULER 0 /* tevs2007 eqs. 5.11/5.12 */
#define STEPPER_RK4 1
#define STEPPER_RK2 2      /* explicit midpoint */
#define STEPPER_ADAPTIVE 3 /* Bogacki-Shampine 3(2) with step-size control */

/* ---- index filters (MARCH_IOR_FILTER; render.ior_filter) ---- */
#define IOR_FILTER_TRILINEAR 0
#define IOR_FILTER_TRICUBIC 1 /* Catmull-Rom of n and its exact gradient, 64 texel fetches */

/* ---- uniform blocks (std140) ---- */
#define BIND_UBO_RENDER 0  /* render_params: camera, settings, objects[] */
#define BIND_UBO_VOLUME 1  /* volume_params: one object's grid for smoothing/gradient */

/* ---- storage buffers (std430) ---- */
#define BIND_SSBO_IMAGE_OUT 0 /* render_view: vec4 radiance per pixel */
#define BIND_SSBO_RAYS_IN 1   /* trace_rays: trace_ray_in[] */
#define BIND_SSBO_HITS_OUT 2  /* trace_rays: trace_hit_out[] */
#define BIND_SSBO_FIELD_IN 3  /* smooth_ior / gradient_ior: float per voxel */
#define BIND_SSBO_FIELD_OUT 4 /* smooth_ior: float per voxel */
#define BIND_SSBO_SKIP_CELLS 19 /* render_view, trace_rays: uint per macro cell, 1 = empty
                                   (after the light simulator's 5..18) */
/* Triangle meshes (shaders/geom/mesh.glsl, server/mesh/mesh_rt.h gives the records):
 * several meshes concatenated, each addressed by its first node, triangle and vertex. */
#define MESH_RT_NO_NORMAL 0x80008000u /* a vertex record's normal bits when the vertex has
                                         no smooth normal (a crease): never a packSnorm2x16
                                         result (-32768 is outside its range) */
#define BIND_SSBO_MESH_NODES 20 /* vec4 x 2 per BVH node: lo + left/first, hi + count */
#define BIND_SSBO_MESH_TRIS 21  /* uvec4 per triangle: v0, v1, v2, original index */
#define BIND_SSBO_MESH_VERTS 22 /* vec4 per vertex: position, octahedral shading normal */

/* ---- exact surfaces (docs/tracing.md "Surfaces"; server/core/geom, shaders/geom) ---- */
#define MAX_SURFACES 32 /* = INTERFACE_MAX_SURFACES: a ray's inside set is 32 bits */
#define BIND_SSBO_SURFACES 23         /* surface_params[] by priority, highest first */
#define BIND_SSBO_SURFACE_PROFILES 24 /* vec2 (r, h) points of the lathes' profiles */
#define GEOM_SPHERE 0 /* = enum geom_kind */
#define GEOM_BOX 1
#define GEOM_CYLINDER 2
#define GEOM_PLANE 3
#define GEOM_LATHE 4
#define GEOM_MESH 5
#define GEOM_ROUNDED_BOX 6
#define BIND_SSBO_TRACE_EVENTS 25 /* trace_rays: trace_event_out[TRACE_MAX_EVENTS] per ray */
#define TRACE_MAX_EVENTS 16       /* surface events recorded per traced ray ("events": true) */
#define TRACE_EVENT_REFRACTED 0
#define TRACE_EVENT_REFLECTED 1 /* total internal reflection */

/* ---- the GPU path tracer (pathtrace_render.comp, docs/pathtracer.md) ---- */
#define BIND_SSBO_PT_PARAMS 27 /* pt_params (pathtrace_types.h) */
#define BIND_SSBO_PT_ACCUM 28  /* vec4 sum, vec4 sum of squares per pixel */

/* ---- caustic photons on the receiver (docs/photons.md, shaders/photons.glsl) ---- */
#define BIND_SSBO_PHOTONS 29        /* render_view: vec4 E (rgb) per lattice hash slot */
#define BIND_SSBO_PHOTON_BUCKETS 30 /* ivec2 (i, j) per lattice hash slot */
#define PHOTON_EMPTY_KEY (-2147483647 - 1) /* = photon.h's: the key of an empty slot */
#define PHOTON_CELL_MAX 1073741824.0     /* = photon.h's: lattice indices are clamped to it */

/* ---- texture units (samplers) ---- */
#define UNIT_IOR_GRAD 0    /* sampler3D atlas: rgb = grad n (object units), a = n */
#define UNIT_ATTENUATION 1 /* sampler3D atlas: rgb = sigma_a per world unit */
#define UNIT_EMISSION 2    /* sampler3D atlas: rgb = emitted radiance per world unit */
#define UNIT_OPAQUE 3      /* sampler3D atlas: rgb = colour, a = coverage */
#define UNIT_ENVIRONMENT 4 /* sampler2D equirectangular environment (RGBA32F) */

/* ---- image units ---- */
#define IMAGE_IOR_GRAD_OUT 0 /* gradient_ior writes the ior+grad atlas */

/* ==== light simulator (docs/lightsim.md; server/lightsim/gpu) ==== */
#define LS_LOCAL_X 64       /* per-patch kernels: lightsim_step, lightsim_emit */
#define LS_SCAN_LOCAL 256   /* lightsim_scan: invocations per work group */
#define LS_SCAN_BLOCK 1024  /* elements per scan block (4 per invocation) */
#define LS_MAX_PATCHES 1048576 /* = LS_SCAN_BLOCK^2: two scan levels suffice */
#define LS_DEPOSIT_CHANNELS 6 /* deposit buffers: irradiance r, g, b; direction x, y, z */
#define LS_DEPOSIT_FLUX 0
#define LS_DEPOSIT_MAX 1
/* float accumulators of one step (ls_accum[]) */
#define LS_ACC_OUT 0        /* rgb: flux_out */
#define LS_ACC_REFLECTED 3  /* rgb */
#define LS_ACC_ABSORBED 6   /* rgb */
#define LS_ACC_CULLED 9     /* rgb */
#define LS_ACC_LIVE 12      /* rgb: power of the patches written by lightsim_emit */
#define LS_ACC_COUNT 15
/* run totals (double ls_totals[]): the LS_ACC_* slots, then these */
#define LS_TOT_SPLITS 15
#define LS_TOT_CULLED_ENERGY 16
#define LS_TOT_CULLED_LEVEL 17
#define LS_TOT_CULLED_FLIP 18
#define LS_TOT_CULLED_CAPACITY 19
#define LS_TOT_PATCH_STEPS 20
#define LS_TOT_COUNT 21
#define BIND_UBO_LIGHTSIM 2        /* lightsim_params */
#define BIND_SSBO_LS_PATCHES_IN 5  /* ls_patch[]: the live list (updated in place) */
#define BIND_SSBO_LS_PATCHES_OUT 6 /* ls_patch[]: the next list (lightsim_emit) */
#define BIND_SSBO_LS_COUNTS 7      /* uint per patch: outputs 0, 1 or 4 */
#define BIND_SSBO_LS_OFFSETS 8     /* uint per patch: exclusive prefix sum of counts */
#define BIND_SSBO_LS_BLOCK_SUMS 9  /* uint per scan block, scanned in place */
#define BIND_SSBO_LS_CONTROL 10    /* ls_control: indirect arguments and counters, then
                                      float[LS_ACC_COUNT], one step's flux sums (11 is free:
                                      they had a block of their own) */
#define BIND_SSBO_LS_TOTALS 12     /* double[LS_TOT_COUNT], the run's totals */
#define BIND_SSBO_LS_TWINS 26      /* ls_patch[] by live index: surface events' reflected twins
                                      (docs/lightsim.md "Surfaces"); 20-22 are the meshes'
                                      (the light simulator packs them into 20), 25 the
                                      trace events' */
#define BIND_SSBO_LS_DEPOSIT 13    /* .. + 5: one float per light voxel and deposit channel
                                      (one buffer each: GL guarantees only 128 MiB a block) */
#define UNIT_LS_IOR_GRAD 5         /* sampler3D: rgb grad n (world units), a = n */
#define UNIT_LS_EXTINCTION 6       /* sampler3D: rgb sigma_t per world unit, a coverage */
#define IMAGE_LS_IRRADIANCE 1      /* lightsim_finish writes the irradiance volume */
#define IMAGE_LS_DIRECTION 2       /* ... and the direction volume */
/* ==== end light simulator ==== */

/* ---- lights (view renderer: tevs2007 eqs. 5.4-5.8; docs/tracing.md "Light") ---- */
#define MAX_LIGHTS 4             /* = SCENE_MAX_LIGHTS (static_assert in render.c) */
#define BIND_UBO_LIGHTS 6        /* march_lights: lights, receiver, per-object BRDFs */
#define UNIT_SCATTERING 7        /* sampler3D atlas: rgb = sigma_s per world unit, a = g */
#define UNIT_IRRADIANCE0 8       /* sampler3D x MAX_LIGHTS: rgb = E of light j (unit light) */
#define UNIT_LIGHT_DIR0 12       /* sampler3D x MAX_LIGHTS: xyz = light direction of light j */
#define LIGHT_MODE_OFF 0         /* the light contributes nothing (no volume yet) */
#define LIGHT_MODE_VOLUME 1      /* E, l from the light's irradiance and direction volumes */
#define LIGHT_MODE_DIRECT 2      /* unshadowed direct light (scenes without light simulation) */
#define LIGHT_MODE_WALTER 3      /* in-scattering by walter2009's exact paths through the
                                    sphere of march_lights.walter_sphere; elsewhere direct */
/* The receiver reads a light's volume where it lies at least this many voxels inside the
 * light grid's x and z faces (the 2 pad voxels and LIGHTSIM_RECEIVER_MARGIN more), and the
 * light's closed form (light_direct) elsewhere (docs/lightsim.md "Domain"). */
#define LIGHTSIM_RECEIVER_MARGIN 2
#define LIGHT_RECEIVER_INSET (2.0 + LIGHTSIM_RECEIVER_MARGIN)
#define LIGHT_KIND_DIRECTIONAL 0 /* = SCENE_LIGHT_DIRECTIONAL */
#define LIGHT_KIND_POINT 1       /* = SCENE_LIGHT_POINT */
#define LIGHT_KIND_SPOT 2        /* = SCENE_LIGHT_SPOT */
#define BRDF_NONE 0              /* = SCENE_BRDF_NONE ... */
#define BRDF_LAMBERT 1
#define BRDF_PHONG 2
#define BRDF_GGX 3
/* ---- end of lights ---- */

#endif
