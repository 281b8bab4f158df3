// photons.glsl - the receiver's light in the "photons" caustics mode (docs/photons.md):
// the photon map's irradiance (the twin of photon_irradiance, server/core/photon_grid.c)
// and the shadow ray of the direct part (the twin of photon_light_visible,
// server/core/photon_receiver.c). Included by ray_march.glsl after the surface kinds when
// the kernel gathers radiance with surfaces and lights; lighting.glsl declares both.

layout(std430, binding = BIND_SSBO_PHOTONS) readonly buffer photons_block
{
    vec4 photon_E[]; // per hash slot: the lattice point's E (rgb)
};

layout(std430, binding = BIND_SSBO_PHOTON_BUCKETS) readonly buffer photon_keys_block
{
    ivec2 photon_keys[]; // per hash slot: the lattice point (i, j); PHOTON_EMPTY_KEY: empty
};

// The slot where the probe for lattice point (i, j) starts (photon.h's photon_hash: 32-bit
// unsigned, wrapping; pixel_hash is lowbias32, from pixel_sample.glsl, which render_view.comp
// includes first).
uint photon_hash(int i, int j, uint capacity)
{
    return pixel_hash(uint(i) ^ pixel_hash(uint(j) + 0x9e3779b9u)) & (capacity - 1u);
}

// E at lattice point (i, j) of light j's map, 0 when it is not stored (no photon within the
// radius): at most probe_max + 1 slots (photon_lattice_at). The maps of the lights lie one
// after another in the buffers, light j's from slot photon_dims[j].z.
vec3 photon_lattice_at(int light, int i, int j)
{
    ivec4 dims = lights.photon_dims[light];
    uint capacity = uint(dims.x), probe_max = uint(dims.y), first = uint(dims.z);
    uint s = photon_hash(i, j, capacity);
    for (uint n = 0u; n <= probe_max; n++) {
        ivec2 key = photon_keys[first + s];
        if (key.x == PHOTON_EMPTY_KEY)
            break;
        if (key == ivec2(i, j))
            return photon_E[first + s].rgb;
        s = (s + 1u) & (capacity - 1u);
    }
    return vec3(0.0);
}

// E (W / unit^2, rgb, of light `light` at unit intensity) on the plane at world (x, z):
// bilinear between the four lattice points about it, each holding the kernel estimate
// sum phi_p 2 / (pi r^2) (1 - s^2 / r^2). The caller scales it by the light's colour times
// intensity (docs/photons.md "The cache": a map per light).
vec3 photon_irradiance(int light, vec2 xz)
{
    if (lights.photon_dims[light].x == 0)
        return vec3(0.0);
    vec2 u = xz / lights.photon_grid[light].x;
    vec2 c = clamp(floor(u), vec2(-PHOTON_CELL_MAX), vec2(PHOTON_CELL_MAX));
    vec2 f = u - floor(u);
    int i = int(c.x), j = int(c.y);
    vec3 e00 = photon_lattice_at(light, i, j), e10 = photon_lattice_at(light, i + 1, j);
    vec3 e01 = photon_lattice_at(light, i, j + 1), e11 = photon_lattice_at(light, i + 1, j + 1);
    return mix(mix(e00, e10, f.x), mix(e01, e11, f.x), f.y);
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
