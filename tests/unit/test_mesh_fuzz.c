/*
 * test_mesh_fuzz.c - hostile bytes never crash the mesh readers: every prefix of valid
 * OBJ and PLY files (ascii, binary of both byte orders), thousands of randomly mutated
 * copies, and random bytes behind a valid-looking PLY header each either parse into a
 * mesh whose indices are all in range or fail with invalid_mesh / limit_exceeded and a
 * message. Run under ASan+UBSan (build-asan) this also proves no out-of-bounds read.
 * Deterministic: a fixed-seed xorshift generator.
 */
#include "mesh_test_util.h"
#include "test.h"

static uint64_t rng_state = 0x9e3779b97f4a7c15ull;

static uint64_t rng(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return rng_state;
}

static int outcomes[3]; /* ok, invalid_mesh, limit_exceeded */

/* Parses a private copy (so a read past len is a heap overflow ASan sees). */
static void parse_one(const char *bytes, size_t len, enum mesh_format f)
{
    char *copy = malloc(len ? len : 1);
    memcpy(copy, bytes, len);
    struct mesh_limits lim = {.max_triangles = 5000};
    struct mesh *m = NULL;
    struct err e = {0};
    enum refract_code rc = mesh_parse(copy, len, f, &lim, &m, &e);
    if (rc == REFRACT_E_OK) {
        outcomes[0]++;
        bool in_range = m != NULL && m->triangle_count > 0;
        for (size_t t = 0; in_range && t < m->triangle_count; t++)
            for (int c = 0; c < 3; c++)
                in_range = in_range && m->triangles[t][c] < m->vertex_count;
        CHECK(in_range);
        mesh_destroy(m);
    } else {
        outcomes[rc == REFRACT_E_LIMIT_EXCEEDED ? 2 : 1]++;
        CHECK_MSG((rc == REFRACT_E_INVALID_MESH || rc == REFRACT_E_LIMIT_EXCEEDED) &&
                      e.msg[0] != '\0' && m == NULL,
                  "code %d, message \"%s\"", rc, e.msg);
    }
    free(copy);
}

static void every_prefix_of_valid_files_is_handled(const struct test_buf *files, int n)
{
    for (int i = 0; i < n; i++)
        for (size_t len = 0; len <= files[i].len; len++)
            parse_one(files[i].p, len, MESH_FORMAT_UNKNOWN);
}

static void mutated_files_are_handled(const struct test_buf *files, int n)
{
    static const char interesting[] = {'\0', '\n', ' ', '-', '9', '/', 'e', '.', (char)0xff};
    for (int iter = 0; iter < 3000; iter++) {
        const struct test_buf *src = &files[iter % n];
        char *copy = malloc(src->len);
        memcpy(copy, src->p, src->len);
        int flips = 1 + (int)(rng() % 8);
        for (int k = 0; k < flips; k++) {
            size_t at = (size_t)(rng() % src->len);
            copy[at] = (rng() & 1) ? (char)rng() : interesting[rng() % sizeof interesting];
        }
        size_t len = (rng() % 4 == 0) ? (size_t)(rng() % src->len) : src->len;
        parse_one(copy, len, (enum mesh_format)(rng() % 3));
        free(copy);
    }
}

static void random_bodies_behind_a_header_are_handled(void)
{
    /* One header per element, each spanning lines: parenthesised, so the concatenation
     * reads (to people and clang's -Wstring-concatenation) as meant, not a lost comma. */
    static const char *const headers[] = {
        ("ply\nformat binary_little_endian 1.0\nelement vertex 20\nproperty float x\nproperty "
         "float y\nproperty float z\nelement face 30\nproperty list uchar int "
         "vertex_indices\nend_header\n"),
        ("ply\nformat binary_big_endian 1.0\nelement vertex 10\nproperty double x\nproperty "
         "double y\nproperty double z\nelement face 10\nproperty list int uint "
         "vertex_indices\nend_header\n"),
        ("ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\nproperty "
         "float z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n"),
    };
    char buf[2048];
    for (int iter = 0; iter < 3000; iter++) {
        const char *h = headers[iter % 3];
        size_t hl = strlen(h), body = (size_t)(rng() % (sizeof buf - hl));
        memcpy(buf, h, hl);
        for (size_t i = 0; i < body; i++) {
            uint64_t r = rng();
            /* Mostly small bytes, so list counts and indices are often plausible. */
            buf[hl + i] = iter % 3 == 2 ? " 0123456789.-\n"[r % 14] : (char)((r & 3) ? r % 16 : r);
        }
        parse_one(buf, hl + body, MESH_FORMAT_UNKNOWN);
    }
}

int main(void)
{
    struct test_mesh tm = test_icosphere(1, 1.0);
    struct test_buf files[4] = {test_write_obj(&tm), test_write_ply(&tm, TEST_PLY_ASCII),
                                test_write_ply(&tm, TEST_PLY_LE), test_write_ply(&tm, TEST_PLY_BE)};
    every_prefix_of_valid_files_is_handled(files, 4);
    mutated_files_are_handled(files, 4);
    random_bodies_behind_a_header_are_handled();
    fprintf(stderr, "outcomes: %d parsed, %d invalid_mesh, %d limit_exceeded\n", outcomes[0],
            outcomes[1], outcomes[2]);
    /* The corpus reaches both outcomes, so the test exercises the readers' paths. */
    CHECK(outcomes[0] > 0 && outcomes[1] > 0);
    for (int i = 0; i < 4; i++)
        free(files[i].p);
    test_mesh_free(&tm);
    return test_summary("mesh_fuzz");
}
