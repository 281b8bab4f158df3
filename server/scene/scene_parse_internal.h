/*
 * scene_parse_internal.h - what the scene parser's files share; not part of the
 * module's interface (include scene.h instead).
 *
 * scene_parse.c reads the document, camera, render settings and objects;
 * scene_parse_field.c reads one channel of one object (values, shape, profile and
 * volume layers). Both report limits the same way through scene_limit_error.
 */
#ifndef REFRACT_SCENE_PARSE_INTERNAL_H
#define REFRACT_SCENE_PARSE_INTERNAL_H

#include <cjson/cJSON.h>

#include "scene.h"

/* Largest coordinate, length or scale a scene may use, in object or world units. */
#define SCENE_COORD_MAX 1e6
/* Smallest transform.scale, and smallest bounds extent per axis: absolute (object units)
 * and relative to the largest |coordinate| of the bounds on that axis. Below them the
 * GPU's single-precision march cannot represent the object (docs/scenes.md). */
#define SCENE_SCALE_MIN 1e-6
#define SCENE_BOUNDS_MIN_EXTENT 1e-6
#define SCENE_BOUNDS_MIN_RELATIVE 1e-4

/* What a channel's parser needs to know about the document around it. Borrowed. */
struct scene_parse_ctx {
    const struct scene_limits *limits;
    double ambient_ior;          /* default n_out of gaussian profiles */
    vec3 bounds_min, bounds_max; /* the object's bounds, to check linear profiles */
};

/* Parses the FIELD `item` (JSON path `path`) of channel ch into out. On failure out may
 * hold some layers; scene_field_fini frees them either way. */
enum refract_code scene_parse_field(const cJSON *item, const char *path, enum scene_channel ch,
                                    const struct scene_parse_ctx *ctx, struct scene_field *out,
                                    struct err *e);

/* A bare shape object ("shape" and its geometry keys) into out (scene_parse_field.c). */
enum refract_code scene_parse_region(const cJSON *o, const char *path,
                                     const struct scene_parse_ctx *ctx, struct scene_shape *out,
                                     struct err *e);

/* scene_parse_particles.c: an object's "particles" medium (docs/media.md), turned into its
 * attenuation, scattering and anisotropy fields. Absent -> OK and nothing changes. */
enum refract_code scene_parse_particles(const cJSON *obj, const char *path,
                                        const struct scene_parse_ctx *ctx, struct scene_object *o,
                                        struct err *e);

/* The geometry keys of a voxel shape kind (after "shape": centre, radius, ...), and their
 * parser (scene_parse_field.c), shared with the surfaces' parser. */
const char *const *scene_shape_keys(enum scene_shape_kind kind);
enum refract_code scene_parse_geometry(const cJSON *o, const char *path,
                                       const struct scene_limits *lim, struct scene_shape *s,
                                       struct err *e);
/* scene_parse.c: an object's or a surface's "transform". */
enum refract_code scene_parse_transform(const cJSON *obj, const char *path, struct xform *x,
                                        struct err *e);
/* scene_parse_surface.c: "surfaces" (arr may be NULL: none); after the objects, which it
 * checks the surfaces against. */
enum refract_code scene_parse_surfaces(const cJSON *arr, const struct scene_limits *lim,
                                       struct scene *s, struct err *e);
/* Refuses, naming `path` (what asks for the light simulator: "receiver",
 * "objects[2].scattering"), a scene whose surfaces include one filled by an object's field
 * (medium "object"): the light simulator's wavefront does not bend inside surfaces yet. */
/* receiver.caustics "photons" (docs/photons.md "Not yet"): refuses volume objects, surfaces
 * filled by an object's field, scattering media and unbounded (plane) surfaces whose
 * medium differs from the ambient one, each with a message that names it. */
enum refract_code scene_check_photon_surfaces(const struct scene *s, struct err *e);
/* A receiver's "auto" caustics (the default) becomes the method the scene needs
 * (docs/photons.md "Choosing"): "volume" when a volume object, a field-filled surface, a
 * scattering medium or an infinite optical plane is present; else "photons" when some
 * surface changes light (another index, absorption); else "none". Sets caustics_reason. */
void scene_resolve_caustics(struct scene *s);
enum refract_code scene_check_lightsim_surfaces(const struct scene *s, const char *path,
                                                struct err *e);

/* Frees what a field owns (layers, lathe profiles, text) and zeroes it. */
void scene_field_fini(struct scene_field *f);

/* scene_parse_light.c: "lights" (arr may be NULL: no lights), one light object at path,
 * "receiver" (o may be NULL: disabled; parse the objects first, the default half_size
 * depends on them), "lightsim" (o may be NULL: all defaults) and an object's "brdf". */
enum refract_code scene_parse_lights(const cJSON *arr, struct scene *s, struct err *e);
enum refract_code scene_parse_light(const cJSON *o, const char *path, int index,
                                    struct scene_light *l, struct err *e);
enum refract_code scene_parse_receiver(const cJSON *o, struct scene *s, struct err *e);
enum refract_code scene_parse_lightsim(const cJSON *o, struct scene_lightsim *ls, struct err *e);
enum refract_code scene_parse_brdf(const cJSON *obj, const char *path, struct scene_brdf *b,
                                   struct err *e);

/* LIMIT_EXCEEDED: "<path>: <given> exceeds the limit <limit_name> = <value>; start
 * refractd with <flag> to raise it". */
enum refract_code scene_limit_error(struct err *e, const char *path, const char *given,
                                    const char *limit_name, long long value, const char *flag);

/* An integer item (already looked up; NULL = absent -> def) in min..limit: below min or
 * not an integer is INVALID_FIELD, above limit is LIMIT_EXCEEDED via scene_limit_error. */
enum refract_code scene_read_limited_int(const cJSON *item, const char *path, int def, int min,
                                         int limit, const char *limit_name, const char *flag,
                                         int *out, struct err *e);

#endif
