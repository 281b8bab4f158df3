// photons.glsl - the receiver's light in the "photons" caustics mode (docs/photons.md):
// the photon map's irradiance (the twin of photon_irradiance, server/core/photon_grid.c)
// and the shadow ray of the direct part (the twin of photon_light_visible,
// server/core/photon_receiver.c). Included by ray_march.glsl after the surface kinds when
// the kernel gathers radiance with surfaces and lights; lighting.glsl declares both.

layout(std430, binding = BIND_SSBO_PHOTONS) readonly buffer photons_block
{
    vec4 photon_data[]; // 2 per photon: (x, z, 0, 0), (power rgb, 0)
};

layout(std430, binding = BIND_SSBO_PHOTON_BUCKETS) readonly buffer photon_buckets_block
{
    uint photon_start[]; // bucket b's photons: [photon_start[b], photon_start[b + 1])
};

// The bucket of cell (i, j) (photon.h's photon_hash: 32-bit unsigned, wrapping).
uint photon_hash(int i, int j, uint buckets)
{
    return ((uint(i) * 73856093u) ^ (uint(j) * 19349663u)) & (buckets - 1u);
}

int photon_cell_of(float v, float cell)
{
    return int(clamp(floor(v / cell), -1073741824.0, 1073741824.0));
}

// E (W / unit^2, rgb) on the plane at world (x, z): the kernel estimate
// sum phi_p 2 / (pi r^2) (1 - s^2 / r^2) over the photons within the radius, from the
// distinct buckets of the 3 x 3 cells about the point.
vec3 photon_irradiance(vec2 xz)
{
    uint buckets = uint(lights.photon_dims.x);
    if (buckets == 0u)
        return vec3(0.0);
    float cell = lights.photon_grid.x, r2 = lights.photon_grid.y * lights.photon_grid.y;
    int ci = photon_cell_of(xz.x, cell), cj = photon_cell_of(xz.y, cell);
    uint seen[9];
    int n_seen = 0;
    vec3 sum = vec3(0.0);
    for (int dj = -1; dj <= 1; dj++) {
        for (int di = -1; di <= 1; di++) {
            uint b = photon_hash(ci + di, cj + dj, buckets);
            bool dup = false;
            for (int k = 0; k < n_seen; k++)
                dup = dup || seen[k] == b;
            if (dup)
                continue; // two cells in one bucket: its photons count once
            seen[n_seen++] = b;
            for (uint k = photon_start[b]; k < photon_start[b + 1u]; k++) {
                vec2 d = photon_data[2u * k].xy - xz;
                float s2 = dot(d, d);
                if (s2 < r2)
                    sum += photon_data[2u * k + 1u].rgb * (1.0 - s2 / r2);
            }
        }
    }
    return sum * (2.0 / (LIGHT_PI * r2));
}

// True when surface k changes light: its medium differs from the ambient one (another
// index, absorption or scattering). The twin of photon_surface_optical.
bool photon_surface_optical(int k)
{
    surface_params sp = surfaces[k];
    return sp.medium.x != params.settings_f.z || any(greaterThan(sp.attenuation.rgb, vec3(0.0))) ||
           any(greaterThan(sp.scattering.rgb, vec3(0.0)));
}

// The shadow ray of light j's direct part at receiver point at: false when an optical
// surface lies between them (that light reaches the plane as photons, or not at all).
bool photon_light_visible(int j, vec3 at)
{
    light_params lp = lights.lights[j];
    vec3 to;
    float dist;
    if (int(lp.position.w) == LIGHT_KIND_DIRECTIONAL) {
        to = -lp.direction.xyz;
        dist = 3.0e38;
    } else {
        vec3 v = lp.position.xyz - at;
        dist = length(v);
        to = v / dist;
    }
    for (int k = 0; k < params.surfaces.x; k++) {
        if (!photon_surface_optical(k))
            continue;
        geom_hit h;
        if (geom_surface_intersect(k, at, to, 0.0, dist, -1, h))
            return false;
    }
    return true;
}
