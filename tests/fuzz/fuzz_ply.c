/*
 * fuzz_ply.c - libFuzzer harness of the PLY reader (server/mesh/mesh_ply.c: ascii and
 * binary of both byte orders), the body of POST /v1/scenes/{id}/meshes?format=ply.
 * docs/fuzzing.md.
 */
#include "fuzz_mesh.h"

/* mesh_parse_ply takes const void *: adapted to the shared reader type. */
static enum refract_code read_ply(const char *bytes, size_t len, const struct mesh_limits *limits,
                                  struct mesh **out, struct err *e)
{
    return mesh_parse_ply(bytes, len, limits, out, e);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_mesh_one(read_ply, data, size);
    return 0;
}
