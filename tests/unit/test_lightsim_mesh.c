/*
 * test_lightsim_mesh.c - triangle-mesh surfaces in the CPU reference light simulator
 * (docs/lightsim.md "Surfaces"):
 *   - a ball lens made of an icosphere mesh (mesh_make_icosphere, 5 subdivisions: 20,480
 *     triangles, smooth shading normals), R = 0.5, n = 1.5, stopped down as in
 *     test_lightsim_surfaces.c: the axis maximum lies at the paraxial focus
 *     n R / (2 (n - 1)) from the centre within 1 % of R, with the same measurement
 *     (test_lightsim_axis.h); the bookkeeping identity holds;
 *   - the fields own a copy of the mesh: the run after the upload is destroyed reads no
 *     freed memory (the sanitizer build would say so), and gives the same statistics;
 *   - the light domain covers the mesh's box, which only the upload knows;
 *   - a receiver and scattering objects now parse with a mesh surface; a missing mesh,
 *     an open mesh and a receiver above the mesh's bottom get their errors when the fields
 *     are built.
 */
#include "core/fresnel.h"
#include "mesh/mesh.h"
#include "mesh/mesh_rt.h"
#include "test_lightsim_axis.h"
#include "test_lightsim_fixture.h"

static struct scene_volume ico_volume;
static struct scene_volume open_volume;

static const struct scene_volume *lookup(void *ctx, const char *name)
{
    (void)ctx;
    if (strcmp(name, SCENE_MESH_LOOKUP_PREFIX "ico") == 0)
        return &ico_volume;
    if (strcmp(name, SCENE_MESH_LOOKUP_PREFIX "open") == 0)
        return &open_volume;
    return NULL;
}

static struct mesh *icosphere(int subdivisions)
{
    struct err e = {0};
    struct mesh *m = NULL;
    if (mesh_make_icosphere(subdivisions, 1.0, &m, &e) != REFRACT_E_OK) {
        fprintf(stderr, "icosphere: %s\n", e.msg);
        test_setup_failed("test_lightsim_mesh", "mesh_make_icosphere failed");
    }
    return m;
}

/* The ball lens of an icosphere of radius R (the unit mesh scaled by R). */
static void test_ball_lens_mesh(double n, int resolution, int patches)
{
    const double R = 0.5, a = 0.06;
    double f_eff = n * R / (2.0 * (n - 1.0)), floor_y = -f_eff - 0.12;
    char ball[160], json[2048];
    snprintf(ball, sizeof ball,
             "\"shape\": \"mesh\", \"mesh\": \"ico\", \"center\": [0, 0, 0], \"scale\": %g", R);
    ball_lens_json_shape(json, sizeof json, ball, R, n, a);
    struct scene *s = fx_scene(json);
    struct scene_lightsim set = fx_settings(resolution, patches);
    struct scene_light l = fx_directional((vec3){0, -1, 0});
    struct lightsim_fields f;
    struct irradiance_volume v;
    double t0 = fx_seconds();
    fx_run_lookup(s, lookup, NULL, &l, &set, &f, &v);
    double secs = fx_seconds() - t0;
    fx_print_stats("mesh ball", &v.stats);
    double E_max;
    double y = axis_focus(&v, -R - 0.02, floor_y + 0.02, 0.06, &E_max);
    printf("mesh ball n %.2f: resolution %d (voxel %.4f), N0 %d: axis maximum E %.2f at %.4f "
           "below the centre, f = %.4f: error %.2f %% of R (%.2f voxels); %.1f s\n",
           n, resolution, v.grid.voxel, patches, E_max, -y, f_eff, 100.0 * (-y - f_eff) / R,
           (-y - f_eff) / v.grid.voxel, secs);
    CHECK_NEAR(-y, f_eff, 0.01 * R);
    CHECK(E_max > 3.0); /* a focus, not the plain beam's E = 1 */
    CHECK(v.stats.flux_absorbed[0] > 0.5 * v.stats.flux_in[0]);
    double imb = lightsim_stats_imbalance(&v.stats);
    printf("mesh ball: bookkeeping imbalance %.2e\n", imb);
    CHECK(imb <= 1e-9);
    CHECK(v.stats.done && v.stats.patches_live == 0);
    /* the mesh surface's events happened: power was reflected at the ball */
    CHECK(v.stats.flux_reflected[0] > 0.0 || v.stats.flux_culled[0] > 0.0);
    irradiance_volume_free(&v);
    lightsim_fields_free(&f);
    scene_destroy(s);
}

/* The fields own their mesh: destroying the upload between the build and the run. */
static void test_owned_copy(void)
{
    const char *json = "{\"surfaces\": [{\"shape\": \"mesh\", \"mesh\": \"ico\", "
                       "\"center\": [0.1, 0, 0], \"scale\": 0.4, \"medium\": {\"ior\": 1.5}}],"
                       " \"receiver\": {\"height\": -0.8, \"half_size\": 0.6}}";
    struct scene *s = fx_scene(json);
    struct scene_lightsim set = fx_settings(24, 16);
    set.max_level = 2; /* a short run: what matters is that it reads the copy */
    set.energy_threshold = 1e-3;
    struct scene_light l = fx_directional((vec3){0.2, -1, 0});
    struct lightsim_fields f1, f2;
    struct irradiance_volume v1, v2;
    fx_run_lookup(s, lookup, NULL, &l, &set, &f1, &v1);

    struct mesh *temp = icosphere(5); /* the same mesh as ico, made again */
    struct scene_volume saved = ico_volume;
    ico_volume = (struct scene_volume){.mesh = temp};
    struct err e = {0};
    s->lightsim = set;
    CHECK_INT(lightsim_fields_build(s, lookup, NULL, &f2, &e), REFRACT_E_OK);
    mesh_destroy(temp); /* the upload goes; the fields keep their copy */
    ico_volume = saved;
    CHECK_INT(f2.mesh_count, 1);
    CHECK_INT(lightsim_ref_run(&f2, &l, &set, &v2, &e), REFRACT_E_OK);
    /* the same mesh both times: the same run */
    printf("owned copy: patch steps %lld and %lld, out %.9g and %.9g\n", v1.stats.patch_steps,
           v2.stats.patch_steps, v1.stats.flux_out[0], v2.stats.flux_out[0]);
    CHECK(v1.stats.patch_steps == v2.stats.patch_steps);
    CHECK_NEAR(v1.stats.flux_out[0], v2.stats.flux_out[0], 1e-12);
    CHECK(lightsim_stats_imbalance(&v2.stats) <= 1e-9);

    /* the domain: the mesh's world box, x from 0.1 - 0.4 to 0.1 + 0.4 */
    struct light_grid g;
    lightsim_domain_lookup(s, lookup, NULL, &g);
    printf("domain with the mesh: bmin (%.4f, %.4f, %.4f) dims %d x %d x %d voxel %.4f\n", g.bmin.x,
           g.bmin.y, g.bmin.z, g.dims[0], g.dims[1], g.dims[2], g.voxel);
    CHECK_NEAR(g.bmin.y, -0.8 - 2.0 * g.voxel, 1e-12); /* 2 voxels below the receiver */
    CHECK(g.bmin.y + g.dims[1] * g.voxel >= 0.4);      /* the mesh's top */
    CHECK(g.bmin.x + g.dims[0] * g.voxel >= 0.5);      /* its +x side */
    struct light_grid blind;
    lightsim_domain(s, &blind); /* without the upload: the receiver alone */
    CHECK(blind.bmin.y + blind.dims[1] * blind.voxel < 0.4);
    irradiance_volume_free(&v1);
    irradiance_volume_free(&v2);
    lightsim_fields_free(&f1);
    lightsim_fields_free(&f2);
    scene_destroy(s);
}

/* What was refused at parse time is accepted; what only the upload can tell is refused
 * when the fields are built. */
static void test_errors(void)
{
    static const char *scattering =
        "{\"objects\": [{\"bounds\": {\"min\": [1, -1, -0.5], \"max\": [2, 0, 0.5]}, "
        "\"resolution\": 8, \"scattering\": 0.5}],"
        " \"surfaces\": [{\"shape\": \"mesh\", \"mesh\": \"ico\", \"center\": [0, 0, 0], "
        "\"scale\": 0.5, \"medium\": {\"ior\": 1.5}}], \"receiver\": {\"height\": -1, "
        "\"half_size\": 3}}";
    struct scene *s = NULL;
    struct err e = {0};
    CHECK_INT(scene_parse(scattering, strlen(scattering), NULL, &s, &e), REFRACT_E_OK);
    if (s == NULL)
        fprintf(stderr, "parse: %s\n", e.msg);
    scene_destroy(s);

    struct lightsim_fields f;
    struct {
        const char *json;
        enum refract_code code;
        const char *words[3];
    } cases[] = {
        {"{\"surfaces\": [{\"shape\": \"mesh\", \"mesh\": \"gem\", \"medium\": {\"ior\": 1.5}}],"
         " \"receiver\": {\"height\": -2, \"half_size\": 1}}",
         REFRACT_E_CONFLICT,
         {"surfaces[0]", "\"gem\"", "was not uploaded"}},
        {"{\"surfaces\": [{\"shape\": \"mesh\", \"mesh\": \"open\", \"medium\": {\"ior\": 1.5}}],"
         " \"receiver\": {\"height\": -2, \"half_size\": 1}}",
         REFRACT_E_INVALID_MESH,
         {"surfaces[0]", "\"open\"", "cannot bound a medium"}},
        {"{\"surfaces\": [{\"shape\": \"mesh\", \"mesh\": \"ico\", \"scale\": 0.5, "
         "\"medium\": {\"ior\": 1.5}}], \"receiver\": {\"height\": -0.25, \"half_size\": 1}}",
         REFRACT_E_INVALID_FIELD,
         {"receiver.height", "surfaces[0]", "y = -0.5"}},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        s = fx_scene(cases[i].json);
        s->lightsim = fx_settings(16, 8);
        e = (struct err){0};
        CHECK_INT(lightsim_fields_build(s, lookup, NULL, &f, &e), cases[i].code);
        printf("case %zu: %s\n", i, e.msg);
        for (int w = 0; w < 3; w++)
            CHECK(strstr(e.msg, cases[i].words[w]) != NULL);
        CHECK(f.surfaces == NULL && f.meshes == NULL && f.ior_grad == NULL);
        scene_destroy(s);
    }
}

int main(void)
{
    struct mesh *ico = icosphere(5);
    CHECK_INT((int)ico->triangle_count, 20480);
    CHECK(ico->solid);
    ico_volume = (struct scene_volume){.mesh = ico};
    /* an open mesh: one triangle */
    double(*v)[3] = malloc(3 * sizeof *v);
    uint32_t(*t)[3] = malloc(sizeof *t);
    const double tri[3][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    memcpy(v, tri, sizeof tri);
    t[0][0] = 0;
    t[0][1] = 1;
    t[0][2] = 2;
    struct mesh *open = NULL;
    struct err e = {0};
    CHECK_INT(mesh_create(v, 3, t, 1, NULL, &open, &e), REFRACT_E_OK);
    open_volume = (struct scene_volume){.mesh = open};

    test_errors();
    test_owned_copy();
    /* The lens runs the mesh code test_owned_copy ran, longer (5 s here); the sanitizer
     * build leaves it out. */
    if (!test_sanitized())
        test_ball_lens_mesh(1.5, 128, 192);
    mesh_destroy(open);
    mesh_destroy(ico);
    return test_summary("test_lightsim_mesh");
}
