/*
 * fuzz_exr.c - libFuzzer harness of the OpenEXR volume reader (server/io/volume_exr.c and
 * the in-memory stream of exr_mem.c, over OpenEXR's C API), the body of
 * PUT /v1/scenes/{id}/volumes/{name}?format=exr. docs/fuzzing.md.
 *
 * Input layout: 4 bytes of query, then the file. Byte 0: components (0 from the file, 1,
 * 3, or 2 which the reader refuses: low 2 bits); byte 0 bit 2 set: dims from bytes 1..3
 * (a single-part slice atlas needs them), else dims from the file.
 */
#include "fuzz_volume.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 4)
        return 0;
    struct io_volume_desc d = fuzz_volume_desc(IO_VOLUME_EXR);
    d.components = data[0] & 3;
    if (data[0] & 4)
        for (int a = 0; a < 3; a++)
            d.dims[a] = data[1 + a];
    fuzz_volume_one(volume_decode_exr, &d, data + 4, size - 4);
    return 0;
}
