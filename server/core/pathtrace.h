/*
 * pathtrace.h - the CPU double-precision reference path tracer (docs/pathtracer.md): an
 * unbiased Monte Carlo estimator of the radiance arriving along a camera ray, for exact
 * surfaces bounding homogeneous media, a diffuse receiver plane, point, spot, directional
 * and spherical lights and a uniform or procedural environment.
 *
 * What it is: the twin every later kernel (the GPU path tracer) is checked against, and
 * the engine of render requests with "mode": "reference". It shares the fast renderer's
 * surfaces (geom/geom.h), interface event and medium rule (interface.h) and Fresnel
 * (fresnel.h); it is independent of the voxel marches (reftrace.h) and of the light
 * simulator.
 *
 * The estimator, per path (docs/pathtracer.md "Estimators"):
 *   - specular interfaces: reflection with probability R (unpolarised Fresnel), refraction
 *     otherwise, total internal reflection always reflects; the throughput does not change;
 *   - media: free-flight distances by the closed form of a homogeneous medium, one colour
 *     channel chosen per collision with the one-sample MIS of the channels (spectral MIS);
 *     absorption-only media attenuate in closed form (Beer-Lambert, no sampling);
 *     Henyey-Greenstein phase function, any number of scatterings;
 *   - the receiver: Lambertian, cosine-sampled;
 *   - next-event estimation from every diffuse or medium vertex; a shadow ray passes
 *     surfaces whose two sides have the same index (with the medium's transmittance) and is
 *     blocked by every refracting interface and the receiver;
 *   - a spherical light hit by a diffuse- or phase-sampled ray counts with the balance
 *     heuristic against its NEE; after a specular event or from the camera (when visible)
 *     it counts in full; point, spot and directional lights are reached by NEE only;
 *   - the environment is reached only by escaping rays (no environment NEE yet);
 *   - Russian roulette after PATHTRACE_RR_DEPTH vertices with survival
 *     min(1, max channel of the throughput); no clamping. PATHTRACE_MAX_DEPTH ends a path
 *     that is still alive after so many events (purely specular loops, which roulette never
 *     ends because their throughput stays 1).
 *
 * Conventions: world space, directions unit along propagation, lengths in world units,
 * coefficients per world unit, radiance in W sr^-1 unit^-2 per channel (linear RGB).
 * Ownership: every function borrows its pointers until return. Thread: any; no globals
 * (each caller owns its pathtrace_rng).
 */
#ifndef REFRACT_PATHTRACE_H
#define REFRACT_PATHTRACE_H

#include <stdbool.h>
#include <stdint.h>

#include "geom/geom.h"
#include "pathtrace_rng.h"
#include "vec3.h"

#define PATHTRACE_MAX_SURFACES 32 /* = INTERFACE_MAX_SURFACES */
#define PATHTRACE_MAX_LIGHTS 8
#define PATHTRACE_RR_DEPTH 4     /* events before Russian roulette starts */
#define PATHTRACE_MAX_DEPTH 1024 /* events of one path at most (see above) */

/* A homogeneous medium: the inside of a surface, or the ambient medium. */
struct pathtrace_medium {
    double ior;        /* refractive index, >= 1 */
    double sigma_a[3]; /* absorption per world unit, >= 0 */
    double sigma_s[3]; /* scattering per world unit, >= 0 */
    double g;          /* Henyey-Greenstein anisotropy, (-1, 1); 0 isotropic */
};

/* An exact surface and the medium inside it; an array of them is sorted by nesting
 * priority, index 0 the highest (interface.h). */
struct pathtrace_surface {
    struct geom_surface geom;
    struct pathtrace_medium medium;
};

/* The Lambertian plane y = height, |x - center[0]|, |z - center[1]| <= half_size
 * (INFINITY: the whole plane), seen from both sides. */
struct pathtrace_receiver {
    bool enabled;
    double height, half_size;
    double albedo[3];
    double center[2]; /* world x, z of the square's centre */
};

enum pathtrace_light_kind {
    PATHTRACE_LIGHT_POINT = 0,       /* intensity I (W/sr) at position */
    PATHTRACE_LIGHT_SPOT = 1,        /* point light inside the cone cos >= cos_spot */
    PATHTRACE_LIGHT_DIRECTIONAL = 2, /* irradiance E normal to the beam along direction */
    PATHTRACE_LIGHT_SPHERE = 3,      /* Lambertian sphere of radius, radiance L_e */
};

struct pathtrace_light {
    enum pathtrace_light_kind kind;
    vec3 position;  /* point, spot, sphere: world */
    vec3 direction; /* spot, directional: unit, the way the light travels */
    double cos_spot;
    double radius;   /* sphere: > 0 */
    double value[3]; /* point, spot: I (W/sr); directional: E (W/unit^2); sphere: L_e */
    bool visible;    /* sphere: seen by camera rays (specular and indirect rays always) */
};

enum pathtrace_env_kind {
    PATHTRACE_ENV_UNIFORM = 0,    /* radiance env_radiance in every direction */
    PATHTRACE_ENV_PROCEDURAL = 1, /* env_procedural(d) (env.h) times env_radiance */
};

struct pathtrace_scene {
    const struct pathtrace_surface *surfaces; /* by priority; NULL when count is 0 */
    int surface_count;                        /* 0..PATHTRACE_MAX_SURFACES */
    struct pathtrace_medium ambient;          /* outside every surface */
    struct pathtrace_receiver receiver;
    struct pathtrace_light lights[PATHTRACE_MAX_LIGHTS];
    int light_count;
    enum pathtrace_env_kind env_kind;
    double env_radiance[3];
    /* Most medium scattering events of a path (0: unlimited, the default); a path that
     * would scatter once more ends there. 1 gives the single-scattered part of the image
     * (and what reaches the eye unscattered): what the fast renderer models
     * (refract-pictures --ref-max-scatter; CPU only, the GPU path tracer has no such
     * limit). */
    int max_scatter;
    /* walter2009's exact connections (docs/walter.md "In the path tracer"): in the medium of
     * surface `surface`, a sphere (centre, radius; its index over the ambient one eta) that
     * is the only way light reaches that medium, a medium vertex connects to each small
     * light outside by every refracted path through the sphere (the point-light NEE a
     * shadow ray cannot make through glass), and a path that scatters there, refracts out
     * and meets such a light does not count it again. Off (enabled false) by default;
     * scene_pathtrace sets it for scene_walter_sphere scenes. */
    struct pathtrace_walter {
        bool enabled;
        int surface;
        vec3 center;
        double radius, eta;
        /* true: after a vertex in that medium, no hit of a small light counts at all (the
         * light that reached the vertex after an internal reflection too, which the
         * connections do not carry): the image of exactly the connected paths, what the
         * fast renderer's single scattering models (refract-pictures --ref-walter-only) */
        bool connected_only;
        /* the largest radius / distance of a sphere lamp connected as a point (scene_pathtrace
         * sets 0.02) */
        double lamp_ratio;
    } walter;
};

/* True when light k is small enough for the exact connections (pathtrace_scene.walter):
 * a point, spot or directional light, or a sphere lamp whose radius is at most
 * walter.lamp_ratio (2 %) of its distance to the walter sphere's centre (treated as a point
 * at its centre; the error is of the order of that ratio squared). */
bool pathtrace_walter_light(const struct pathtrace_scene *s, int k);

/* The converted spherical light of total flux phi_w (W, per channel) and radius r: a
 * Lambertian sphere of radiance L_e = phi / (4 pi^2 r^2), whose far field is a point of
 * intensity phi / (4 pi) (docs/pathtracer.md "Lights"). */
double pathtrace_sphere_radiance(double phi_w, double radius);

/* The receiver's hit of the ray o + t d with t in (tmin, tmax): true with *t (the photon
 * tracer uses it too). */
bool pathtrace_receiver_hit(const struct pathtrace_receiver *r, vec3 o, vec3 d, double tmin,
                            double tmax, double *t);

/* The set of surfaces whose solids contain p (bit k for surface k): the camera's start. */
uint32_t pathtrace_inside_set(const struct pathtrace_scene *s, vec3 p);

/* One sample of the radiance arriving at origin from direction -dir (unit dir), per
 * channel, into L; inside: the set of surfaces containing origin
 * (pathtrace_inside_set). camera: true for camera rays (lights with visible = false
 * are then not seen directly). */
void pathtrace_radiance(const struct pathtrace_scene *s, vec3 origin, vec3 dir, uint32_t inside,
                        bool camera, struct pathtrace_rng *rng, double L[3]);

/* ---- pathtrace_light.c: next-event estimation ---- */

/* A sampled connection from a shading point to light k: the unit direction towards it,
 * the distance to the point sampled on it (INFINITY: directional), the incident radiance
 * divided by the pdf (per channel, 0 when outside a spot cone or behind the point), and
 * the pdf in solid angle (0 for delta lights, which take no MIS). */
struct pathtrace_light_sample {
    vec3 wi;
    double dist;
    double Li_over_pdf[3];
    double pdf_sa;
};
void pathtrace_light_sample(const struct pathtrace_light *l, vec3 p, struct pathtrace_rng *rng,
                            struct pathtrace_light_sample *out);
/* The nearest hit (t in (tmin, tmax)) of the ray with a spherical light; false for the
 * other kinds. */
bool pathtrace_light_hit(const struct pathtrace_light *l, vec3 o, vec3 d, double tmin, double tmax,
                         double *t);
/* The solid-angle pdf with which pathtrace_light_sample picks direction d from p, for a
 * spherical light p is outside of (the cone of its visible cap). */
double pathtrace_light_pdf(const struct pathtrace_light *l, vec3 p);

/* ---- pathtrace_medium.c: homogeneous media ---- */

/* Samples the next collision in medium m along a segment of length t_max (may be
 * INFINITY) with the one-sample MIS of the channels (pbrt-v3 HomogeneousMedium::Sample).
 * Returns true and sets *t for a real collision (a scattering event), false when the
 * segment is crossed; in both cases multiplies weight[] by the estimator's factor
 * (T sigma_s / pdf or T / pdf). Absorption-only media never collide: weight *= T. */
bool pathtrace_medium_sample(const struct pathtrace_medium *m, double t_max,
                             struct pathtrace_rng *rng, double weight[3], double *t);
/* Transmittance exp(-sigma_t d) per channel, multiplied into tr[]. */
void pathtrace_medium_transmittance(const struct pathtrace_medium *m, double d, double tr[3]);
/* True when the medium scatters in some channel. */
bool pathtrace_medium_scatters(const struct pathtrace_medium *m);

/* ---- pathtrace_sample.c: directions ---- */

/* Cosine-weighted direction about unit n (pdf cos / pi). */
vec3 pathtrace_sample_cosine(vec3 n, struct pathtrace_rng *rng);
/* Henyey-Greenstein direction about the travel direction d (pdf = phase_hg(g, cos)). */
vec3 pathtrace_sample_hg(vec3 d, double g, struct pathtrace_rng *rng);
/* Uniform direction in the cone of half angle acos(cos_max) about unit axis (pdf
 * 1 / (2 pi (1 - cos_max))). */
vec3 pathtrace_sample_cone(vec3 axis, double cos_max, struct pathtrace_rng *rng);

#endif
