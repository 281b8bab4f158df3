/*
 * test_mesh_ply.c - the PLY reader: a generated icosphere survives the round trip exactly
 * in ascii, binary little-endian and binary big-endian (with properties and lists the
 * reader must skip), and every malformed or lying file gets its own precise message.
 */
#include "mesh_test_util.h"
#include "test.h"

static void icosphere_round_trips_through_each_ply_encoding(void)
{
    struct test_mesh tm = test_icosphere(3, 0.75);
    for (int kind = TEST_PLY_ASCII; kind <= TEST_PLY_BE; kind++) {
        struct test_buf b = test_write_ply(&tm, (enum test_ply_kind)kind);
        CHECK_INT(mesh_sniff(b.p, b.len), MESH_FORMAT_PLY);
        struct mesh *m = NULL;
        struct err e = {0};
        CHECK_INT(mesh_parse(b.p, b.len, MESH_FORMAT_UNKNOWN, NULL, &m, &e), REFRACT_E_OK);
        if (m == NULL) {
            fprintf(stderr, "ply kind %d: %s\n", kind, e.msg);
        } else {
            CHECK_INT(m->vertex_count, tm.nv);
            CHECK_INT(m->triangle_count, tm.nt);
            CHECK(memcmp(m->vertices, tm.v, tm.nv * sizeof *tm.v) == 0);
            CHECK(memcmp(m->triangles, tm.t, tm.nt * sizeof *tm.t) == 0);
        }
        mesh_destroy(m);
        free(b.p);
    }
    test_mesh_free(&tm);
}

static void float_vertices_and_int_counts_read_too(void)
{
    /* float32 coordinates, an int-counted uint index list, a quad, and a skipped element. */
    struct test_buf b = {0};
    buf_printf(&b, "ply\r\nformat binary_little_endian 1.0\r\nelement vertex 4\r\n"
                   "property float x\r\nproperty float y\r\nproperty float z\r\n"
                   "element face 1\r\nproperty list int uint vertex_index\r\n"
                   "element edge 1\r\nproperty int vertex1\r\nproperty int vertex2\r\n"
                   "end_header\r\n");
    const float v[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    for (int i = 0; i < 4; i++)
        for (int k = 0; k < 3; k++)
            put_scalar(&b, &v[i][k], 4, false);
    const uint32_t face[5] = {4, 0, 1, 2, 3};
    for (int i = 0; i < 5; i++)
        put_scalar(&b, &face[i], 4, false);
    const int32_t edge[2] = {0, 1};
    put_scalar(&b, &edge[0], 4, false);
    put_scalar(&b, &edge[1], 4, false);
    struct mesh *m = NULL;
    struct err e = {0};
    CHECK_INT(mesh_parse_ply(b.p, b.len, NULL, &m, &e), REFRACT_E_OK);
    if (m != NULL) {
        CHECK_INT(m->triangle_count, 2);
        CHECK_INT(m->triangles[1][2], 3);
        CHECK_NEAR(m->vertices[2][1], 1.0, 0.0);
    }
    mesh_destroy(m);
    free(b.p);
}

#define HDR_ASCII "ply\nformat ascii 1.0\n"
#define VTX3 "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
#define FACE1 "element face 1\nproperty list uchar int vertex_indices\n"
#define TRI_VERTS "0 0 0\n1 0 0\n0 1 0\n"

struct bad_case {
    const char *text;
    size_t max_triangles;
    enum refract_code code;
    const char *msg;
};

static void each_malformed_ascii_ply_gets_its_precise_message(void)
{
    static const struct bad_case cases[] = {
        {"ply\n", 0, REFRACT_E_INVALID_MESH,
         "the header has no \"end_header\" line (after 1 lines); the file is truncated or not "
         "PLY"},
        {"ply\nelement vertex 3\nend_header\n", 0, REFRACT_E_INVALID_MESH,
         "the header has no \"format\" line; add \"format ascii 1.0\" (or binary_little_endian "
         "/ binary_big_endian) after \"ply\""},
        {"ply\nformat ascii 2.0\n", 0, REFRACT_E_INVALID_MESH,
         "header line 2: expected \"format ascii|binary_little_endian|binary_big_endian 1.0\""},
        {"ply\nformat utf8 1.0\n", 0, REFRACT_E_INVALID_MESH,
         "header line 2: unknown format \"utf8\"; use ascii, binary_little_endian or "
         "binary_big_endian"},
        {HDR_ASCII "element vertex -3\n", 0, REFRACT_E_INVALID_MESH,
         "header line 3: element count \"-3\" is not a non-negative integer"},
        {HDR_ASCII "property float x\n", 0, REFRACT_E_INVALID_MESH,
         "header line 3: a property before any element; write \"element NAME COUNT\" first"},
        {HDR_ASCII "element vertex 3\nproperty real x\n", 0, REFRACT_E_INVALID_MESH,
         "header line 4: unknown type \"real\"; PLY types are char uchar short ushort int uint "
         "float double (or int8 ... float64)"},
        {HDR_ASCII VTX3 "element face 1\nproperty list float int vertex_indices\n", 0,
         REFRACT_E_INVALID_MESH,
         "header line 8: list count type \"float\" must be an integer type (uchar, int, ...)"},
        {HDR_ASCII VTX3 "element face 1\nproperty list uchar float vertex_indices\n", 0,
         REFRACT_E_INVALID_MESH,
         "header line 8: face indices of type \"float\" must be an integer type (int or uint)"},
        {HDR_ASCII VTX3 "texture none\n", 0, REFRACT_E_INVALID_MESH,
         "header line 7: unknown keyword \"texture\"; a PLY header has format, element, "
         "property, comment, obj_info and end_header"},
        {HDR_ASCII FACE1 "end_header\n3 0 1 2\n", 0, REFRACT_E_INVALID_MESH,
         "the header declares no \"vertex\" element; a mesh PLY needs \"element vertex N\" "
         "with properties x, y, z"},
        {HDR_ASCII "element vertex 3\nproperty float x\nproperty float y\n" FACE1 "end_header\n", 0,
         REFRACT_E_INVALID_MESH,
         "the \"vertex\" element has no property z; declare \"property float z\""},
        {HDR_ASCII VTX3 "end_header\n" TRI_VERTS, 0, REFRACT_E_INVALID_MESH,
         "the header declares no \"face\" element; a mesh needs at least one face (\"element "
         "face N\", N >= 1)"},
        {HDR_ASCII VTX3
         "element face 0\nproperty list uchar int vertex_indices\nend_header\n" TRI_VERTS,
         0, REFRACT_E_INVALID_MESH,
         "the header declares 0 faces; a mesh needs at least one face (\"element face N\", N "
         ">= 1)"},
        {HDR_ASCII VTX3 "element face 1\nproperty list uchar int corners\nend_header\n", 0,
         REFRACT_E_INVALID_MESH,
         "the \"face\" element has no list property vertex_indices; declare \"property list "
         "uchar int vertex_indices\""},
        {HDR_ASCII VTX3 "element face 2\nproperty list uchar int vertex_indices\nend_header\n", 1,
         REFRACT_E_LIMIT_EXCEEDED,
         "the header declares 2 faces, more than the limit max_mesh_triangles = 1; simplify the "
         "mesh or start refractd with --max-mesh-triangles to raise it"},
        {HDR_ASCII VTX3 FACE1 "end_header\n" TRI_VERTS "3 0 1 3\n", 0, REFRACT_E_INVALID_MESH,
         "face 0: vertex index 3 is out of range; the header declares 3 vertices (indices "
         "0..2)"},
        {HDR_ASCII VTX3 FACE1 "end_header\n" TRI_VERTS "3 0 -1 2\n", 0, REFRACT_E_INVALID_MESH,
         "face 0: vertex index -1 is out of range; the header declares 3 vertices (indices "
         "0..2)"},
        {HDR_ASCII VTX3 FACE1 "end_header\n" TRI_VERTS "2 0 1\n", 0, REFRACT_E_INVALID_MESH,
         "face 0 has 2 vertices; a face needs at least 3"},
        /* an ascii count beyond its type and the file (found by tests/fuzz/fuzz_ply.c: the
         * conversion to the loop's bound overflowed) */
        {HDR_ASCII VTX3 FACE1 "end_header\n" TRI_VERTS "3e40 0 1 2\n", 0, REFRACT_E_INVALID_MESH,
         "face 0 has 3e+40 vertices, more than the 29 bytes after the header can hold; the "
         "face's vertex count is wrong"},
        /* the same for a list that is not the faces' indices (skipped, but its count is
         * still the loop's bound; found by the fuzz run in CI) */
        {HDR_ASCII VTX3 FACE1 "element edge 1\nproperty list uchar int vertex_pair\n"
                              "end_header\n" TRI_VERTS "3 0 1 2\n3e40 0 2\n",
         0, REFRACT_E_INVALID_MESH,
         "edge 0: a list count of 3e+40 is more than the bytes after the header can hold; the "
         "list's count is wrong"},
        {HDR_ASCII VTX3 FACE1 "element edge 1\nproperty list uchar int vertex_pair\n"
                              "end_header\n" TRI_VERTS "3 0 1 2\n-2 0 2\n",
         0, REFRACT_E_INVALID_MESH,
         "edge 0: a list count of -2 is negative; the list's count is wrong"},
        {HDR_ASCII VTX3 FACE1 "end_header\n0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n", 0,
         REFRACT_E_INVALID_MESH,
         "vertex 1: coordinate y is nan, not a finite number; every coordinate must be finite"},
        {HDR_ASCII VTX3 FACE1 "end_header\n0 0 0\n1 0\n0 1 0\n3 0 1 2\n", 0, REFRACT_E_INVALID_MESH,
         "line 11 (vertex 1 of 3): fewer values than declared; each record is one line of its "
         "properties' values, as the header declares them"},
        {HDR_ASCII VTX3 FACE1 "end_header\n0 0 0\n1 0 0 9\n0 1 0\n3 0 1 2\n", 0,
         REFRACT_E_INVALID_MESH,
         "line 11 (vertex 1 of 3): more values than the element's properties declare; each "
         "record is one line of its properties' values, as the header declares them"},
        {HDR_ASCII VTX3 FACE1 "end_header\n0 0 0\n1 0 x\n0 1 0\n3 0 1 2\n", 0,
         REFRACT_E_INVALID_MESH,
         "line 11 (vertex 1 of 3): a value is not a number; each record is one line of its "
         "properties' values, as the header declares them"},
        {HDR_ASCII VTX3 FACE1 "end_header\n" TRI_VERTS "3 0 1 2\n3 0 1 2\n", 0,
         REFRACT_E_INVALID_MESH,
         "line 14: data after the last element the header declares; the header's element "
         "counts are wrong"},
        {HDR_ASCII VTX3 FACE1 "end_header\n" TRI_VERTS "3 0 1\n", 0, REFRACT_E_INVALID_MESH,
         "line 13 (face 0 of 1): fewer vertex indices than the face's count; each record is one "
         "line of its properties' values, as the header declares them"},
        {HDR_ASCII
         "element vertex 3000\nproperty float x\nproperty float y\nproperty float z\n" FACE1
         "end_header\n" TRI_VERTS "3 0 1 2\n",
         0, REFRACT_E_INVALID_MESH,
         "the header declares 3000 \"vertex\" records of at least 6 bytes each, but only 26 "
         "bytes follow; the header's counts are wrong or the file is truncated"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        struct err e = {0};
        const char *msg = test_mesh_error(cases[i].text, strlen(cases[i].text), MESH_FORMAT_PLY,
                                          cases[i].max_triangles, cases[i].code, &e);
        CHECK_MSG(strcmp(msg, cases[i].msg) == 0, "case %zu: got \"%s\"", i, msg);
    }
}

/* A binary file of the icosphere cut or padded: every lie about its length is named. */
static void truncated_and_padded_binary_files_are_named(void)
{
    struct test_mesh tm = test_icosphere(1, 1.0); /* 42 vertices, 80 faces */
    struct test_buf b = test_write_ply(&tm, TEST_PLY_LE);
    size_t header = (size_t)(strstr(b.p, "end_header\n") + 11 - b.p);
    struct err e = {0};
    /* Cut inside the faces: the face it ended in is named. Each face is 1 + 12 + 1 + 4. */
    size_t cut = header + 42 * 28 + 10 * 18 + 5;
    CHECK_STR(test_mesh_error(b.p, cut, MESH_FORMAT_PLY, 0, REFRACT_E_INVALID_MESH, &e),
              "face 10 of 80: the file ends at byte 1361 of the body; it is truncated or its "
              "header's element counts are wrong");
    /* Cut so much that the faces' minimum size no longer fits: caught before reading. */
    CHECK_STR(test_mesh_error(b.p, header + 42 * 28 + 100, MESH_FORMAT_PLY, 0,
                              REFRACT_E_INVALID_MESH, &e),
              "the header declares 80 \"face\" records of at least 2 bytes each, but only 100 "
              "bytes follow; the header's counts are wrong or the file is truncated");
    /* Padding after the last face. */
    buf_put(&b, "\0\0\0", 3);
    CHECK_STR(test_mesh_error(b.p, b.len, MESH_FORMAT_PLY, 0, REFRACT_E_INVALID_MESH, &e),
              "3 bytes follow the last element the header declares; the header's element counts "
              "are wrong (or the file has trailing data)");
    /* A header claiming 4 billion vertices is refused without allocating them. */
    struct test_buf lie = {0};
    buf_printf(&lie, "ply\nformat binary_big_endian 1.0\nelement vertex 4000000000\nproperty "
                     "double x\nproperty double y\nproperty double z\n" FACE1 "end_header\n");
    buf_put(&lie, b.p + header, 64);
    CHECK_STR(test_mesh_error(lie.p, lie.len, MESH_FORMAT_PLY, 0, REFRACT_E_INVALID_MESH, &e),
              "the header declares 4000000000 \"vertex\" records of at least 24 bytes each, but "
              "only 64 bytes follow; the header's counts are wrong or the file is truncated");
    free(lie.p);
    free(b.p);
    test_mesh_free(&tm);
}

int main(void)
{
    icosphere_round_trips_through_each_ply_encoding();
    float_vertices_and_int_counts_read_too();
    each_malformed_ascii_ply_gets_its_precise_message();
    truncated_and_padded_binary_files_are_named();
    return test_summary("mesh_ply");
}
