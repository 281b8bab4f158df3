/*
 * exr_mem.h - an OpenEXR file held in memory as the source of a read context (OpenEXR's
 * C API): the reader is pread over the buffer, and the library's first error message
 * becomes the struct err. Shared by exr_read.c (irradiance EXRs) and volume_exr.c.
 * Thread: any; one source per context.
 */
#ifndef REFRACT_IO_EXR_MEM_H
#define REFRACT_IO_EXR_MEM_H

#include <openexr.h>
#include <stdbool.h>
#include <stddef.h>

#include "../core/err.h"

struct exr_mem_src {
    const unsigned char *bytes;
    size_t len;
    struct err *e;
    bool have_error;             /* e holds the first error; later ones are dropped */
    enum refract_code bad_input; /* the code of an error the library reports */
};

/* Points init's read, size and error handler functions and user data at src. */
void exr_mem_src_attach(exr_context_initializer_t *init, struct exr_mem_src *src);

#endif
