/*
 * shared_types.h - structs shared by C and GLSL: uniform blocks (std140) and storage
 * buffer records (std430). Valid C and valid GLSL.
 *
 * Only vec4, ivec4 and mat4 members, so the C layout equals std140/std430 without
 * padding rules (no vec3: its size differs between devices). The C side includes this
 * with REFRACT_HOST_C defined, which supplies the vector types; static asserts in
 * server/render/gpu_types.c check sizes. Keep member comments: they carry units.
 */
#ifndef REFRACT_SHARED_TYPES_H
#define REFRACT_SHARED_TYPES_H

#include "bindings.h"

#ifdef REFRACT_HOST_C
typedef struct {
    float x, y, z, w;
} vec4;
typedef struct {
    int x, y, z, w;
} ivec4;
typedef struct {
    float m[16]; /* column-major */
} mat4;
typedef struct object_params object_params;
#endif

/* Channel flags in object_params.resolution.w */
#define OBJECT_HAS_ATTENUATION 1
#define OBJECT_HAS_EMISSION 2
#define OBJECT_HAS_OPAQUE 4
/* (8 is OBJECT_HAS_SCATTERING, below.) The object fills a surface (docs/scenes.md "Surfaces",
 * medium "object"): seen only inside it, never entered through its bounds. */
#define OBJECT_BOUND 16
/* Its n is the same everywhere: inside its surface rays go straight. */
#define OBJECT_IOR_CONSTANT 32

/* One volume object as the march sees it. */
struct object_params {
    mat4 object_from_world;  /* M^-1 */
    mat4 world_from_object;  /* M = translate * scale * R */
    vec4 bounds_min;         /* xyz: object space; w: scale (world units per object unit) */
    vec4 bounds_max;         /* xyz: object space; w: h_min, smallest voxel edge (object units) */
    vec4 inv_voxel_size;     /* xyz: voxels per object unit; w: smoothing sigma (voxels) */
    vec4 atlas_offset;       /* xyz: this object's first texel in the atlases; w: opaque_ior */
    vec4 atlas_inv_size;     /* xyz: 1 / atlas size in texels; w: unused */
    ivec4 resolution;        /* xyz: voxels; w: OBJECT_HAS_* flags */
};

/* Uniform block of render_view.comp and trace_rays.comp. */
struct march_params {
    vec4 eye;         /* xyz: camera position, world; w: tan(fov_y / 2) */
    vec4 forward;     /* xyz: unit view direction; w: aspect (width / height) */
    vec4 right;       /* xyz: unit right vector */
    vec4 up;          /* xyz: unit up vector (orthogonal to forward and right) */
    ivec4 image;      /* x: width, y: height (pixels); z: ray count (trace), first row of
                         the tile (render); w: 1 = record surface events (trace), end row
                         of the tile, exclusive (render) */
    ivec4 settings_i; /* x: STEPPER_*; y: max_steps; z: object count; w: 1 = image env */
    vec4 settings_f;  /* x: step (voxels); y: boundary threshold (dn per voxel);
                         z: ambient n; w: environment intensity */
    vec4 env;         /* x: environment rotation about +y (degrees) */
    vec4 settings_f2; /* x: adaptive stepper's tolerance per step (voxels); y: view rays per
                         pixel (render_view.comp; a square number, as a float); z: the first
                         of them this dispatch traces; w: how many (0: all) */
    object_params objects[MAX_OBJECTS];
    /* Only what a scene needs (docs/tracing.md "Empty space"); appended to keep the
     * members above where they were. */
    vec4 settings_f3;              /* x: min_throughput (0: never); y: macro cell edge (voxels) */
    ivec4 skip_cells[MAX_OBJECTS]; /* xyz: macro cells per axis; w: the object's first cell in
                                      the BIND_SSBO_SKIP_CELLS buffer */
    /* Exact surfaces (docs/tracing.md "Surfaces"), appended likewise. */
    ivec4 surfaces; /* x: surface count; y: the eye's inside set (bits, render_view) */
};

#ifdef REFRACT_HOST_C
typedef struct surface_params surface_params;
#endif

/* One exact surface and its medium (std430, BIND_SSBO_SURFACES), in priority order. */
struct surface_params {
    mat4 object_from_world;
    mat4 world_from_object; /* similarity: scale * R, then translate */
    ivec4 kind;     /* x: GEOM_*; y: axis (cylinder, lathe); z: lathe's first profile point;
                       w: lathe's point count */
    ivec4 mesh;     /* GEOM_MESH: x first node, y first triangle, z first vertex */
    vec4 shape0;    /* sphere: centre, radius; box, cylinder, rounded box: centre (w: cylinder
                       or corner radius);
                       plane: a point; lathe: base (w: +1 counter-clockwise profile, -1 not) */
    vec4 shape1;    /* box, rounded box: full sizes; cylinder: x full height; plane: unit normal;
                       lathe: x largest r, y lowest h, z highest h of the profile */
    vec4 medium;    /* x: n inside; y: scale (world units per object unit); z: offset past
                       the surface just left (world units); w: 1 = extinction in every channel */
    vec4 attenuation; /* rgb: sigma_a per world unit; w: the object whose fields fill the
                         solid instead of the constants (march_bound.glsl), -1: none */
    vec4 emission;    /* rgb: L_e per world unit */
    vec4 scattering;  /* rgb: sigma_s per world unit (extinction sigma_a + sigma_s, in-scattering
                         along the segments, docs/tracing.md "Scattering inside surfaces");
                         w: Henyey-Greenstein g */
};

/* Uniform block of smooth_ior.comp and gradient_ior.comp: one object's grid. */
struct volume_params {
    ivec4 resolution;   /* xyz: voxels; w: smoothing axis (0, 1, 2) */
    ivec4 atlas_offset; /* xyz: first texel of the object in the ior+grad atlas; w: radius */
    vec4 voxel_size;    /* xyz: object units per voxel */
    vec4 weights[8];    /* Gaussian weights w_k for k = 0..31 (4 per vec4), normalised */
};

/* trace_rays.comp input record (std430). */
struct trace_ray_in {
    vec4 origin;    /* xyz: world position; w: the origin's inside set (uint bits, surfaces) */
    vec4 direction; /* xyz: unit world direction */
};

/* trace_rays.comp output record (std430). */
struct trace_hit_out {
    vec4 exit_origin;    /* xyz: world; w: status (RAY_STATUS_*) */
    vec4 exit_direction; /* xyz: unit world; w: steps */
    vec4 transmittance;  /* xyz: T_fresnel * exp(-alpha); w: optical path length */
    ivec4 events;        /* x: surface events of the ray (also those past TRACE_MAX_EVENTS) */
};

/* trace_rays.comp: one surface event (std430), when the request asks for events
 * (march_params.image.w = 1). */
struct trace_event_out {
    vec4 point;  /* xyz: world; w: TRACE_EVENT_* */
    vec4 normal; /* xyz: unit, facing the incoming ray; w: Fresnel R (1: total reflection) */
    ivec4 media; /* x: surface; y: medium before (surface index, -1 ambient); z: after */
    vec4 ior;    /* x: n before; y: n after */
};

/* ==== light simulator (docs/lightsim.md; server/lightsim/gpu) ==== */
#ifdef REFRACT_HOST_C
typedef struct lightsim_params lightsim_params;
typedef struct ls_gpu_patch ls_gpu_patch;
typedef struct ls_control ls_control;
#endif

/* Uniform block of the lightsim_*.comp kernels (std140). */
struct lightsim_params {
    vec4 grid_min;   /* xyz: light grid bmin (world); w: voxel edge (world units) */
    vec4 grid_max;   /* xyz: bmin + dims * voxel; w: dt (world units) */
    ivec4 dims;      /* xyz: light grid voxels; w: LS_DEPOSIT_* */
    vec4 medium;     /* x: ambient n; y: probe distance k (world); z: boundary threshold
                        (dn per light voxel); w: split length (world units) */
    vec4 cull;       /* x: energy cut (absolute max(P)); y: 1 = cull flipped patches;
                        z: the domain's diagonal (how far a surface event's crossings are
                        predicted, docs/lightsim.md "Surfaces") */
    ivec4 limits;    /* x: max_level; y: max_patches; z: flux deposit every z steps;
                        w: exact surfaces (BIND_SSBO_SURFACES), 0: none */
};

/* One wavefront patch (std430; docs/lightsim.md "Patches"): corners p00, p10, p11, p01. */
struct ls_gpu_patch {
    vec4 x[4];    /* xyz: corner positions (world); w of x[0..2]: cached sigma_t(c) rgb */
    vec4 w[4];    /* xyz: corner ray vectors n d (tevs2007 eq. 4.8) */
    vec4 power;   /* rgb: P (unit light); w: cached n(c) */
    vec4 zone;    /* x: n_lo, y: n_hi of the interface zone */
    ivec4 state;  /* x: level; y: in_zone; z: crossed; w: 1 = the cached samples are those
                     at the current centre c (the previous step's c') */
    vec4 pend;      /* rgb: pending flux deposit, sum of P ds over the pending steps (docs/
                       lightsim.md step 5); w: pending step count */
    vec4 pend_from; /* xyz: start of the pending segment (world); w: unused */
    ivec4 inside;   /* each corner's inside set of exact surfaces (uint bits) */
    ivec4 last;     /* the surface each corner crossed last, -1: none */
    ivec4 event;    /* the pending surface event: x surface (-1: none), y corners still to
                       cross it (bit k), z 1 = reflected twin; w: between lightsim_step and
                       lightsim_emit, 1 = the last of the outputs is the twin (twins[i]) */
};

/* Indirect dispatch arguments and counters written on the GPU (std430). */
struct ls_control {
    ivec4 dispatch_patches; /* xyz: work groups of LS_LOCAL_X over the live list */
    ivec4 dispatch_blocks;  /* xyz: scan blocks over the live list */
    ivec4 counts;           /* x: live patches; y: scan total; z: steps; w: peak live */
    ivec4 events;           /* this step: x splits, y culled_energy, z culled_level,
                               w culled_flip */
    ivec4 events2;          /* this step: x culled_capacity */
};
/* ==== end light simulator ==== */

/* ---- lights (view renderer: tevs2007 eqs. 5.4-5.8; docs/tracing.md "Light") ---- */

/* Channel flag in object_params.resolution.w: the object has a scattering channel
 * (sigma_s, and g from its anisotropy channel) in the scattering atlas. */
#define OBJECT_HAS_SCATTERING 8

/* One light as the march sees it. */
struct light_params {
    vec4 position;  /* xyz: world (point, spot); w: LIGHT_KIND_* */
    vec4 direction; /* xyz: unit, the way light travels (directional, spot); w: cos_spot */
    vec4 scale;    /* rgb: colour * intensity (multiplies the unit-light volume); w: LIGHT_MODE_* */
    vec4 grid_min; /* xyz: world bmin of the light grid; w: voxel edge (world units) */
    vec4 grid_size; /* xyz: grid extent dims * voxel (world units); w: point: the lamp's
                       radius (0: none; negative: hidden from camera rays), light_emitter */
};

#ifdef REFRACT_HOST_C
typedef struct light_params light_params;
#endif

/* Uniform block BIND_UBO_LIGHTS of render_view.comp. */
struct march_lights {
    ivec4 count;                  /* x: lights; y: 1 = receiver enabled; z: 1 = the receiver's
                                     caustics are photons (docs/photons.md): direct light by
                                     shadow rays, the rest from the photon map; w: 1 = single
                                     scattering by exact paths (LIGHT_MODE_WALTER) */
    vec4 receiver;                /* x: height (world y); y: half size (<= 0: the whole
                                     plane); zw: world x, z of the square's centre */
    vec4 receiver_albedo;         /* rgb: Lambertian reflectance */
    vec4 photon_grid[MAX_LIGHTS]; /* count.z = 1, per light's map (unit light): x the
                                     lattice spacing; y the gather radius */
    ivec4 photon_dims[MAX_LIGHTS]; /* x: hash slots (a power of two; 0: no map, or no photon
                                     landed); y: the longest probe sequence; z: the map's
                                     first slot in the photon buffers */
    vec4 walter_sphere;           /* count.w = 1 (scene_walter_sphere): xyz the world centre,
                                     w the radius of the sphere of LIGHT_MODE_WALTER */
    vec4 walter_medium;           /* rgb: its sigma_t; w: its index over the ambient one */
    vec4 brdf[MAX_OBJECTS + MAX_SURFACES];       /* x: BRDF_*; y: GGX alpha (roughness^2);
                                                    z: Phong exponent. Objects, then surfaces
                                                    (slot MAX_OBJECTS + k) */
    vec4 brdf_color[MAX_OBJECTS + MAX_SURFACES]; /* rgb: colour of the BRDF */
    light_params lights[MAX_LIGHTS];
};
/* ---- end of lights ---- */

#endif
