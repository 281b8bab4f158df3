/*
 * scene_transport.c - what a scene asks of the light simulator: whether it needs one at
 * all, and the hash of everything that shapes its irradiance volumes (the scene half of
 * the irradiance cache key, docs/lightsim.md; the light's pose is the other half).
 *
 * The hash reads the parsed structs field by field, never the document: parsing fills in
 * every default, so "written out" and "left away" meet here as the same numbers, and key
 * order cannot matter. Doubles enter as their bit patterns with -0 folded into +0 (they
 * compare equal, and "-0" is valid JSON). Variable-length parts (layer lists, lathe
 * polygons, text, volume names) are prefixed by their lengths, so that no two different
 * scenes concatenate to the same byte stream.
 *
 * Deliberately left out (transport is linear in them, or they act after the simulation):
 * lights (their pose keys each volume separately; colour and intensity scale it), camera,
 * environment, emission, anisotropy (of objects and surface media alike: it shapes
 * in-scattering at render time, not the irradiance arriving), BRDFs, names, the receiver's
 * albedo and the render settings other than boundary_threshold.
 */
#include <string.h>

#include "scene.h"

#define FNV_OFFSET 0xcbf29ce484222325ull
#define FNV_PRIME 0x100000001b3ull

bool scene_surface_scatters(const struct scene_surface *sf)
{
    const struct scene_medium *m = &sf->medium;
    return !m->has_object &&
           (m->scattering[0] > 0.0 || m->scattering[1] > 0.0 || m->scattering[2] > 0.0);
}

bool scene_scatters(const struct scene *s)
{
    for (size_t i = 0; i < s->object_count; i++) {
        if (scene_channel_used(&s->objects[i], SCENE_CH_SCATTERING))
            return true;
    }
    for (size_t k = 0; k < s->surface_count; k++) {
        if (scene_surface_scatters(&s->surfaces[k]))
            return true;
    }
    return false;
}

bool scene_needs_light_simulation(const struct scene *s)
{
    if (s->receiver.enabled && s->receiver.caustics == SCENE_CAUSTICS_VOLUME)
        return true; /* photons: shadow rays and the photon map (docs/photons.md) */
    if (scene_walter_sphere(s, NULL))
        return false; /* exact single-scattering paths (docs/walter.md) */
    return scene_scatters(s);
}

bool scene_needs_photon_maps(const struct scene *s)
{
    return s->receiver.enabled && s->receiver.caustics == SCENE_CAUSTICS_PHOTONS;
}

bool scene_receiver_shadow_rays(const struct scene *s)
{
    return s->receiver.enabled && (s->receiver.caustics == SCENE_CAUSTICS_PHOTONS ||
                                   s->receiver.caustics == SCENE_CAUSTICS_NONE);
}

static void mix_bytes(uint64_t *h, const void *data, size_t n)
{
    const unsigned char *p = data;
    for (size_t i = 0; i < n; i++) {
        *h ^= p[i];
        *h *= FNV_PRIME;
    }
}

/* Little-endian byte order regardless of the host, so hashes agree across machines. */
static void mix_u64(uint64_t *h, uint64_t v)
{
    unsigned char b[8];
    for (int i = 0; i < 8; i++)
        b[i] = (unsigned char)(v >> (8 * i));
    mix_bytes(h, b, sizeof b);
}

static void mix_int(uint64_t *h, long long v)
{
    mix_u64(h, (uint64_t)v);
}

static void mix_double(uint64_t *h, double v)
{
    if (v == 0.0)
        v = 0.0; /* -0 -> +0 */
    uint64_t bits;
    memcpy(&bits, &v, sizeof bits);
    mix_u64(h, bits);
}

static void mix_vec3(uint64_t *h, vec3 v)
{
    mix_double(h, v.x);
    mix_double(h, v.y);
    mix_double(h, v.z);
}

static void mix_string(uint64_t *h, const char *s)
{
    size_t n = s ? strlen(s) : 0;
    mix_int(h, (long long)n);
    mix_bytes(h, s, n);
}

/* Every geometric field of a shape. The parser leaves the fields a kind does not use at
 * zero (layers are zero-allocated), so hashing them all is both simple and exact. */
static void mix_shape(uint64_t *h, const struct scene_shape *sh)
{
    mix_int(h, sh->kind);
    mix_vec3(h, sh->center);
    mix_double(h, sh->radius);
    mix_vec3(h, sh->size);
    mix_double(h, sh->height);
    mix_int(h, sh->axis);
    mix_vec3(h, sh->base);
    mix_int(h, (long long)sh->profile_count);
    for (size_t i = 0; i < sh->profile_count; i++) {
        mix_double(h, sh->profile[i][0]);
        mix_double(h, sh->profile[i][1]);
    }
    mix_string(h, sh->text);
    mix_double(h, sh->depth);
    mix_double(h, sh->bump_amplitude);
    mix_int(h, sh->bump_frequency);
    if (sh->kind == SCENE_SHAPE_MESH) {
        /* The name; the caller mixes in the mesh's content checksum like a volume's. */
        mix_string(h, sh->mesh);
        mix_vec3(h, sh->object_from_mesh.translate);
        for (int r = 0; r < 3; r++)
            mix_vec3(h, vec3_make(sh->object_from_mesh.rot[r][0], sh->object_from_mesh.rot[r][1],
                                  sh->object_from_mesh.rot[r][2]));
        mix_double(h, sh->object_from_mesh.scale);
    }
}

static void mix_profile(uint64_t *h, const struct grin_profile *g)
{
    mix_int(h, g->kind);
    mix_vec3(h, g->center);
    mix_double(h, g->radius);
    mix_double(h, g->n0);
    mix_vec3(h, g->gradient);
    mix_double(h, g->n_peak);
    mix_double(h, g->n_out);
    mix_double(h, g->sigma);
}

static void mix_values(uint64_t *h, const double v[4])
{
    for (int c = 0; c < 4; c++)
        mix_double(h, v[c]);
}

static void mix_field(uint64_t *h, const struct scene_field *f)
{
    mix_int(h, (long long)f->count);
    for (size_t i = 0; i < f->count; i++) {
        const struct scene_layer *l = &f->layers[i];
        mix_int(h, l->kind);
        switch (l->kind) {
        case SCENE_LAYER_CONSTANT:
            mix_values(h, l->inside);
            break;
        case SCENE_LAYER_SHAPE:
            mix_shape(h, &l->shape);
            mix_values(h, l->inside);
            mix_int(h, l->has_outside);
            if (l->has_outside)
                mix_values(h, l->outside);
            break;
        case SCENE_LAYER_PROFILE:
            mix_profile(h, &l->profile);
            break;
        case SCENE_LAYER_VOLUME:
            /* The content is the caller's to mix in (its checksum); here the reference. */
            mix_string(h, l->volume);
            mix_double(h, l->volume_scale);
            mix_double(h, l->volume_offset);
            break;
        }
    }
}

static void mix_xform(uint64_t *h, const struct xform *x)
{
    mix_vec3(h, x->translate);
    for (int r = 0; r < 3; r++) {
        for (int c = 0; c < 3; c++)
            mix_double(h, x->rot[r][c]);
    }
    mix_double(h, x->scale);
}

static void mix_object(uint64_t *h, const struct scene_object *o)
{
    static const enum scene_channel transport_channels[] = {SCENE_CH_IOR, SCENE_CH_ATTENUATION,
                                                            SCENE_CH_SCATTERING, SCENE_CH_OPAQUE};
    mix_vec3(h, o->bounds_min);
    mix_vec3(h, o->bounds_max);
    for (int a = 0; a < 3; a++)
        mix_int(h, o->resolution[a]);
    mix_xform(h, &o->world_from_object);
    mix_double(h, o->smoothing_sigma_voxels);
    mix_double(h, o->opaque_ior);
    for (size_t c = 0; c < sizeof transport_channels / sizeof transport_channels[0]; c++) {
        mix_int(h, transport_channels[c]);
        mix_field(h, &o->fields[transport_channels[c]]);
    }
}

static void mix_lightsim(uint64_t *h, const struct scene_lightsim *ls)
{
    mix_int(h, ls->resolution);
    mix_double(h, ls->step_voxels);
    mix_int(h, ls->initial_patches);
    mix_int(h, ls->max_level);
    mix_double(h, ls->split_voxels);
    mix_double(h, ls->energy_threshold);
    mix_double(h, ls->point_radius);
    mix_int(h, ls->deposit);
    mix_int(h, ls->cull_flipped);
    mix_int(h, ls->max_patches);
}

/* A surface and its medium (docs/tracing.md "Surfaces"): the order is the priority
 * order, which decides the media. Emission is left out as for objects. */
static void mix_surface(uint64_t *h, const struct scene_surface *sf)
{
    mix_shape(h, &sf->shape);
    mix_vec3(h, sf->shape.normal);
    mix_xform(h, &sf->world_from_object);
    mix_int(h, sf->priority);
    mix_double(h, sf->medium.ior);
    for (int c = 0; c < 3; c++)
        mix_double(h, sf->medium.attenuation[c]);
    /* The medium "object" form: which object fills the solid (its fields are mixed with
     * the objects). Only when set, so constant media hash as before. */
    if (sf->medium.has_object) {
        mix_int(h, 0x0b1ec7);
        mix_int(h, sf->medium.object);
    }
    /* Scattering: part of the extinction the light simulator applies (sigma_a + sigma_s).
     * Only when the medium scatters, so non-scattering media hash as before. */
    if (scene_surface_scatters(sf)) {
        mix_int(h, 0x5ca77e);
        for (int c = 0; c < 3; c++)
            mix_double(h, sf->medium.scattering[c]);
    }
}

uint64_t scene_transport_hash(const struct scene *s)
{
    uint64_t h = FNV_OFFSET;
    mix_double(&h, s->ambient_ior);
    mix_double(&h, s->render.boundary_threshold);
    mix_int(&h, (long long)s->object_count);
    for (size_t i = 0; i < s->object_count; i++)
        mix_object(&h, &s->objects[i]);
    /* Scenes without surfaces hash as they did before surfaces existed, so that their
     * cached irradiance volumes stay valid. */
    if (s->surface_count > 0) {
        mix_int(&h, (long long)s->surface_count);
        for (size_t i = 0; i < s->surface_count; i++)
            mix_surface(&h, &s->surfaces[i]);
    }
    /* A disabled receiver's numbers are zero from the parser, but only its presence
     * matters then. */
    mix_int(&h, s->receiver.enabled);
    if (s->receiver.enabled) {
        mix_double(&h, s->receiver.height);
        mix_double(&h, s->receiver.half_size); /* INFINITY for the whole plane */
        mix_double(&h, s->receiver.center[0]);
        mix_double(&h, s->receiver.center[1]);
    }
    mix_lightsim(&h, &s->lightsim);
    return h;
}
