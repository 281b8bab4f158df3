/*
 * test_scene_mesh.c - mesh shapes in scenes: {"shape": "mesh", "mesh": NAME, "center",
 * "scale", "rotate"} parses with precise errors; a scene's ior and attenuation from an
 * uploaded icosphere match the same scene with the procedural sphere to within 0.05 of
 * the channel's step at every voxel (the boundary within 1/20 voxel); a missing mesh is a
 * CONFLICT naming the path and the upload to make, and is listed by scene_missing_meshes;
 * the second channel copies the mesh's remembered voxelization instead of computing it;
 * the transport hash sees the mesh's name and placement.
 */
#include "mesh_test_util.h"
#include "scene_test_util.h"

struct uploads {
    struct scene_volume sphere; /* .mesh set */
};

static const struct scene_volume *lookup(void *ctx, const char *name)
{
    struct uploads *u = ctx;
    return strcmp(name, "mesh:ball") == 0 ? &u->sphere : NULL;
}

/* One object whose ior and attenuation are the shape with geometry keys `geom`. */
#define MESH_OBJ(res, geom)                                                                        \
    "{\"objects\": [{" BOUNDS ", \"resolution\": [" res "], \"ior\": [1.0, {" geom                 \
    ", \"inside\": 1.5}], \"attenuation\": [{" geom ", \"inside\": [1, 2, 3]}]}]}"

static void mesh_shapes_parse_with_precise_errors(void)
{
    struct scene *s = parse_ok(OBJ("\"ior\": [1.0, {\"shape\": \"mesh\", \"mesh\": \"ball\", "
                                   "\"center\": [0.1, 0, 0], \"scale\": 2, \"rotate\": "
                                   "{\"axis\": [0, 0, 1], \"angle_deg\": 90}, \"inside\": 1.5}]"));
    if (s != NULL) {
        const struct scene_shape *sh = &s->objects[0].fields[SCENE_CH_IOR].layers[1].shape;
        CHECK_INT(sh->kind, SCENE_SHAPE_MESH);
        CHECK_STR(sh->mesh, "ball");
        vec3 p = xform_point_to_world(&sh->object_from_mesh, vec3_make(1, 0, 0));
        CHECK_NEAR(p.x, 0.1, 1e-12);
        CHECK_NEAR(p.y, 2.0, 1e-12);
        scene_destroy(s);
    }
    static const struct bad_case cases[] = {
        {OBJ("\"ior\": [1.0, {\"shape\": \"mesh\", \"inside\": 1.5}]"), REFRACT_E_MISSING_FIELD,
         "objects[0].ior[1]: missing required field \"mesh\" (the name given to POST "
         "/v1/scenes/{id}/meshes?name=NAME)",
         NULL},
        {OBJ("\"ior\": [1.0, {\"shape\": \"mesh\", \"mesh\": \"a/b\", \"inside\": 1.5}]"),
         REFRACT_E_INVALID_FIELD,
         "objects[0].ior[1].mesh: expected a mesh name of 1..63 characters from A-Z a-z 0-9 _ "
         "-, got",
         NULL},
        {OBJ("\"ior\": [1.0, {\"shape\": \"mesh\", \"mesh\": \"b\", \"scale\": 0, \"inside\": "
             "1.5}]"),
         REFRACT_E_INVALID_FIELD, "objects[0].ior[1].scale", NULL},
        {OBJ("\"ior\": [1.0, {\"shape\": \"mesh\", \"mesh\": \"b\", \"radius\": 1, \"inside\": "
             "1.5}]"),
         REFRACT_E_UNKNOWN_FIELD, "objects[0].ior[1]", "rotate"},
        {OBJ("\"ior\": [1.0, {\"shape\": \"mesh\", \"mesh\": \"b\", \"rotate\": {\"angle_deg\": "
             "5}, \"inside\": 1.5}]"),
         REFRACT_E_MISSING_FIELD, "objects[0].ior[1].rotate", "axis"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++)
        check_bad(&cases[i], NULL);
}

static void mesh_sphere_fields_match_the_procedural_sphere(void)
{
    struct test_mesh tm = test_icosphere(5, 1.0);
    struct uploads u = {.sphere = {.mesh = test_mesh_make(&tm)}};
    /* The unit mesh sphere scaled to 0.55 and moved, against the sphere shape there. */
    struct scene *sm = parse_ok(MESH_OBJ("40, 40, 40", "\"shape\": \"mesh\", \"mesh\": "
                                                       "\"ball\", \"center\": [0.1, -0.05, 0.2], "
                                                       "\"scale\": 0.55"));
    struct scene *ss = parse_ok(MESH_OBJ("40, 40, 40", "\"shape\": \"sphere\", \"center\": "
                                                       "[0.1, -0.05, 0.2], \"radius\": 0.55"));
    if (sm != NULL && ss != NULL) {
        size_t n = voxels(&sm->objects[0]);
        float *a = eval(sm, SCENE_CH_IOR, lookup, &u), *b = eval(ss, SCENE_CH_IOR, NULL, NULL);
        double worst = 0.0;
        for (size_t i = 0; i < n; i++)
            worst = fmax(worst, fabs(a[i] - b[i]) / 0.5); /* the step is 1.5 - 1.0 */
        CHECK_NEAR(worst, 0.0, 0.05);
        free(a);
        free(b);
        a = eval(sm, SCENE_CH_ATTENUATION, lookup, &u);
        b = eval(ss, SCENE_CH_ATTENUATION, NULL, NULL);
        worst = 0.0;
        for (size_t i = 0; i < 4 * n; i++)
            worst = fmax(worst, fabs(a[i] - b[i]) / 3.0);
        CHECK_NEAR(worst, 0.0, 0.05);
        free(a);
        free(b);
        /* Both channels use the same grid and placement: voxelized once, copied once. */
        long long hits = 0, computed = 0;
        mesh_memo_counts(u.sphere.mesh, &hits, &computed);
        CHECK_INT(computed, 1);
        CHECK_INT(hits, 1);
        char buf[64];
        CHECK_INT(scene_missing_meshes(sm, lookup, &u, buf, sizeof buf), 0);
        CHECK(scene_transport_hash(sm) != scene_transport_hash(ss));
    }
    scene_destroy(sm);
    scene_destroy(ss);
    mesh_destroy((struct mesh *)u.sphere.mesh);
    test_mesh_free(&tm);
}

static void missing_meshes_are_conflicts_and_listed(void)
{
    struct scene *s = parse_ok(MESH_OBJ("8, 8, 8", "\"shape\": \"mesh\", \"mesh\": \"cup\""));
    if (s == NULL)
        return;
    float out[8 * 8 * 8];
    struct err e = {0};
    CHECK_INT(
        scene_field_eval(s, &s->objects[0], SCENE_CH_IOR, lookup, &(struct uploads){0}, out, &e),
        REFRACT_E_CONFLICT);
    CHECK_STR(e.msg, "objects[0].ior[1]: mesh \"cup\" has not been uploaded; upload it with POST "
                     "/v1/scenes/{id}/meshes?name=cup before rendering");
    char buf[64];
    CHECK_INT(scene_missing_meshes(s, NULL, NULL, buf, sizeof buf), 1);
    CHECK_STR(buf, "cup");
    scene_destroy(s);
}

int main(void)
{
    mesh_shapes_parse_with_precise_errors();
    mesh_sphere_fields_match_the_procedural_sphere();
    missing_meshes_are_conflicts_and_listed();
    return test_summary("scene_mesh");
}
