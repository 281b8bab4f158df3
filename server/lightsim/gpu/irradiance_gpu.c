/*
 * irradiance_gpu.c - an irradiance volume as two 3D textures the view renderer samples
 * with hardware trilinear filtering. See lightsim_gpu.h.
 */
#include "lightsim_gpu.h"

#include <string.h>

enum refract_code irradiance_gpu_create(const struct light_grid *g, struct irradiance_gpu *out,
                                        struct err *e)
{
    memset(out, 0, sizeof *out);
    const int *d = g->dims;
    struct gpu_volume_desc irr = {.label = "irradiance volume",
                                  .width = d[0],
                                  .height = d[1],
                                  .depth = d[2],
                                  .format = GPU_TEXEL_RGBA32F};
    struct gpu_volume_desc dir = irr;
    dir.label = "light direction volume";
    dir.format = GPU_TEXEL_RGBA16F;
    enum refract_code rc = gpu_volume_create(&irr, &out->irradiance, e);
    if (rc == REFRACT_E_OK)
        rc = gpu_volume_create(&dir, &out->direction, e);
    if (rc != REFRACT_E_OK) {
        irradiance_gpu_free(out);
        return rc;
    }
    out->grid = *g;
    out->bytes = out->irradiance.bytes + out->direction.bytes;
    return REFRACT_E_OK;
}

enum refract_code irradiance_gpu_upload(const struct irradiance_volume *v,
                                        struct irradiance_gpu *out, struct err *e)
{
    const int *d = v->grid.dims;
    enum refract_code rc = irradiance_gpu_create(&v->grid, out, e);
    if (rc == REFRACT_E_OK)
        rc = gpu_volume_upload(&out->irradiance, 0, 0, 0, d[0], d[1], d[2], 4, v->irradiance, e);
    if (rc == REFRACT_E_OK)
        rc = gpu_volume_upload(&out->direction, 0, 0, 0, d[0], d[1], d[2], 4, v->direction, e);
    if (rc != REFRACT_E_OK)
        irradiance_gpu_free(out);
    return rc;
}

void irradiance_gpu_free(struct irradiance_gpu *g)
{
    if (g == NULL)
        return;
    gpu_volume_destroy(&g->irradiance);
    gpu_volume_destroy(&g->direction);
    g->bytes = 0;
}
