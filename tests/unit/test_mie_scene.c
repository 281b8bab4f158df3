/*
 * test_mie_scene.c - an object's "particles" (docs/media.md): the parser turns a medium
 * description into attenuation, scattering and anisotropy fields equal to what the Mie
 * code computes for it, inside its region and 0 outside, and refuses bad or ambiguous
 * descriptions with 400-class errors that name the JSON path.
 */
#include <math.h>

#include "../../server/core/mie/mie.h"
#include "scene_test_util.h"

#define MILK "\"preset\": \"milk\", \"fat_percent\": 3.5, \"protein_percent\": 3.2"

static void expected_milk(double units, double att[3], double sca[3], double *g)
{
    struct mie_medium m;
    struct mie_spectrum s;
    struct mie_rgb c;
    CHECK(mie_preset_milk(3.5, 3.2, &m));
    CHECK(mie_medium_spectrum(&m, &s));
    mie_spectrum_to_rgb(&s, &c);
    for (int k = 0; k < 3; k++) {
        att[k] = c.sigma_a[k] / units;
        sca[k] = c.sigma_s[k] / units;
    }
    *g = c.g_scene;
}

static bool near_rel(double got, double want)
{
    return fabs(got - want) <= 1e-6 * fabs(want) + 1e-12;
}

/* Milk in a sphere region, centimetre world units: the centre voxel holds the medium,
 * a corner voxel (outside the sphere) holds 0. */
static void test_milk_region(void)
{
    struct scene *s = parse_ok(OBJ("\"resolution\": 8, \"ior\": 1.35, \"particles\": {" MILK
                                   ", \"units_per_meter\": 100, \"region\": {\"shape\": "
                                   "\"sphere\", \"radius\": 0.8}}"));
    if (s == NULL)
        return;
    double att[3], sca[3], g;
    expected_milk(100.0, att, sca, &g);
    const struct scene_object *o = &s->objects[0];
    float *a = eval(s, SCENE_CH_ATTENUATION, NULL, NULL);
    float *sc = eval(s, SCENE_CH_SCATTERING, NULL, NULL);
    float *an = eval(s, SCENE_CH_ANISOTROPY, NULL, NULL);
    size_t mid = voxel_index(o, 4, 4, 4), corner = voxel_index(o, 0, 0, 0);
    for (int k = 0; k < 3; k++) {
        CHECK_MSG(near_rel(a[4 * mid + k], att[k]), "attenuation[%d] %g, want %g", k,
                  a[4 * mid + k], att[k]);
        CHECK_MSG(near_rel(sc[4 * mid + k], sca[k]), "scattering[%d] %g, want %g", k,
                  sc[4 * mid + k], sca[k]);
        CHECK_NEAR(a[4 * corner + k], 0.0, 0.0);
        CHECK_NEAR(sc[4 * corner + k], 0.0, 0.0);
    }
    CHECK_NEAR(an[mid], g, 1e-6);
    CHECK_NEAR(an[corner], 0.0, 0.0);
    /* Whole milk per centimetre: hundreds, bluer than red (sigma_s B > R). */
    CHECK(sc[4 * mid] > 100.0 && sc[4 * mid + 2] > sc[4 * mid]);
    free(a);
    free(sc);
    free(an);
    scene_destroy(s);
}

/* Explicit populations without a region fill the bounds; water preset gives no
 * scattering. */
static void test_explicit_and_water(void)
{
    struct scene *s = parse_ok(
        OBJ("\"resolution\": 4, \"particles\": {\"host\": 1.33, \"populations\": [{\"ior\": [1.5, "
            "0.001], \"volume_fraction\": 1e-4, \"radius_um\": 0.5}, {\"ior\": 1.6, "
            "\"number_density\": 1e12, \"lognormal\": {\"r_vs_um\": 1, \"c_s_um\": 0.3, "
            "\"r_min_um\": 0.1, \"r_max_um\": 4}}]}"));
    if (s != NULL) {
        float *sc = eval(s, SCENE_CH_SCATTERING, NULL, NULL);
        const struct scene_object *o = &s->objects[0];
        CHECK(sc[0] > 0.0f);
        CHECK_NEAR(sc[4 * voxel_index(o, 3, 2, 1)], sc[0], 0.0);
        free(sc);
        scene_destroy(s);
    }
    /* docs/media.md's turbid water: a power law of mineral particles. */
    s = parse_ok(OBJ("\"resolution\": 4, \"particles\": {\"host\": \"water\", \"populations\": "
                     "[{\"ior\": [1.58, 0.001], \"volume_fraction\": 2e-6, \"power_law\": "
                     "{\"exponent\": 4, \"r_min_um\": 0.1, \"r_max_um\": 20}}]}"));
    if (s != NULL) {
        float *sc = eval(s, SCENE_CH_SCATTERING, NULL, NULL);
        CHECK_MSG(sc[0] > 0.01f && sc[0] < 100.0f, "turbid water sigma_s %g per m", sc[0]);
        free(sc);
        scene_destroy(s);
    }
    s = parse_ok(OBJ("\"resolution\": 4, \"particles\": {\"preset\": \"water\"}"));
    if (s != NULL) {
        float *a = eval(s, SCENE_CH_ATTENUATION, NULL, NULL);
        float *sc = eval(s, SCENE_CH_SCATTERING, NULL, NULL);
        /* Per metre; water's steep red absorption leaves the sRGB map's blue at or near 0
         * (docs/media.md, "Spectrum to RGB"). */
        CHECK_MSG(a[0] > 0.1f && a[0] > a[1] && a[1] >= a[2] && a[2] >= 0.0f,
                  "water attenuation %g %g %g", a[0], a[1], a[2]);
        CHECK_NEAR(sc[0], 0.0, 0.0);
        free(a);
        free(sc);
        scene_destroy(s);
    }
}

static void test_bad_input(void)
{
    static const struct bad_case cases[] = {
        {OBJ("\"particles\": {" MILK "}, \"scattering\": 1"), REFRACT_E_INVALID_FIELD,
         "objects[0].particles: sets attenuation, scattering and anisotropy",
         "objects[0].scattering"},
        {OBJ("\"particles\": {\"preset\": \"beer\"}"), REFRACT_E_INVALID_FIELD,
         "objects[0].particles.preset", "milk"},
        {OBJ("\"particles\": {\"preset\": \"milk\", \"fat_percent\": 50}"), REFRACT_E_INVALID_FIELD,
         "objects[0].particles.fat_percent", NULL},
        {OBJ("\"particles\": {" MILK ", \"riboflavin_mg_per_100g\": -0.1}"),
         REFRACT_E_INVALID_FIELD, "objects[0].particles.riboflavin_mg_per_100g", NULL},
        {OBJ("\"particles\": {\"preset\": \"milk\"}"), REFRACT_E_MISSING_FIELD,
         "objects[0].particles: missing required field \"fat_percent\"", NULL},
        {OBJ("\"particles\": {\"preset\": \"water\", \"fat_percent\": 1}"), REFRACT_E_UNKNOWN_FIELD,
         "objects[0].particles: unknown field \"fat_percent\"", NULL},
        {OBJ("\"particles\": {\"preset\": \"milk\", \"fat_percent\": 1, \"populations\": []}"),
         REFRACT_E_UNKNOWN_FIELD, "objects[0].particles: unknown field \"populations\"", NULL},
        {OBJ("\"particles\": {\"host\": 1.33}"), REFRACT_E_MISSING_FIELD,
         "objects[0].particles: missing required field \"populations\"", NULL},
        {OBJ("\"particles\": {\"host\": \"oil\", \"populations\": []}"), REFRACT_E_INVALID_FIELD,
         "objects[0].particles.host", "\"water\""},
        {OBJ("\"particles\": {\"populations\": [{\"ior\": 1.5, \"volume_fraction\": 0.1, "
             "\"radius_um\": 1, \"lognormal\": {}}]}"),
         REFRACT_E_INVALID_FIELD,
         "objects[0].particles.populations[0]: has both \"radius_um\" "
         "and \"lognormal\"",
         NULL},
        {OBJ("\"particles\": {\"populations\": [{\"ior\": 1.5, \"radius_um\": 1}]}"),
         REFRACT_E_MISSING_FIELD, "objects[0].particles.populations[0]: needs one of",
         "\"volume_fraction\" or \"number_density\""},
        {OBJ("\"particles\": {\"populations\": [{\"ior\": [1.5, -1], \"volume_fraction\": 0.1, "
             "\"radius_um\": 1}]}"),
         REFRACT_E_INVALID_FIELD, "objects[0].particles.populations[0].ior[1]", NULL},
        {OBJ("\"particles\": {\"populations\": [{\"ior\": 1.5, \"volume_fraction\": 0.1, "
             "\"lognormal\": {\"r_vs_um\": 5, \"c_s_um\": 1, \"r_min_um\": 0.1, \"r_max_um\": "
             "2}}]}"),
         REFRACT_E_INVALID_FIELD, "objects[0].particles.populations[0].lognormal.r_vs_um", NULL},
        {OBJ("\"particles\": {\"preset\": \"milk\", \"fat_percent\": 40}"), REFRACT_E_INVALID_FIELD,
         "objects[0].particles: gives", "units_per_meter"},
        {OBJ("\"particles\": {" MILK ", \"units_per_meter\": 0}"), REFRACT_E_INVALID_FIELD,
         "objects[0].particles.units_per_meter", NULL},
        {OBJ("\"particles\": {" MILK ", \"region\": {\"shape\": \"blob\"}}"),
         REFRACT_E_INVALID_FIELD, "objects[0].particles.region.shape", NULL},
        {OBJ("\"particles\": {" MILK ", \"region\": {\"shape\": \"sphere\", \"inside\": 1}}"),
         REFRACT_E_UNKNOWN_FIELD, "objects[0].particles.region: unknown field \"inside\"", NULL},
        {OBJ("\"particles\": {\"populations\": [{\"ior\": 1.5, \"volume_fraction\": 1e-6, "
             "\"lognormal\": {\"r_vs_um\": 100, \"c_s_um\": 50, \"r_min_um\": 1, "
             "\"r_max_um\": 1000}}]}"),
         REFRACT_E_INVALID_FIELD, "objects[0].particles: these particles need about",
         "use smaller radii"},
        {OBJ("\"particles\": [1]"), REFRACT_E_INVALID_FIELD,
         "objects[0].particles: expected "
         "an object",
         NULL},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++)
        check_bad(&cases[i], NULL);
}

int main(void)
{
    test_milk_region();
    test_explicit_and_water();
    test_bad_input();
    return test_summary("mie_scene");
}
