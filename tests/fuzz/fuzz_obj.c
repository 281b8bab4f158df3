/*
 * fuzz_obj.c - libFuzzer harness of the Wavefront OBJ reader (server/mesh/mesh_obj.c), the
 * body of POST /v1/scenes/{id}/meshes?format=obj. docs/fuzzing.md.
 */
#include "fuzz_mesh.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_mesh_one(mesh_parse_obj, data, size);
    return 0;
}
