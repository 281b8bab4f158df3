/*
 * reftrace.h - the CPU double-precision reference tracer.
 *
 * It follows docs/tracing.md step for step, as the GPU kernels do, so tests can bound
 * the GPU's deviation: same objects, same voxel fields (or the exact analytic field),
 * same steppers, same statuses. It also offers an adaptive Runge-Kutta stepper
 * with error control (Dormand-Prince 5(4)) for references on exact continuous fields.
 *
 * This is not a renderer: it traces single rays, slowly and exactly. Radiance is
 * computed with the procedural environment (env.h) so image pixels can be checked too.
 *
 * Ownership: reftrace borrows every pointer in its inputs for the duration of a call.
 * Thread: any; no globals.
 */
#ifndef REFRACT_REFTRACE_H
#define REFRACT_REFTRACE_H

#include <stdbool.h>

#include "brdf.h"
#include "geom/geom.h"
#include "interface.h"
#include "macrocell.h"
#include "ray_status.h"
#include "vec3.h"
#include "xform.h"

/* One object's precomputed voxel fields (docs/tracing.md "Precomputation"), x fastest.
 * NULL channels are unused. */
struct reftrace_grid {
    const double *ior_grad;    /* 4 per voxel: dn/dx, dn/dy, dn/dz (object units), n */
    const double *attenuation; /* 4 per voxel: sigma_a r, g, b per world unit, unused */
    const double *emission;    /* 4 per voxel: L_e r, g, b per world unit, unused */
    const double *opaque;      /* 4 per voxel: colour r, g, b, coverage */
    const double *scattering;  /* 4 per voxel: sigma_s r, g, b per world unit, unused */
    const double *anisotropy;  /* 1 per voxel: Henyey-Greenstein g */
};

/* The exact continuous index field of an object, in object space: returns n at p and
 * writes grad n. */
/* Reconstruction of a grid's index and gradient between voxel centres (render.ior_filter,
 * docs/tracing.md "Index filter"); the GPU's twin is the MARCH_IOR_FILTER variant. */
enum reftrace_ior_filter {
    REFTRACE_FILTER_TRILINEAR = 0, /* 8 taps, C0 */
    REFTRACE_FILTER_TRICUBIC = 1,  /* Catmull-Rom of n, its exact gradient (voxel_tricubic.h) */
};

typedef double (*reftrace_ior_fn)(void *ctx, vec3 p_object, vec3 *grad_object);

struct reftrace_object {
    vec3 bmin, bmax; /* object-space bounds */
    int res[3];      /* voxels per axis (also sets the step size for analytic fields) */
    struct xform xf; /* world_from_object */
    double smoothing_sigma_voxels; /* used for the boundary probe distance k */
    double opaque_ior;
    const struct reftrace_grid *grid; /* voxel fields; when NULL, `ior` is used */
    reftrace_ior_fn ior;              /* exact field (no attenuation/emission/opaque) */
    void *ior_ctx;
    struct brdf_params brdf;           /* reflection of lights at its Fresnel events; zero: none */
    const struct macrocell_map *cells; /* empty-space map of the voxel fields (macrocell.h);
                                          NULL: no skipping in this object */
    enum reftrace_ior_filter ior_filter; /* how `grid` reconstructs n and grad n */
    bool bound;        /* fills a surface (reftrace_surface.field): seen only through it, never
                          entered through its bounds */
    bool ior_constant; /* n is the same everywhere: inside a surface the ray goes straight and
                          only the integrals are stepped */
};

struct photon_grid; /* photon.h */

/* One light as the reference sees it (docs/tracing.md "Light"); the CPU twin of the GPU's
 * light_params, independent of the light simulator. */
struct reftrace_light {
    int kind;                      /* LIGHT_KIND_* (shaders/bindings.h) */
    int mode;                      /* LIGHT_MODE_OFF, _VOLUME, _DIRECT, _WALTER */
    vec3 position, direction;      /* world; direction unit, the way light travels */
    double cos_spot;               /* spot: cos of the cone half angle */
    double scale[3];               /* colour * intensity */
    const float *irradiance;       /* LIGHT_MODE_VOLUME: 4 per voxel (E rgb, -), x fastest */
    const float *direction_volume; /* 4 per voxel (light direction xyz, lit) */
    int dims[3];
    vec3 bmin;          /* world corner of the grid */
    double voxel;       /* cubic voxel edge, world units */
    double radius;      /* point: > 0, the lamp's sphere that rays leaving the scene see
                           (reftrace_light_emitter); 0: a point, never seen */
    bool camera_hidden; /* the sphere is not seen by camera rays that met nothing */
    /* receiver.caustics "photons": this light's photon map at unit intensity (scale
     * multiplies it; docs/photons.md "The cache"); NULL: no caustic from it (yet). */
    const struct photon_grid *photons;
};

/* The receiver plane y = height, |x - center[0]|, |z - center[1]| <= half_size
 * (INFINITY: the whole plane; thesis fig. 7.4). */
struct reftrace_receiver {
    bool enabled;
    double height, half_size;
    double albedo[3];
    double center[2]; /* world x, z of the square's centre */
};

struct pathtrace_scene; /* pathtrace.h */

struct reftrace_lighting {
    const struct reftrace_light *lights;
    int count;
    struct reftrace_receiver receiver;
    /* receiver.caustics "photons" (docs/photons.md; the GPU's lights.count.z = 1): the scene
     * whose surfaces the direct light's shadow rays test (its lights indexed as `lights`),
     * each light's map in reftrace_light.photons. NULL: the receiver reads the lights'
     * modes as usual. */
    const struct pathtrace_scene *photon_scene;
    /* The sphere of the lights in LIGHT_MODE_WALTER (docs/walter.md; the GPU's
     * lights.walter_sphere and walter_medium): in-scattering inside it by walter2009's exact
     * refracted paths. */
    struct reftrace_walter {
        bool enabled;
        vec3 center;
        double radius, eta; /* eta: the medium's index over the ambient one */
        double sigma_t[3];
        double step_offset; /* where the inner in-scattering steps sample, in (0, 1) (the
                               GPU's pixel_step_offset of the ray); 0: the midpoint */
    } walter;
};

enum reftrace_stepper {
    REFTRACE_EULER = 0,    /* tevs2007 eqs. 5.11/5.12 */
    REFTRACE_RK4 = 1,      /* classical Runge-Kutta, fixed step */
    REFTRACE_ADAPTIVE = 2, /* Dormand-Prince 5(4), error per step <= tolerance: the exact
                              reference, not a GPU stepper */
    REFTRACE_RK2 = 3,      /* explicit midpoint, fixed step (the GPU's "rk2") */
    REFTRACE_BS23 = 4,     /* Bogacki-Shampine 3(2) with step control, error per step <=
                              tolerance_voxels: the twin of the GPU's "adaptive" */
};

/* An exact surface and the medium inside it (docs/tracing.md "Surfaces"). An array of
 * them is sorted by nesting priority, index 0 the highest (interface.h). */
struct reftrace_surface {
    struct geom_surface geom;
    double ior;              /* constant n of the medium inside */
    double attenuation[3];   /* sigma_a per world unit */
    double emission[3];      /* L_e per world unit */
    double scattering[3];    /* sigma_s per world unit: extinction sigma_a + sigma_s and, with
                                lights, single in-scattering (docs/tracing.md "Scattering
                                inside surfaces") */
    double anisotropy;       /* Henyey-Greenstein g of the in-scattering */
    struct brdf_params brdf; /* reflection of lights where it refracts; zero: none */
    /* The medium "object" form: this bound object's fields fill the solid instead of the
     * constants above (ior, attenuation, emission unused); NULL: constant medium. Borrowed. */
    const struct reftrace_object *field;
};

/* sigma_t = sigma_a + sigma_s of a surface's constant medium in channel c (tevs2007 eq. 5.9:
 * light scattered out of a ray is lost to it); the twin of surface_extinction in
 * shaders/geom/surface.glsl. */
static inline double reftrace_surface_extinction(const struct reftrace_surface *sf, int c)
{
    return sf->attenuation[c] + sf->scattering[c];
}

/* One surface event of a ray (the trace API's "events"). */
enum reftrace_event_kind {
    REFTRACE_EVENT_REFRACTED = 0,
    REFTRACE_EVENT_REFLECTED = 1, /* total internal reflection */
};

struct reftrace_event {
    enum reftrace_event_kind kind;
    vec3 point, normal;         /* world; normal unit, pointing back into the incoming side */
    int surface;                /* index into the surface array */
    int medium_from, medium_to; /* surface whose medium it is, -1 the ambient medium */
    double n_from, n_to;
    double fresnel_R; /* the reflectance at the event; 1 for total internal reflection */
    double step_gap;  /* leaving a field-filled surface: distance from the event point (on the
                         surface) to the end of the ray-equation step cut there, world units
                         (the cut's accuracy, at most 1e-6 of the step); 0 otherwise */
};

#define REFTRACE_MAX_EVENTS 64

struct reftrace_settings {
    enum reftrace_stepper stepper;
    double step_voxels;        /* fixed step (euler, rk4); initial and largest step (adaptive) */
    int max_steps;             /* over the whole ray */
    double boundary_threshold; /* docs/tracing.md "Sharp boundaries" */
    double ambient_ior;
    double tolerance;        /* REFTRACE_ADAPTIVE: absolute error per step in object units */
    double tolerance_voxels; /* REFTRACE_BS23: error per step in voxels (h_min) of the object */
    double env_intensity;    /* procedural environment multiplier for radiance */
    const struct reftrace_lighting *lighting; /* lights and receiver; NULL: none. In-scattering
                                                 is not modelled by REFTRACE_ADAPTIVE. */
    bool empty_space_skipping;                /* jump over the objects' empty cells (render.
                                                 empty_space_skipping; not with REFTRACE_ADAPTIVE) */
    double min_throughput;                   /* the absorbed cut-off (render.min_throughput); 0: the
                                                default 1e-6; negative: never */
    const struct reftrace_surface *surfaces; /* exact surfaces by priority; NULL: none */
    int surface_count;                       /* at most INTERFACE_MAX_SURFACES */
};

struct reftrace_result {
    enum ray_status status;
    vec3 exit_origin, exit_direction; /* world space */
    vec3 transmittance;               /* T_fresnel * exp(-alpha), per channel */
    double optical_path_length;       /* integral of n ds, world units */
    int steps;
    vec3 radiance;   /* L along the ray as a view ray would gather it */
    int event_count; /* surface events, the first REFTRACE_MAX_EVENTS of them in events */
    struct reftrace_event events[REFTRACE_MAX_EVENTS];
};

/* The set of surfaces whose solids contain the world point p (bit k: surfaces[k]). */
uint32_t reftrace_inside_set(const struct reftrace_surface *surfaces, int count, vec3 p);

/* Traces one ray (origin, unit direction, world space) through `count` objects. */
void reftrace_ray(const struct reftrace_object *objects, int count,
                  const struct reftrace_settings *settings, vec3 origin, vec3 dir,
                  struct reftrace_result *out);

#endif
