/*
 * test_mesh_obj.c - the OBJ reader: a generated icosphere survives the round trip
 * exactly, polygons fan into triangles, negative indices count back, and every malformed
 * file gets its own precise message (line number, what was wrong, what to do).
 */
#include "mesh_test_util.h"
#include "test.h"

static void icosphere_round_trips_through_obj(void)
{
    struct test_mesh tm = test_icosphere(3, 1.5);
    struct test_buf b = test_write_obj(&tm);
    CHECK_INT(mesh_sniff(b.p, b.len), MESH_FORMAT_OBJ);
    struct mesh *m = NULL;
    struct err e = {0};
    CHECK_INT(mesh_parse(b.p, b.len, MESH_FORMAT_UNKNOWN, NULL, &m, &e), REFRACT_E_OK);
    if (m != NULL) {
        CHECK_INT(m->vertex_count, tm.nv);
        CHECK_INT(m->triangle_count, tm.nt);
        CHECK(memcmp(m->vertices, tm.v, tm.nv * sizeof *tm.v) == 0);
        CHECK(memcmp(m->triangles, tm.t, tm.nt * sizeof *tm.t) == 0);
        CHECK_NEAR(m->hi.x, 1.5, 1e-12);
        CHECK_NEAR(m->lo.y, -1.5, 1e-12);
    }
    mesh_destroy(m);
    free(b.p);
    test_mesh_free(&tm);
}

static void polygons_fan_and_negative_indices_count_back(void)
{
    const char *obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0.5 1 \t# apex\n"
                      "f 1 2 3 4\nf -5 -4 -1\r\n";
    struct mesh *m = NULL;
    struct err e = {0};
    CHECK_INT(mesh_parse_obj(obj, strlen(obj), NULL, &m, &e), REFRACT_E_OK);
    if (m != NULL) {
        CHECK_INT(m->triangle_count, 3);
        const uint32_t want[3][3] = {{0, 1, 2}, {0, 2, 3}, {0, 1, 4}};
        CHECK(memcmp(m->triangles, want, sizeof want) == 0);
    }
    mesh_destroy(m);
}

struct bad_case {
    const char *text;
    size_t max_triangles;
    enum refract_code code;
    const char *msg;
};

static void each_malformed_obj_gets_its_precise_message(void)
{
    static const struct bad_case cases[] = {
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\n", 0, REFRACT_E_INVALID_MESH,
         "the OBJ file has 3 vertices and no faces; add \"f i j k\" lines (a mesh needs at "
         "least one triangle)"},
        {"", 0, REFRACT_E_INVALID_MESH,
         "the OBJ file has 0 vertices and no faces; add \"f i j k\" lines (a mesh needs at "
         "least one triangle)"},
        {"v 0 0 0\nv 1 0\n", 0, REFRACT_E_INVALID_MESH,
         "line 2: a vertex needs 3 coordinates \"v x y z\", got 2"},
        {"v 0 0 0\nv 1 nan 0\n", 0, REFRACT_E_INVALID_MESH,
         "line 2: vertex coordinate y is \"nan\", not a finite number; every coordinate must be "
         "finite"},
        {"v 0 0 inf\n", 0, REFRACT_E_INVALID_MESH,
         "line 1: vertex coordinate z is \"inf\", not a finite number; every coordinate must be "
         "finite"},
        {"v 0 0 1e999\n", 0, REFRACT_E_INVALID_MESH,
         "line 1: vertex coordinate z is \"1e999\", not a finite number; every coordinate must "
         "be finite"},
        {"v 0 0 zero\n", 0, REFRACT_E_INVALID_MESH,
         "line 1: vertex value 3 \"zero\" is not a number; write \"v x y z\" with decimal "
         "numbers"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", 0, REFRACT_E_INVALID_MESH,
         "line 4: face vertex 3 refers to vertex 4, but only 3 vertices are defined before this "
         "line; indices must be 1..3 or -1..-3"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n", 0, REFRACT_E_INVALID_MESH,
         "line 4: face vertex 3 refers to vertex -4, but only 3 vertices are defined before "
         "this line; indices must be 1..3 or -1..-3"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", 0, REFRACT_E_INVALID_MESH,
         "line 4: face vertex 1 has index 0; OBJ indices start at 1 (or count back from -1)"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n", 0, REFRACT_E_INVALID_MESH,
         "line 4: a face needs at least 3 vertices, got 2"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x/1\n", 0, REFRACT_E_INVALID_MESH,
         "line 4: face vertex 3 \"x\" is not an integer index"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 /1/1\n", 0, REFRACT_E_INVALID_MESH,
         "line 4: face vertex 3 \"/1/1\" is not a vertex index; write \"f i j k\" with 1-based "
         "(or negative) indices, optionally i/t/n"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999999999999\n", 0, REFRACT_E_INVALID_MESH,
         "line 4: face vertex 3 \"99999999999999999999\" is not an integer index"},
        {"v 0 0 0\ncurv 0 1 2\n", 0, REFRACT_E_INVALID_MESH,
         "line 2: unknown statement \"curv\"; a mesh OBJ holds v and f (vt, vn, vp, o, g, s, "
         "usemtl, mtllib, l, p and # comments are ignored)"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3 4\n", 1, REFRACT_E_LIMIT_EXCEEDED,
         "line 5: the mesh has more than 1 triangles (after splitting polygons into "
         "triangles), the limit max_mesh_triangles; simplify the mesh or start refractd with "
         "--max-mesh-triangles to raise it"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        struct err e = {0};
        const char *msg = test_mesh_error(cases[i].text, strlen(cases[i].text), MESH_FORMAT_OBJ,
                                          cases[i].max_triangles, cases[i].code, &e);
        CHECK_STR(msg, cases[i].msg);
    }
    /* A NUL byte: binary data sent as OBJ. */
    const char nul[] = "v 0 0 0\nv 1\0 0 0\n";
    struct err e = {0};
    CHECK_STR(test_mesh_error(nul, sizeof nul - 1, MESH_FORMAT_OBJ, 0, REFRACT_E_INVALID_MESH, &e),
              "line 2: the file contains a NUL byte (binary data?); an OBJ file is text: send "
              "binary meshes as PLY");
}

static void unknown_formats_are_refused_with_a_hint(void)
{
    const char *junk = "hello world\n";
    CHECK_INT(mesh_sniff(junk, strlen(junk)), MESH_FORMAT_UNKNOWN);
    struct err e = {0};
    CHECK_STR(
        test_mesh_error(junk, strlen(junk), MESH_FORMAT_UNKNOWN, 0, REFRACT_E_INVALID_MESH, &e),
        "the file is neither PLY (it would start with the line \"ply\") nor OBJ (its first "
        "statement would be v, vt, vn, f, o, g, ...); send an OBJ or PLY file, or name the "
        "format with ?format=obj|ply");
    CHECK_INT(mesh_sniff("# c\n\nv 1 2 3\n", 12), MESH_FORMAT_OBJ);
    CHECK_INT(mesh_sniff("ply\r\nformat", 11), MESH_FORMAT_PLY);
}

int main(void)
{
    icosphere_round_trips_through_obj();
    polygons_fan_and_negative_indices_count_back();
    each_malformed_obj_gets_its_precise_message();
    unknown_formats_are_refused_with_a_hint();
    return test_summary("mesh_obj");
}
