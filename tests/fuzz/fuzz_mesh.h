/*
 * fuzz_mesh.h - what fuzz_obj.c and fuzz_ply.c share: one mesh reader called on a private
 * copy of the bytes, and the checks every outcome must pass.
 */
#ifndef REFRACT_FUZZ_MESH_H
#define REFRACT_FUZZ_MESH_H

#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "mesh/mesh.h"

typedef enum refract_code (*fuzz_mesh_reader)(const char *bytes, size_t len,
                                              const struct mesh_limits *limits, struct mesh **out,
                                              struct err *e);

static inline void fuzz_mesh_one(fuzz_mesh_reader read, const uint8_t *data, size_t size)
{
    /* A private copy without terminator: a read past len is a heap overflow ASan sees. */
    char *copy = malloc(size ? size : 1);
    if (copy == NULL)
        return;
    memcpy(copy, data, size);
    /* 5000 triangles (refractd: 2M) keep the BVH and solidity checks fast per input;
     * the limit's own check still runs. */
    struct mesh_limits lim = {.max_triangles = 5000};
    struct mesh *m = NULL;
    struct err e = {0};
    enum refract_code rc = read(copy, size, &lim, &m, &e);
    if (rc == REFRACT_E_OK) {
        if (m == NULL || m->triangle_count == 0 || m->triangle_count > lim.max_triangles)
            abort();
        for (size_t t = 0; t < m->triangle_count; t++)
            for (int k = 0; k < 3; k++)
                if (m->triangles[t][k] >= m->vertex_count)
                    abort(); /* an index out of range would be read by the BVH */
        mesh_destroy(m);
    } else if (m != NULL || e.msg[0] == '\0') {
        abort();
    }
    free(copy);
}

#endif
