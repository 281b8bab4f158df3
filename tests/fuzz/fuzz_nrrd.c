/*
 * fuzz_nrrd.c - libFuzzer harness of the NRRD volume reader (server/io/volume_nrrd.c:
 * header fields, raw and gzip data), the body of PUT /v1/scenes/{id}/volumes/{name}
 * ?format=nrrd with dims and components from the file. docs/fuzzing.md.
 */
#include "fuzz_volume.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    struct io_volume_desc d = fuzz_volume_desc(IO_VOLUME_NRRD);
    fuzz_volume_one(volume_decode_nrrd, &d, data, size);
    return 0;
}
