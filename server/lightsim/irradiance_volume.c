/*
 * irradiance_volume.c - the host-side irradiance volume: freeing and sizing. See lightsim.h.
 */
#include <stdlib.h>

#include "lightsim.h"

void irradiance_volume_free(struct irradiance_volume *v)
{
    if (v == NULL)
        return;
    free(v->irradiance);
    free(v->direction);
    v->irradiance = NULL;
    v->direction = NULL;
}

size_t irradiance_volume_bytes(const struct irradiance_volume *v)
{
    size_t voxels = (size_t)v->grid.dims[0] * (size_t)v->grid.dims[1] * (size_t)v->grid.dims[2];
    return voxels * 8 * sizeof(float);
}
