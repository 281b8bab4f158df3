/*
 * test_lightsim_gpu_mesh.c - the GPU light simulator among triangle-mesh surfaces
 * (docs/lightsim.md "Surfaces"), on llvmpipe in CI, against its CPU double twin
 * (lightsim_ref_run) with the bounds test_lightsim_gpu_surfaces.c uses for the analytic
 * kinds (flux terms 1e-3 of flux_in, patch-steps 1e-2, irradiance relative L1 3e-3,
 * direction mean 1 - cos 3e-3; bookkeeping to float rounding):
 *   - an absorbing glass ball made of an icosphere mesh (mesh_make_icosphere, 4
 *     subdivisions, 5,120 triangles, smooth shading normals) over a receiver, lit by a
 *     tilted directional light: the GPU traverses the mesh's BVH from the packed buffer
 *     (shaders/geom/mesh.glsl, MESH_RT_PACKED) and counts crossings for the inside sets
 *     of split corners;
 *   - the same mesh placed by its shape (scale, rotation) and the surface's transform
 *     (turned, scaled, moved), next to a second mesh (an icosahedron) of another index and
 *     a higher nesting priority, under a point light: two meshes' offsets in the packed
 *     buffer, and the transforms.
 * Coarse grids (16 voxels; N0 8 and 4; max_level 4) keep it to seconds on llvmpipe. The
 * ball lens's focus through a mesh is test_lightsim_mesh.c's (CPU); this twin comparison
 * carries it over to the GPU.
 */
#include "mesh/mesh.h"
#include "mesh/mesh_rt.h"
#include "scene/scene.h"
#include "test_lightsim_gpu_support.h"

static struct scene_volume ico_volume, cube_volume;

static const struct scene_volume *lookup(void *ctx, const char *name)
{
    (void)ctx;
    if (strcmp(name, SCENE_MESH_LOOKUP_PREFIX "ico") == 0)
        return &ico_volume;
    if (strcmp(name, SCENE_MESH_LOOKUP_PREFIX "cube") == 0)
        return &cube_volume;
    return NULL;
}

static struct scene *parse(const char *json)
{
    struct scene *s = NULL;
    struct err e = {0};
    if (scene_parse(json, strlen(json), NULL, &s, &e) != REFRACT_E_OK) {
        fprintf(stderr, "scene: %s\n", e.msg);
        test_setup_failed("test_lightsim_gpu_mesh", "a scene did not parse");
    }
    return s;
}

static void print_stats(const char *what, const struct lightsim_stats *a)
{
    printf("%s: in %.6g out %.6g refl %.6g abs %.6g culled %.6g live %.6g | steps %lld "
           "patch_steps %lld splits %lld peak %d\n",
           what, a->flux_in[0], a->flux_out[0], a->flux_reflected[0], a->flux_absorbed[0],
           a->flux_culled[0], a->flux_live[0], a->steps, a->patch_steps, a->splits,
           a->patches_peak);
}

struct compare_case {
    const char *name;
    const char *json;
    struct scene_light light;
    int resolution, initial_patches, max_level;
};

static void compare(struct gpu *gpu, const struct compare_case *c)
{
    struct scene *s = parse(c->json);
    struct err e = {0};
    s->lightsim = test_lightsim_settings(c->initial_patches);
    s->lightsim.resolution = c->resolution;
    s->lightsim.energy_threshold = 1e-4;
    s->lightsim.max_level = c->max_level;
    struct lightsim_fields f;
    CHECK_INT(lightsim_fields_build(s, lookup, NULL, &f, &e), REFRACT_E_OK);
    if (f.surfaces == NULL) {
        fprintf(stderr, "fields: %s\n", e.msg);
        scene_destroy(s);
        return;
    }
    CHECK(f.mesh_count >= 1);
    double t0 = gpu_time_ms();
    struct irradiance_volume ref;
    CHECK_INT(lightsim_ref_run(&f, &c->light, &s->lightsim, &ref, &e), REFRACT_E_OK);
    double cpu_ms = gpu_time_ms() - t0;
    struct test_gpu_run t = {.fields = &f, .light = c->light, .set = s->lightsim, .chunk = 32};
    CHECK_INT(test_gpu_simulate(gpu, &t), REFRACT_E_OK);
    if (t.out.irradiance == NULL || ref.irradiance == NULL)
        return;
    const struct lightsim_stats *a = &t.out.stats, *b = &ref.stats;
    printf("%s (%dx%dx%d, N0 %d): CPU %.0f ms, GPU %.0f ms\n", c->name, f.grid.dims[0],
           f.grid.dims[1], f.grid.dims[2], c->initial_patches, cpu_ms, t.ms);
    print_stats("  GPU", a);
    print_stats("  CPU", b);
    CHECK_INT(a->patches_initial, b->patches_initial);
    CHECK(a->done && b->done);
    double dps = fabs((double)a->patch_steps - (double)b->patch_steps) / (double)b->patch_steps;
    printf("  patch_steps differ by %.2e\n", dps);
    CHECK(dps <= 1e-2);
    for (int ch = 0; ch < 3; ch++) {
        double in = b->flux_in[ch];
        double d[4] = {fabs(a->flux_out[ch] - b->flux_out[ch]) / in,
                       fabs(a->flux_reflected[ch] - b->flux_reflected[ch]) / in,
                       fabs(a->flux_absorbed[ch] - b->flux_absorbed[ch]) / in,
                       fabs(a->flux_culled[ch] - b->flux_culled[ch]) / in};
        double worst = fmax(fmax(d[0], d[1]), fmax(d[2], d[3]));
        printf("  ch %d: out %.6f/%.6f refl %.6f/%.6f abs %.6f/%.6f culled %.6f/%.6f -> max "
               "diff %.2e of flux_in; residual GPU %.1e CPU %.1e\n",
               ch, a->flux_out[ch], b->flux_out[ch], a->flux_reflected[ch], b->flux_reflected[ch],
               a->flux_absorbed[ch], b->flux_absorbed[ch], a->flux_culled[ch], b->flux_culled[ch],
               worst, test_bookkeeping_residual(a, ch), test_bookkeeping_residual(b, ch));
        CHECK(fabs(a->flux_in[ch] - in) / in < 1e-6);
        CHECK(worst < 1e-3);
        CHECK(test_bookkeeping_residual(a, ch) < 1e-5);
        CHECK(test_bookkeeping_residual(b, ch) < 1e-12);
    }
    size_t n = (size_t)f.grid.dims[0] * f.grid.dims[1] * f.grid.dims[2];
    double l1 = 0, norm = 0, max_e = 0, dir_sum = 0;
    int lit_both = 0, lit_either = 0;
    for (size_t v = 0; v < n; v++) {
        for (int ch = 0; ch < 3; ch++) {
            double g = t.out.irradiance[4 * v + ch], r = ref.irradiance[4 * v + ch];
            l1 += fabs(g - r);
            norm += fabs(r);
            max_e = fmax(max_e, fabs(r));
        }
        bool lg = t.out.direction[4 * v + 3] == 1.0f, lr = ref.direction[4 * v + 3] == 1.0f;
        lit_either += lg || lr;
        if (lg && lr) {
            lit_both++;
            double dot = 0, lg2 = 0, lr2 = 0;
            for (int k = 0; k < 3; k++) {
                double dg = t.out.direction[4 * v + k], dr = ref.direction[4 * v + k];
                dot += dg * dr;
                lg2 += dg * dg;
                lr2 += dr * dr;
            }
            dir_sum += 1 - dot / sqrt(lg2 * lr2);
        }
    }
    printf("  irradiance: relative L1 %.2e, max E %.3g; lit %d both / %d either, direction "
           "1 - cos mean %.2e\n",
           l1 / norm, max_e, lit_both, lit_either, lit_both ? dir_sum / lit_both : 0);
    CHECK(max_e > 1.5); /* the ball focuses: a caustic, not the plain beam's E = 1 */
    CHECK(l1 / norm < 3e-3);
    CHECK(lit_both >= 0.99 * lit_either);
    CHECK(lit_both == 0 || dir_sum / lit_both < 3e-3);
    irradiance_volume_free(&t.out);
    irradiance_volume_free(&ref);
    lightsim_fields_free(&f);
    scene_destroy(s);
}

static const char *const ball_json =
    "{\"surfaces\": [{\"shape\": \"mesh\", \"mesh\": \"ico\", \"center\": [0, 0, 0],"
    " \"scale\": 0.6, \"medium\": {\"ior\": 1.5, \"attenuation\": [0.2, 0.5, 1.0]}}],"
    " \"receiver\": {\"height\": -0.8, \"half_size\": 0.8}}";

static const char *const mixed_json =
    "{\"surfaces\": [{\"shape\": \"mesh\", \"mesh\": \"ico\", \"center\": [0, 0, 0],"
    " \"scale\": 0.5, \"rotate\": {\"axis\": [1, 1, 0], \"angle_deg\": 20},"
    " \"transform\": {\"translate\": [-0.1, 0, 0], \"scale\": 1.1, \"rotate\": "
    "{\"axis\": [0, 0, 1], \"angle_deg\": 40}}, \"medium\": {\"ior\": 1.5}},"
    " {\"shape\": \"mesh\", \"mesh\": \"cube\", \"center\": [0.75, -0.3, 0], \"scale\": 0.25,"
    " \"priority\": 5, \"medium\": {\"ior\": 1.4}}]}";

int main(void)
{
    struct gpu *gpu = test_start_gpu("test_lightsim_gpu_mesh");
    printf("GL_RENDERER: %s\n", gpu_info(gpu)->renderer);
    struct err e = {0};
    struct mesh *ico = NULL, *cube = NULL;
    CHECK_INT(mesh_make_icosphere(4, 1.0, &ico, &e), REFRACT_E_OK);
    CHECK_INT(mesh_make_icosphere(0, 1.0, &cube, &e), REFRACT_E_OK); /* an icosahedron */
    if (ico == NULL || cube == NULL)
        return test_summary("test_lightsim_gpu_mesh");
    ico_volume = (struct scene_volume){.mesh = ico};
    cube_volume = (struct scene_volume){.mesh = cube};
    const struct compare_case cases[] = {
        {"glass icosphere mesh, directional", ball_json, test_directional(0.1, -1, 0.05), 16, 8,
         4},
        {"two meshes, point light", mixed_json, test_point(0.3, 0.9, 0.2), 16, 4, 4},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++)
        compare(gpu, &cases[i]);
    mesh_destroy(ico);
    mesh_destroy(cube);
    gpu_destroy(gpu, NULL);
    return test_summary("test_lightsim_gpu_mesh");
}
