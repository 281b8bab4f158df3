/*
 * scene.h - the scene model: what a scene JSON document (proto/scene.schema.json,
 * docs/scenes.md) becomes after complete validation, and the CPU evaluation of its
 * procedural fields into voxels.
 *
 * A scene holds volume objects. Each object has axis-aligned bounds in its object
 * space, a voxel resolution, a similarity transform to world space and up to six
 * channels (refractive index, RGB attenuation, RGB emission, opaque colour, RGB
 * scattering, scattering anisotropy). A channel
 * is a list of layers evaluated in order; later layers override earlier ones where
 * they cover (shapes, with an anti-aliased boundary one voxel wide) or everywhere
 * (GRIN profiles, uploaded volumes, constants).
 *
 * Ownership: scene_parse returns a new scene; the caller destroys it with
 * scene_destroy(). A scene is immutable after parsing, so any thread may read it.
 * This module never touches the GPU, HTTP or files.
 */
#ifndef REFRACT_SCENE_H
#define REFRACT_SCENE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "../core/err.h"
#include "../core/grin.h"
#include "../core/vec3.h"
#include "../core/xform.h"

#define SCENE_NAME_MAX 128
#define SCENE_VOLUME_NAME_MAX 64

enum scene_channel {
    SCENE_CH_IOR = 0,         /* 1 component: refractive index n */
    SCENE_CH_ATTENUATION = 1, /* RGB sigma_a per world unit (tevs2007 eq. 3.4, 5.9) */
    SCENE_CH_EMISSION = 2,    /* RGB emitted radiance per world unit (L_e, eq. 5.4) */
    SCENE_CH_OPAQUE = 3,      /* RGB opaque colour; coverage is the 4th component */
    SCENE_CH_SCATTERING = 4,  /* RGB scattering coefficient sigma_s per world unit (eq. 5.4's
                                 scattering strength: albedo = sigma_s / (sigma_a + sigma_s)) */
    SCENE_CH_ANISOTROPY = 5,  /* 1 component: Henyey-Greenstein g in [-0.99, 0.99] (eq. 5.5) */
    SCENE_CH_COUNT = 6,
};

enum scene_layer_kind {
    SCENE_LAYER_CONSTANT = 0, /* value everywhere in the bounds */
    SCENE_LAYER_SHAPE = 1,    /* inside/outside a shape */
    SCENE_LAYER_PROFILE = 2,  /* analytic GRIN profile (ior only) */
    SCENE_LAYER_VOLUME = 3,   /* uploaded volume, trilinearly resampled to the grid */
};

enum scene_shape_kind {
    SCENE_SHAPE_SPHERE = 0,
    SCENE_SHAPE_BOX = 1,
    SCENE_SHAPE_ROUNDED_BOX = 2,
    SCENE_SHAPE_CYLINDER = 3,
    SCENE_SHAPE_LATHE = 4,
    SCENE_SHAPE_TEXT = 5,
    SCENE_SHAPE_BUMPY_SPHERE = 6, /* sphere whose radius is modulated: caustic cusps (hard case) */
    SCENE_SHAPE_MESH = 7,         /* an uploaded triangle mesh (server/mesh), voxelized */
    SCENE_SHAPE_PLANE = 8,        /* surfaces only: the half-space behind `normal` through center */
};

/* All lengths in object-space units of the owning object. */
struct scene_shape {
    enum scene_shape_kind kind;
    vec3 center;          /* sphere, box, rounded_box, cylinder, text */
    double radius;        /* sphere; cylinder; rounded_box corner radius */
    vec3 size;            /* box, rounded_box: full edge lengths */
    double height;        /* cylinder: full length along axis; text: glyph cell height */
    int axis;             /* cylinder, lathe: 0 = x, 1 = y, 2 = z */
    vec3 base;            /* lathe: point on the axis where h = 0 */
    double (*profile)[2]; /* lathe: closed polygon of (r, h) points, r >= 0; owned */
    size_t profile_count;
    char *text;            /* text: printable ASCII; owned */
    double depth;          /* text: extrusion length along z, centred on center.z */
    double bump_amplitude; /* bumpy_sphere: r(theta, phi) = radius + a sin(f theta) sin(f phi) */
    int bump_frequency;    /* bumpy_sphere: f, 1..32 */
    char mesh[SCENE_VOLUME_NAME_MAX]; /* mesh: upload name */
    struct xform object_from_mesh;    /* mesh: center + scale * R(rotate) * p_mesh */
    vec3 normal;                      /* plane: unit */
};

struct scene_layer {
    enum scene_layer_kind kind;
    struct scene_shape shape;           /* SCENE_LAYER_SHAPE */
    struct grin_profile profile;        /* SCENE_LAYER_PROFILE */
    char volume[SCENE_VOLUME_NAME_MAX]; /* SCENE_LAYER_VOLUME: upload name */
    double volume_scale, volume_offset; /* value = offset + scale * sample */
    double inside[4];  /* shape: value inside; constant: the value. Components as the channel. */
    double outside[4]; /* shape: value outside, when has_outside */
    bool has_outside;
};

struct scene_field {
    struct scene_layer *layers; /* owned; NULL when count == 0 (channel unused) */
    size_t count;
};

/* BRDF f_r of eq. 5.6/5.8 for light reflected at boundaries inside an object (the
 * delta(x) R L_r term of eq. 5.4). Only lights contribute; the environment's reflection is
 * the mirror term of docs/tracing.md. */
enum scene_brdf_kind {
    SCENE_BRDF_NONE = 0,    /* no reflection of lights */
    SCENE_BRDF_LAMBERT = 1, /* color / pi */
    SCENE_BRDF_PHONG = 2,   /* normalised Phong: color (e + 2) / (2 pi) cos^e(alpha_r) */
    SCENE_BRDF_GGX = 3,     /* Trowbridge-Reitz microfacet D G / (4 cos_i cos_o), F applied
                               by the event's Fresnel R; color multiplies */
};

struct scene_brdf {
    enum scene_brdf_kind kind; /* default GGX */
    double color[3];           /* default (1, 1, 1) */
    double roughness;          /* GGX alpha = roughness^2; 0.01..1, default 0.1 */
    double exponent;           /* Phong exponent, 1..10000, default 200 */
};

struct scene_object {
    char name[SCENE_NAME_MAX];
    vec3 bounds_min, bounds_max; /* object space, max > min on each axis */
    int resolution[3];           /* voxels along x, y, z */
    struct xform world_from_object;
    double smoothing_sigma_voxels; /* Gaussian std dev for the ior field (tevs2007 3.1); 0 = none */
    double opaque_ior; /* n of opaque embeddings' surfaces, for their Fresnel reflection */
    struct scene_field fields[SCENE_CH_COUNT];
    struct scene_brdf brdf; /* reflection of lights at the object's boundaries (eq. 5.6) */
    /* Bound to a surface (docs/scenes.md "Surfaces", the medium "object" form): the object's
     * fields fill that surface's solid and the object is seen nowhere else. Zero: free, a
     * voxel object in the ambient medium. */
    bool bound;
    int bound_surface; /* when bound: index into scene.surfaces (priority order) */
};

struct scene_camera {
    vec3 eye, look_at, up; /* world space */
    double fov_y_deg;      /* vertical field of view */
    int width, height;     /* pixels */
};

enum scene_env_kind { SCENE_ENV_PROCEDURAL = 0, SCENE_ENV_IMAGE = 1 };

struct scene_environment {
    enum scene_env_kind kind;
    double intensity;    /* radiance multiplier */
    double rotation_deg; /* rotation of the environment about world +y */
};

enum scene_stepper {
    SCENE_STEPPER_EULER = 0,    /* tevs2007 eqs. 5.11/5.12 */
    SCENE_STEPPER_RK4 = 1,      /* classical Runge-Kutta */
    SCENE_STEPPER_RK2 = 2,      /* explicit midpoint */
    SCENE_STEPPER_ADAPTIVE = 3, /* Bogacki-Shampine 3(2), step control by tolerance */
};
/* Storage of the index+gradient atlas (docs/tracing.md "Precision"). */
enum scene_ior_texture { SCENE_IOR_FLOAT32 = 0, SCENE_IOR_FLOAT16 = 1 };
/* Reconstruction of n and grad n between voxel centres (docs/tracing.md "Index filter"). */
enum scene_ior_filter { SCENE_FILTER_TRILINEAR = 0, SCENE_FILTER_TRICUBIC = 1 };
enum scene_tonemap { SCENE_TONEMAP_CLAMP = 0, SCENE_TONEMAP_FILMIC = 1 };

/* The JSON words of these enums, indexed by value, NULL-terminated (scene_words.c): the one
 * table each that parsers (jr_enum) and status answers share. */
extern const char *const scene_stepper_words[];
/* The stepper's key was "integrator" (renamed: "integrator" is kept for a light-transport
 * algorithm); documents and requests that use the old key keep working (jr_renamed). */
#define SCENE_STEPPER_OLD_KEY "integrator" /* renamed: the old key */
extern const char *const scene_ior_texture_words[];
extern const char *const scene_ior_filter_words[];
extern const char *const scene_tonemap_words[];

/* Render defaults of a scene; a render request may override each. */
struct scene_render_settings {
    enum scene_stepper stepper;
    double step_voxels;                 /* integration step, in voxels of the object being crossed;
                                           adaptive: the largest step */
    double tolerance_voxels;            /* adaptive: error per step, voxels (1e-6..1; 1e-3) */
    enum scene_ior_texture ior_texture; /* scene document only (a build setting): a request
                                           cannot change it */
    int max_steps;                      /* per ray, over all objects */
    double exposure_ev;                 /* PNG/JPEG: pixel = tonemap(2^exposure * L) */
    double boundary_threshold; /* |grad n| * voxel size above which Fresnel reflection applies */
    enum scene_tonemap tonemap;
    /* Only what a scene needs (docs/tracing.md "Empty space", "The march"): */
    bool empty_space_skipping;        /* jump over macro cells with no gradient and no channels
                                         (default true) */
    double min_throughput;            /* T_f max(exp(-alpha)) below this ends a ray as absorbed
                                         (0..0.5; default 1e-6; 0: never) */
    enum scene_ior_filter ior_filter; /* trilinear (default) or tricubic Catmull-Rom */
    int samples_per_pixel;            /* view renders: jittered rays per pixel, a square
                                         (1, 4, 9, ...; default 1), box filter
                                         (docs/tracing.md "Anti-aliasing") */
};

/* ---- lights, receiver and light simulation (tevs2007 ch. 4.2, 6.2) ---- */

#define SCENE_MAX_LIGHTS 4
#define SCENE_LIGHT_NAME_MAX 64 /* names are 1..63 characters */

enum scene_light_kind {
    SCENE_LIGHT_DIRECTIONAL = 0, /* plane wavefront */
    SCENE_LIGHT_POINT = 1,       /* spherical wavefront from `position` */
    SCENE_LIGHT_SPOT = 2,        /* point light restricted to a cone about `direction` */
};

struct scene_light {
    char name[SCENE_NAME_MAX]; /* [a-z0-9_-], unique in the scene; default "light<index>" */
    enum scene_light_kind kind;
    vec3 direction;        /* directional, spot: unit, the way the light travels (world) */
    vec3 position;         /* point, spot: world */
    double spot_angle_deg; /* spot: half angle of the cone, 1..89 */
    double color[3];       /* linear RGB, each 0..1e3; default (1, 1, 1) */
    double intensity;      /* directional: irradiance normal to the beam; point/spot:
                              radiant intensity per steradian. 0..1e6, default 1 */
    /* Point lights: the path tracer's spherical emitter (docs/pathtracer.md "Lights"); the
     * fast renderer shows the sphere to rays leaving the scene (docs/tracing.md "Lamps")
     * but lights from the point at its centre, as the light simulator does. */
    double radius;       /* > 0: a Lambertian sphere of this radius and the same far-field
                            intensity (radiance intensity / (pi r^2)); 0: a point */
    bool camera_visible; /* the sphere is seen by camera rays (default true); reflections,
                            refractions and indirect rays always see it */
};

/* A diffuse plane y = height that receives caustics and shadows (thesis fig. 7.4). */
/* How light that went through or off the surfaces reaches the receiver (docs/photons.md
 * "Choosing"): the light simulator's volume; photons traced through exact surfaces, with
 * shadow rays for direct light; "auto" (the document's default), which the parser resolves
 * to one of the others by the scene's content (receiver.caustics_reason says why); or none:
 * direct light with shadow rays only. */
enum scene_caustics {
    SCENE_CAUSTICS_VOLUME = 0,
    SCENE_CAUSTICS_PHOTONS = 1,
    SCENE_CAUSTICS_AUTO = 2, /* in documents only: a parsed scene holds the method chosen */
    SCENE_CAUSTICS_NONE = 3,
};
extern const char *const scene_caustics_words[];
#define SCENE_MAX_PHOTONS 67108864 /* receiver.photons at most (2^26: 2.7 GB of photons) */

struct scene_receiver {
    bool enabled;
    double height;    /* world y of the plane */
    double half_size; /* the plane is the square |x - center[0]|, |z - center[1]| <=
                         half_size; INFINITY: the whole plane ("infinite") */
    double center[2]; /* world x and z of the square's centre; default (0, 0) */
    double albedo[3]; /* Lambertian reflectance, 0..1; default 0.8 */
    /* How light that went through or off the surfaces reaches the plane (docs/photons.md):
     * the light simulator's volume (default) or caustic photons with shadow rays. */
    enum scene_caustics caustics;  /* never SCENE_CAUSTICS_AUTO once parsed */
    bool caustics_auto;            /* the document said "auto" (or nothing) */
    const char *caustics_reason;   /* why this method (a static sentence) */
    int photons;          /* caustic photons per map, 1024..SCENE_MAX_PHOTONS; 1048576 */
    int photons_max;      /* the cache refines a map up to this many (photons..
                             SCENE_MAX_PHOTONS; default photons: no further) */
    double photon_radius; /* gather radius, world units; 0 (default): the auto rule */
};

enum scene_lightsim_deposit {
    SCENE_DEPOSIT_FLUX = 0, /* default: power x path length / voxel volume, summed */
    SCENE_DEPOSIT_MAX = 1,  /* thesis sect. 6.2.3: highest patch irradiance per voxel */
};

/* Settings of the light simulator (docs/lightsim.md); all part of the transport hash. */
struct scene_lightsim {
    int resolution;          /* voxels along the longest axis of the light domain, 8..512; 64 */
    double step_voxels;      /* wavefront time step in vacuum voxel lengths, 0.05..4; 0.5 */
    int initial_patches;     /* patches per side of the initial wavefront, 2..1024; 64 */
    int max_level;           /* subdivision levels, 0..12; 6 */
    double split_voxels;     /* a patch whose longest edge exceeds this many voxels splits,
                                0.1..8; 1 */
    double energy_threshold; /* cull a patch below this fraction of the initial mean patch
                                power, 0..1; 1e-4 */
    double point_radius;     /* point/spot: initial wavefront radius (thesis note 5),
                                world units, > 0; default 0.01 */
    enum scene_lightsim_deposit deposit;
    bool cull_flipped; /* cull patches whose orientation flips (thesis 6.2.4); false */
    int max_patches;   /* capacity of the patch list, 1024..1048576; 262144 */
};

/* ---- exact surfaces (docs/scenes.md "Surfaces", docs/tracing.md "Surfaces") ---- */

#define SCENE_MAX_SURFACES 32 /* = INTERFACE_MAX_SURFACES: bits of a ray's inside set */

/* What fills a surface's solid: a constant medium, or a voxel object's fields ("object":
 * a GRIN lens bounded by its exact sphere). */
struct scene_medium {
    double ior;            /* 1..5; 1 and unused when has_object */
    double attenuation[3]; /* sigma_a per world unit, >= 0; 0 when has_object */
    double emission[3];    /* L_e per world unit, >= 0; 0 when has_object */
    bool has_object;       /* the medium is the fields of scene.objects[object] */
    int object;            /* when has_object: index into scene.objects */
    /* Extinction sigma_a + sigma_s everywhere; single in-scattering in the fast renderer
     * (docs/tracing.md "Scattering inside surfaces"), multiple in "mode": "reference"
     * (docs/pathtracer.md). */
    double scattering[3]; /* sigma_s per world unit, >= 0 */
    double anisotropy;    /* Henyey-Greenstein g, -0.99..0.99 */
};

/* A surface bounding a medium: its shape (sphere, box, cylinder, plane, lathe, mesh) in
 * object space, placed by a similarity transform. */
struct scene_surface {
    char name[SCENE_NAME_MAX];
    struct scene_shape shape;
    struct xform world_from_object;
    int priority; /* nesting priority: the higher wins where solids overlap */
    struct scene_medium medium;
    struct scene_brdf brdf; /* reflection of lights where the surface refracts (eq. 5.6) */
    int document_index;     /* position in the document's "surfaces" (messages) */
};

struct scene {
    char name[SCENE_NAME_MAX];
    double ambient_ior; /* n outside every object's bounds */
    struct scene_camera camera;
    struct scene_environment environment;
    struct scene_render_settings render;
    struct scene_object *objects; /* owned; may be empty when there are surfaces */
    size_t object_count;
    struct scene_surface *surfaces; /* owned; sorted by priority, highest first (interface.h) */
    size_t surface_count;
    struct scene_light lights[SCENE_MAX_LIGHTS];
    size_t light_count;
    struct scene_receiver receiver;
    struct scene_lightsim lightsim;
};

/* True when a surface's constant medium scatters (sigma_s > 0 in some channel): the fast
 * renderer's in-scattering and the light simulator's extinction (docs/tracing.md
 * "Scattering inside surfaces"). */
bool scene_surface_scatters(const struct scene_surface *sf);

/* True when some object scatters (a SCENE_CH_SCATTERING field) or some surface's medium
 * does (scene_surface_scatters). */
bool scene_scatters(const struct scene *s);

/* True when some object scatters (a SCENE_CH_SCATTERING field), some surface's medium
 * scatters (scene_surface_scatters; not when scene_walter_sphere holds) or a receiver with
 * "volume" caustics is enabled:
 * only then does the scene need irradiance volumes (tevs2007 sect. 1.2: model only what a
 * scene needs). Defined by the scene's transport alone, not by its lights: a scene that
 * needs light simulation but has no lights simply has nothing to simulate yet (lights
 * come and go with PUT .../lights without changing the answer). */
bool scene_needs_light_simulation(const struct scene *s);
/* True when the receiver is enabled with "photons" caustics: each light then needs a photon
 * map (docs/photons.md), which the irradiance cache keeps like a volume. */
bool scene_needs_photon_maps(const struct scene *s);
/* True when the receiver's direct light is found by shadow rays that optical surfaces block
 * (caustics "photons" or "none"; docs/photons.md "Which light is whose"). */
bool scene_receiver_shadow_rays(const struct scene *s);

/* The sphere whose medium's single scattering comes from exact refracted paths (walter2009,
 * core/walter.h; docs/walter.md "When"): a scene of one exact sphere whose constant medium
 * scatters, no voxel object and no receiver. Then every light reaches the medium through
 * that one boundary only, the fast renderer's lights use LIGHT_MODE_WALTER and no light
 * simulation is needed. Returns false otherwise; w may be NULL. */
struct scene_walter {
    int surface;       /* index into scene.surfaces */
    vec3 center;       /* world */
    double radius;     /* world */
    double eta;        /* the medium's index over the ambient one */
    double sigma_t[3]; /* sigma_a + sigma_s per world unit */
};
bool scene_walter_sphere(const struct scene *s, struct scene_walter *w);

/* How the scene's scattering media get their single scattering, for the scene status:
 * "walter" (scene_walter_sphere), "volume" (the light simulator's irradiance volumes) or
 * "none" (nothing scatters). */
const char *scene_single_scattering_method(const struct scene *s);

/* FNV-1a 64 over everything that affects light transport (docs/lightsim.md, the irradiance
 * cache key): ambient_ior, each object's bounds, resolution, transform, smoothing, opaque_ior
 * and its ior, attenuation, scattering and opaque layers (uploaded volumes by name, scale and
 * offset: the caller mixes in their content checksums), the receiver's geometry (height,
 * half_size, center), the
 * lightsim settings and render.boundary_threshold. Not: lights, camera, environment,
 * emission, anisotropy, BRDFs, names, other render settings. Equal scenes give equal hashes
 * whatever the document's spelling (defaults written out or left away). */
uint64_t scene_transport_hash(const struct scene *s);

/* Limits enforced by scene_parse (configurable with refractd flags). */
struct scene_limits {
    int max_resolution; /* per axis */
    int64_t max_voxels; /* summed over the scene's objects */
    int max_objects;
    int max_layers;         /* per channel */
    int max_profile_points; /* lathe polygon */
    int max_text_length;
    int max_image_dim; /* camera width/height */
    int max_steps;
    int64_t max_mesh_triangles; /* per uploaded mesh, after splitting polygons */
    int max_samples_per_pixel;  /* view renders' jittered rays per pixel */
    /* Decoded voxels of one uploaded volume. A gzip NRRD of 62 KB decodes to 64M voxels
     * (256 MB as float32), so this, not the body size, bounds what an upload costs. */
    int64_t max_upload_voxels;
};

/* render.samples_per_pixel and its request twins (render and view requests): a square
 * number (k x k equal strata) in 1..lim->max_samples_per_pixel; def when item is NULL. */
struct cJSON;
enum refract_code scene_read_samples_per_pixel(const struct cJSON *item, const char *path, int def,
                                               const struct scene_limits *lim, int *out,
                                               struct err *e);

/* Defaults: 512, 64M voxels, 8 objects, 64 layers, 1024 points, 64 chars, 4096, 100000,
 * 2M triangles, 32M voxels per upload. */
struct scene_limits scene_limits_default(void);

/* Parses and validates a whole scene document (not NUL-terminated; len bytes).
 * On success *out is a new scene; the caller destroys it with scene_destroy().
 * On failure returns the code and e->msg starts with the JSON path. */
enum refract_code scene_parse(const char *json, size_t len, const struct scene_limits *limits,
                              struct scene **out, struct err *e);
void scene_destroy(struct scene *s);

/* ---- uploaded volumes referenced by SCENE_LAYER_VOLUME ---- */

struct mesh; /* server/mesh/mesh.h */

struct scene_volume {
    int dims[3];             /* x, y, z */
    int components;          /* 1 or 3 */
    const float *data;       /* dims[0]*dims[1]*dims[2]*components floats, x fastest */
    const struct mesh *mesh; /* set (and the rest unused) when looked up as a mesh */
};

/* Returns the volume uploaded under `name`, or NULL. Borrowed for the call.
 *
 * Meshes (SCENE_SHAPE_MESH) are found through the same function, asked for
 * SCENE_MESH_LOOKUP_PREFIX followed by the mesh's name ("mesh:glass"); upload names are
 * [A-Za-z0-9_-], so the two kinds never collide. The answer then has `mesh` set.
 * CONCEPT: a second scene_mesh_lookup_fn next to this one. REALITY: every caller of
 * scene_field_eval (render, lightsim, the irradiance cache, tests) passes one function
 * and one ctx through several interfaces; adding a second function to each would have
 * touched all of them while other branches change them, so meshes share the function
 * and scene_mesh_lookup() hides the naming. */
typedef const struct scene_volume *(*scene_volume_lookup_fn)(void *ctx, const char *name);

#define SCENE_MESH_LOOKUP_PREFIX "mesh:"

/* The mesh uploaded under `name` (lookup(ctx, "mesh:" name)->mesh), or NULL. Borrowed. */
const struct mesh *scene_mesh_lookup(scene_volume_lookup_fn lookup, void *ctx, const char *name);

/* Number of floats per voxel that scene_field_eval writes for a channel: 1 for ior and
 * anisotropy, 4 for the others (RGB + 0 for attenuation/emission/scattering; RGB +
 * coverage for opaque). */
int scene_channel_components(enum scene_channel ch);
const char *scene_channel_name(enum scene_channel ch);
bool scene_channel_used(const struct scene_object *obj, enum scene_channel ch);

/* Lists volume names referenced by the scene that lookup cannot find, comma
 * separated, into buf. Returns how many are missing. */
int scene_missing_volumes(const struct scene *s, scene_volume_lookup_fn lookup, void *ctx,
                          char *buf, size_t buf_size);

/* Lists mesh names referenced by mesh shapes that lookup cannot find, comma separated,
 * into buf, each once. Returns how many are missing. */
int scene_missing_meshes(const struct scene *s, scene_volume_lookup_fn lookup, void *ctx, char *buf,
                         size_t buf_size);

/* Evaluates channel ch of obj at every voxel centre into out (x fastest, then y, then
 * z; scene_channel_components(ch) floats per voxel). Voxel (i,j,k) has its centre at
 * bounds_min + (i + 0.5) * (bounds_max - bounds_min) / resolution. Borrows everything
 * until return. Fails only on a missing or mismatched volume or a missing mesh
 * (REFRACT_E_CONFLICT), or OUT_OF_MEMORY for a mesh layer's coverage grid or a bound
 * object's mask. Mesh layers are voxelized here, in parallel on all CPUs (mesh_voxelize). A
 * bound object's field is continued beyond its surface (scene_field_extend_bound). */
enum refract_code scene_field_eval(const struct scene *s, const struct scene_object *obj,
                                   enum scene_channel ch, scene_volume_lookup_fn lookup, void *ctx,
                                   float *out, struct err *e);

/* For an object bound to a surface (obj->bound): replaces the channel's voxels outside the
 * surface's solid, in a band of 2 + 3 sigma voxels, by the inside field continued linearly
 * across the surface, so that samples near the surface see only the medium
 * (scene_field_bound.c). scene_field_eval calls it; a no-op for free objects. Borrows
 * everything until return; fails only with OUT_OF_MEMORY. */
enum refract_code scene_field_extend_bound(const struct scene *s, const struct scene_object *obj,
                                           enum scene_channel ch, scene_volume_lookup_fn lookup,
                                           void *ctx, float *out, struct err *e);

/* Signed distance from p (object space) to the shape's surface: negative inside.
 * Exact for sphere, box, rounded_box, cylinder, lathe and text; for bumpy_sphere a
 * first-order estimate near the surface, with the exact sign (shapes.c). Meshes are not
 * known here (they are uploads): INFINITY, and scene_field.c voxelizes them instead. */
double scene_shape_sdf(const struct scene_shape *shape, vec3 p);

/* Axis-aligned box (object space) that contains the shape's solid. Returns false, and
 * leaves lo/hi alone, when the solid is empty (text of spaces only). */
bool scene_shape_bounds(const struct scene_shape *shape, vec3 *lo, vec3 *hi);

/* ---- exact surfaces for the marches (scene_surface.c) ---- */

struct geom_surface; /* core/geom/geom.h */

/* The surface as core/geom describes it. A mesh surface gets kind GEOM_MESH and its
 * transform; the caller attaches the mesh. */
void scene_surface_geom(const struct scene_surface *sf, struct geom_surface *g);
/* A mesh surface with its mesh m: object space is mesh space (the surface's transform
 * after the shape's placement), crossings by mesh_rt, inside by the winding number. */
void scene_surface_geom_mesh(const struct scene_surface *sf, const struct mesh *m,
                             struct geom_surface *g);
/* Either of the two; a mesh surface finds its mesh through lookup ("mesh:" names, as
 * mesh layers do). false when the mesh is missing (g then describes nothing). */
bool scene_surface_geom_lookup(const struct scene_surface *sf, scene_volume_lookup_fn lookup,
                               void *ctx, struct geom_surface *g);
/* The set of surfaces (bit k: s->surfaces[k], in priority order) whose solids contain the
 * world point p: where a ray from p starts (core/interface.h). */
uint32_t scene_surfaces_inside(const struct scene *s, scene_volume_lookup_fn lookup, void *ctx,
                               vec3 p);
/* A surface's world box (infinite components for planes); false for meshes, whose box
 * is known only with the upload (scene_parse_surface.c). */
bool scene_surface_world_bounds(const struct scene_surface *sf, vec3 *lo, vec3 *hi);

/* True when the object's index is the same everywhere (no ior layers, or constants only):
 * inside a surface it fills, rays go straight (docs/tracing.md "Fields inside surfaces"). */
bool scene_ior_constant(const struct scene_object *obj);

/* Voxel size of an object in object-space units along each axis, and its smallest. */
vec3 scene_object_voxel_size(const struct scene_object *obj);
double scene_object_min_voxel(const struct scene_object *obj);

#endif
