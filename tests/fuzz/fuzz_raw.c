/*
 * fuzz_raw.c - libFuzzer harness of the raw volume reader (server/io/volume_raw.c and the
 * sample converters of volume_sink.c), the body of PUT /v1/scenes/{id}/volumes/{name}
 * ?format=raw. docs/fuzzing.md.
 *
 * Input layout: 4 bytes of query, then the file. Byte 0: sample type (low 2 bits: the
 * four that io_sample_type_parse accepts for raw), components (bit 3: 3, else 1; bit 4:
 * absent), scale and offset other than 1 and 0 (bit 5); bytes 1..3: dims x, y, z
 * (0..255; 0 and > 64 exercise the refusals).
 */
#include "fuzz_volume.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 4)
        return 0;
    struct io_volume_desc d = fuzz_volume_desc(IO_VOLUME_RAW);
    d.type = (enum io_sample_type)(data[0] & 3);
    d.components = (data[0] & 16) ? 0 : (data[0] & 8) ? 3 : 1;
    if (data[0] & 32) {
        d.scale = -0.5;
        d.offset = 1.25;
    }
    for (int a = 0; a < 3; a++)
        d.dims[a] = data[1 + a];
    fuzz_volume_one(volume_decode_raw, &d, data + 4, size - 4);
    return 0;
}
