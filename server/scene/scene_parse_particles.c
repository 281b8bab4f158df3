/*
 * scene_parse_particles.c - an object's "particles": a medium described by what it is made
 * of (a preset, or populations of spheres in a host), turned at parse time into the
 * object's attenuation, scattering and anisotropy fields by Lorenz-Mie theory
 * (server/core/mie, docs/media.md).
 *
 * The three fields get one layer each: a constant over the bounds, or, with "region", a
 * shape layer whose inside holds the medium and whose outside keeps 0. The object may not
 * also set attenuation, scattering or anisotropy itself: two descriptions of one medium
 * would have to be combined by a rule the document cannot see, so that is refused.
 *
 * Units: the Mie sums give coefficients per metre; "units_per_meter" (world units in one
 * metre, default 1) divides them into per world unit, the unit of the fields.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../core/mie/mie.h"
#include "json_read.h"
#include "scene_parse_internal.h"

#define MAX_VOLUME_FRACTION 0.74 /* densest packing of equal spheres */
#define MAX_RADIUS_UM 1000.0     /* keeps the size parameter below MIE_MAX_SIZE_PARAMETER */

static const cJSON *member(const cJSON *obj, const char *key)
{
    return cJSON_IsObject(obj) ? cJSON_GetObjectItemCaseSensitive(obj, key) : NULL;
}

/* A refractive index: a number n, or [n, k] with k >= 0 the absorbing part. */
static enum refract_code parse_index(const cJSON *item, const char *path, double complex *out,
                                     struct err *e)
{
    double n, k = 0.0;
    char got[80];
    if (cJSON_IsNumber(item)) {
        enum refract_code rc = jr_check_number(item, path, 1.0, false, 5.0, &n, e);
        *out = n;
        return rc;
    }
    if (!cJSON_IsArray(item) || cJSON_GetArraySize(item) != 2)
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "%s: expected a refractive index n in 1..5 or [n, k] with k in 0..10, got "
                       "%s",
                       path, jr_describe(item, got, sizeof got));
    char p[256];
    enum refract_code rc = jr_check_number(
        cJSON_GetArrayItem(item, 0), jr_path_index(p, sizeof p, path, 0), 1.0, false, 5.0, &n, e);
    if (rc == REFRACT_E_OK)
        rc = jr_check_number(cJSON_GetArrayItem(item, 1), jr_path_index(p, sizeof p, path, 1), 0.0,
                             false, 10.0, &k, e);
    *out = n + I * k;
    return rc;
}

/* Exactly one of the keys in names[0..count) is present; its index in *which. */
static enum refract_code exactly_one(const cJSON *o, const char *path, const char *const *names,
                                     int count, int *which, struct err *e)
{
    *which = -1;
    for (int i = 0; i < count; i++) {
        if (member(o, names[i]) == NULL)
            continue;
        if (*which >= 0)
            return err_set(e, REFRACT_E_INVALID_FIELD,
                           "%s: has both \"%s\" and \"%s\"; give exactly one of them", path,
                           names[*which], names[i]);
        *which = i;
    }
    if (*which < 0) {
        char list[200] = "";
        for (int i = 0; i < count; i++)
            snprintf(list + strlen(list), sizeof list - strlen(list), "%s\"%s\"",
                     i == 0           ? ""
                     : i == count - 1 ? " or "
                                      : ", ",
                     names[i]);
        return err_set(e, REFRACT_E_MISSING_FIELD, "%s: needs one of %s", path, list);
    }
    return REFRACT_E_OK;
}

/* "lognormal": {"r_vs_um", "c_s_um", "r_min_um", "r_max_um"} or "power_law":
 * {"exponent", "r_min_um", "r_max_um"}, radii in micrometres. */
static enum refract_code parse_distribution(const cJSON *o, const char *path, bool lognormal,
                                            struct mie_distribution *d, struct err *e)
{
    static const char *const ln_keys[] = {"r_vs_um", "c_s_um", "r_min_um", "r_max_um", NULL};
    static const char *const pl_keys[] = {"exponent", "r_min_um", "r_max_um", NULL};
    enum refract_code rc = jr_check_object(o, path, lognormal ? ln_keys : pl_keys, e);
    double r_min = 0, r_max = 0;
    if (rc == REFRACT_E_OK)
        rc = jr_number(o, path, "r_min_um", true, 0.0, lognormal ? 0.0 : 1e-4, MAX_RADIUS_UM,
                       &r_min, e);
    if (rc == REFRACT_E_OK)
        rc = jr_number_gt(o, path, "r_max_um", true, 0.0, r_min, MAX_RADIUS_UM, &r_max, e);
    if (rc != REFRACT_E_OK)
        return rc;
    d->r_min = r_min * 1e-6;
    d->r_max = r_max * 1e-6;
    if (!lognormal) {
        d->kind = MIE_DIST_POWER_LAW;
        return jr_number(o, path, "exponent", true, 0.0, -10.0, 10.0, &d->exponent, e);
    }
    double r_vs;
    d->kind = MIE_DIST_LOGNORMAL;
    rc = jr_number_gt(o, path, "r_vs_um", true, 0.0, r_min, r_max, &r_vs, e);
    if (rc == REFRACT_E_OK && r_vs >= r_max)
        rc = err_set(e, REFRACT_E_INVALID_FIELD, "%s.r_vs_um: must be below r_max_um (%g)", path,
                     r_max);
    if (rc == REFRACT_E_OK)
        rc = jr_number_gt(o, path, "c_s_um", true, 0.0, 0.0, MAX_RADIUS_UM, &d->c_s, e);
    d->r_vs = r_vs * 1e-6;
    return rc;
}

static enum refract_code parse_population(const cJSON *o, const char *path,
                                          struct mie_population *p, struct err *e)
{
    static const char *const keys[] = {
        "ior", "volume_fraction", "number_density", "radius_um", "lognormal", "power_law", NULL};
    static const char *const amounts[] = {"volume_fraction", "number_density"};
    static const char *const sizes[] = {"radius_um", "lognormal", "power_law"};
    enum refract_code rc = jr_check_object(o, path, keys, e);
    if (rc != REFRACT_E_OK)
        return rc;
    char p_ior[256];
    const cJSON *ior = member(o, "ior");
    if (ior == NULL)
        return err_set(e, REFRACT_E_MISSING_FIELD, "%s: missing required field \"ior\"", path);
    rc = parse_index(ior, jr_path(p_ior, sizeof p_ior, path, "ior"), &p->ior[0], e);
    int amount, size;
    if (rc == REFRACT_E_OK)
        rc = exactly_one(o, path, amounts, 2, &amount, e);
    if (rc == REFRACT_E_OK)
        rc = exactly_one(o, path, sizes, 3, &size, e);
    if (rc != REFRACT_E_OK)
        return rc;
    if (amount == 0)
        rc = jr_number(o, path, "volume_fraction", true, 0.0, 0.0, MAX_VOLUME_FRACTION,
                       &p->volume_fraction, e);
    else
        rc = jr_number(o, path, "number_density", true, 0.0, 0.0, 1e30, &p->number_density, e);
    if (rc != REFRACT_E_OK)
        return rc;
    if (size == 0) {
        double r;
        p->size.kind = MIE_DIST_MONODISPERSE;
        rc = jr_number_gt(o, path, "radius_um", true, 0.0, 0.0, MAX_RADIUS_UM, &r, e);
        p->size.r_vs = r * 1e-6;
        return rc;
    }
    char pd[256];
    const char *key = sizes[size];
    return parse_distribution(member(o, key), jr_path(pd, sizeof pd, path, key), size == 1,
                              &p->size, e);
}

/* Explicit populations in a host ("host": "water" by default, or an index). */
static enum refract_code parse_explicit(const cJSON *o, const char *path, struct mie_medium *m,
                                        struct err *e)
{
    char p[256], got[80];
    memset(m, 0, sizeof *m);
    const cJSON *host = member(o, "host");
    if (host == NULL || (cJSON_IsString(host) && strcmp(host->valuestring, "water") == 0)) {
        mie_host_water(m->host);
    } else if (cJSON_IsString(host)) {
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "%s: expected \"water\", a refractive index n or [n, k], got %s",
                       jr_path(p, sizeof p, path, "host"), jr_describe(host, got, sizeof got));
    } else {
        double complex n;
        enum refract_code rc = parse_index(host, jr_path(p, sizeof p, path, "host"), &n, e);
        if (rc != REFRACT_E_OK)
            return rc;
        for (int i = 0; i < MIE_SPECTRUM_SAMPLES; i++)
            m->host[i] = n;
    }
    const cJSON *pops = member(o, "populations");
    jr_path(p, sizeof p, path, "populations");
    if (pops == NULL)
        return err_set(e, REFRACT_E_MISSING_FIELD,
                       "%s: missing required field \"populations\" (or give a \"preset\")", path);
    int n = cJSON_IsArray(pops) ? cJSON_GetArraySize(pops) : -1;
    if (n < 1 || n > MIE_MAX_POPULATIONS)
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "%s: expected an array of 1..%d populations, "
                       "got %s",
                       p, MIE_MAX_POPULATIONS, jr_describe(pops, got, sizeof got));
    int i = 0;
    for (const cJSON *it = pops->child; it != NULL; it = it->next, i++) {
        char pi[256];
        enum refract_code rc =
            parse_population(it, jr_path_index(pi, sizeof pi, p, i), &m->pop[i], e);
        if (rc != REFRACT_E_OK)
            return rc;
    }
    m->count = n;
    return REFRACT_E_OK;
}

static enum refract_code parse_medium(const cJSON *o, const char *path, struct mie_medium *m,
                                      struct err *e)
{
    static const char *const presets[] = {"milk", "water", NULL};
    static const char *const milk_keys[] = {
        "preset", "fat_percent", "protein_percent", "riboflavin_mg_per_100g", "units_per_meter",
        "region", NULL};
    static const char *const water_keys[] = {"preset", "units_per_meter", "region", NULL};
    static const char *const explicit_keys[] = {"host", "populations", "units_per_meter", "region",
                                                NULL};
    if (member(o, "preset") == NULL) {
        enum refract_code rc = jr_check_object(o, path, explicit_keys, e);
        return rc == REFRACT_E_OK ? parse_explicit(o, path, m, e) : rc;
    }
    int preset;
    enum refract_code rc = jr_enum(o, path, "preset", true, 0, presets, &preset, e);
    if (rc == REFRACT_E_OK)
        rc = jr_check_object(o, path, preset == 0 ? milk_keys : water_keys, e);
    if (rc != REFRACT_E_OK)
        return rc;
    if (preset == 1) {
        mie_preset_water(m);
        return REFRACT_E_OK;
    }
    double fat, protein, riboflavin;
    rc = jr_number(o, path, "fat_percent", true, 0.0, 0.0, 40.0, &fat, e);
    if (rc == REFRACT_E_OK)
        rc = jr_number(o, path, "protein_percent", false, 3.4, 0.0, 15.0, &protein, e);
    if (rc == REFRACT_E_OK)
        rc = jr_number(o, path, "riboflavin_mg_per_100g", false, MIE_MILK_RIBOFLAVIN, 0.0, 10.0,
                       &riboflavin, e);
    if (rc == REFRACT_E_OK && !mie_preset_milk_riboflavin(fat, protein, riboflavin, m))
        rc = err_set(e, REFRACT_E_INTERNAL, "%s: the milk preset refused fat %g%%, protein %g%%",
                     path, fat, protein);
    return rc;
}

/* One layer per channel: a constant, or the region's shape holding the value inside (0
 * until the caller writes the medium's value into layers[0].inside). */
static enum refract_code set_field(const cJSON *region, const char *path,
                                   const struct scene_parse_ctx *ctx, struct scene_field *f,
                                   struct err *e)
{
    f->layers = calloc(1, sizeof *f->layers);
    if (f->layers == NULL)
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "%s: out of memory", path);
    f->count = 1;
    if (region == NULL) {
        f->layers[0].kind = SCENE_LAYER_CONSTANT;
        return REFRACT_E_OK;
    }
    char p[256];
    f->layers[0].kind = SCENE_LAYER_SHAPE;
    return scene_parse_region(region, jr_path(p, sizeof p, path, "region"), ctx,
                              &f->layers[0].shape, e);
}

enum refract_code scene_parse_particles(const cJSON *obj, const char *path,
                                        const struct scene_parse_ctx *ctx, struct scene_object *o,
                                        struct err *e)
{
    static const char *const owned[] = {"attenuation", "scattering", "anisotropy"};
    const cJSON *item = member(obj, "particles");
    if (item == NULL)
        return REFRACT_E_OK;
    char p[256];
    jr_path(p, sizeof p, path, "particles");
    for (int i = 0; i < 3; i++) {
        if (member(obj, owned[i]) != NULL)
            return err_set(e, REFRACT_E_INVALID_FIELD,
                           "%s: sets attenuation, scattering and anisotropy, so %s.%s would "
                           "describe the same medium twice; remove one of them",
                           p, path, owned[i]);
    }
    if (!cJSON_IsObject(item)) {
        char got[80];
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "%s: expected an object (a \"preset\" or \"populations\"), got %s", p,
                       jr_describe(item, got, sizeof got));
    }
    struct mie_medium m;
    enum refract_code rc = parse_medium(item, p, &m, e);
    double units = 1.0;
    if (rc == REFRACT_E_OK)
        rc = jr_number_gt(item, p, "units_per_meter", false, 1.0, 0.0, 1e9, &units, e);
    if (rc != REFRACT_E_OK)
        return rc;
    /* The region first: a typo in it should not wait for the Mie sums. */
    static const enum scene_channel channels[] = {SCENE_CH_ATTENUATION, SCENE_CH_SCATTERING,
                                                  SCENE_CH_ANISOTROPY};
    const cJSON *region = member(item, "region");
    for (int i = 0; i < 3 && rc == REFRACT_E_OK; i++)
        rc = set_field(region, p, ctx, &o->fields[channels[i]], e);
    if (rc != REFRACT_E_OK)
        return rc;
    double work = mie_medium_work(&m);
    if (work > MIE_MAX_WORK)
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "%s: these particles need about %.3g Lorenz-Mie terms, above the limit "
                       "of %.3g (about a second of the upload); use smaller radii (r_max_um, "
                       "radius_um) or fewer populations",
                       p, work, MIE_MAX_WORK);
    struct mie_spectrum s;
    if (!mie_medium_spectrum(&m, &s))
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "%s: a particle is out of Lorenz-Mie range (size parameter above %g or "
                       "a host too absorbing at the particle's size); use smaller particles",
                       p, MIE_MAX_SIZE_PARAMETER);
    struct mie_rgb rgb;
    mie_spectrum_to_rgb(&s, &rgb);
    double *att = o->fields[SCENE_CH_ATTENUATION].layers[0].inside;
    double *sca = o->fields[SCENE_CH_SCATTERING].layers[0].inside;
    for (int c = 0; c < 3; c++) {
        att[c] = rgb.sigma_a[c] / units;
        sca[c] = rgb.sigma_s[c] / units;
    }
    o->fields[SCENE_CH_ANISOTROPY].layers[0].inside[0] = fmax(-0.99, fmin(0.99, rgb.g_scene));
    double biggest = fmax(fmax(fmax(att[0], att[1]), fmax(att[2], sca[0])), fmax(sca[1], sca[2]));
    if (biggest > 1e5)
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "%s: gives %.6g per world unit, above the fields' 1e5; world units are "
                       "metres unless \"units_per_meter\" says otherwise (100 for centimetres)",
                       p, biggest);
    return rc;
}
