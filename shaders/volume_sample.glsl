// volume_sample.glsl - sampling an object's voxel fields at an object-space point.
//
// All objects of a scene share one atlas texture per channel: object i occupies the box
// starting at objects[i].atlas_offset. Continuous voxel coordinates are clamped to
// [0.5, res - 0.5] texels so trilinear filtering never reads a neighbour object
// (clamp-to-edge, docs/tracing.md "Conventions"). Needs `params` and the samplers
// ior_grad_atlas, attenuation_atlas, emission_atlas, opaque_atlas, scattering_atlas.
// The index and its gradient are trilinear or tricubic (MARCH_IOR_FILTER); the other
// channels are always trilinear.

// Continuous texel coordinates of p in object obj (voxel centres at i + 0.5), clamped to
// [0.5, res - 0.5].
vec3 volume_sample_texel(int obj, vec3 p)
{
    vec3 v = (p - params.objects[obj].bounds_min.xyz) * params.objects[obj].inv_voxel_size.xyz;
    return clamp(v, vec3(0.5), vec3(params.objects[obj].resolution.xyz) - vec3(0.5));
}

// The atlas coordinates of p in object obj (the clamped texel coordinates).
vec3 volume_sample_coord(int obj, vec3 p)
{
    vec3 v = volume_sample_texel(obj, p);
    return (v + params.objects[obj].atlas_offset.xyz) * params.objects[obj].atlas_inv_size.xyz;
}

#if MARCH_IOR_FILTER == IOR_FILTER_TRICUBIC
// Catmull-Rom weights w and their derivatives d (per voxel) of the taps i-1..i+2 at
// fraction t. A tap beyond the grid (below: i-1 < 0, above: i+2 > res-1) stands for the
// linear extrapolation of the two edge voxels, f[-1] = 2 f[0] - f[1]; its weight is folded
// into theirs and the tap itself gets weight 0 (server/core/voxel_tricubic.c does the same).
void volume_catmull_rom(float t, bool below, bool above, out vec4 w, out vec4 d)
{
    float t2 = t * t, t3 = t2 * t;
    w = 0.5 * vec4(-t3 + 2.0 * t2 - t, 3.0 * t3 - 5.0 * t2 + 2.0, -3.0 * t3 + 4.0 * t2 + t,
                   t3 - t2);
    d = 0.5 * vec4(-3.0 * t2 + 4.0 * t - 1.0, 9.0 * t2 - 10.0 * t, -9.0 * t2 + 8.0 * t + 1.0,
                   3.0 * t2 - 2.0 * t);
    if (below) {
        w += vec4(-w.x, 2.0 * w.x, -w.x, 0.0);
        d += vec4(-d.x, 2.0 * d.x, -d.x, 0.0);
    }
    if (above) {
        w += vec4(0.0, -w.w, 2.0 * w.w, -w.w);
        d += vec4(0.0, -d.w, 2.0 * d.w, -d.w);
    }
}

// Tricubic Catmull-Rom of n (Keys 1981 with a = -1/2) and grad n as the exact gradient of
// that interpolant, from the 4 x 4 x 4 voxels around p (64 texel fetches of the alpha
// channel; the stored central-difference gradient is not used). The interpolant returns
// the voxel at voxel centres, reproduces quadratics inside the grid and linear fields up to
// its edge, and is C1, so grad n is continuous and consistent with n (the ray follows the
// exact ray equation of one continuous field). Taps are clamped to the object's voxels, so
// the atlas neighbour is never read (docs/tracing.md "Index filter"). CPU twin:
// voxel_tricubic_n_grad.
vec4 volume_sample_ior_grad(int obj, vec3 p)
{
    ivec3 r = params.objects[obj].resolution.xyz;
    vec3 c = volume_sample_texel(obj, p) - vec3(0.5); // voxel-centre coordinates
    // The cell [i, i+1] holding c; at c = res-1 the last cell with t = 1, so the gradient
    // on the grid's last plane is the limit from inside.
    vec3 fi = max(min(floor(c), vec3(r) - vec3(2.0)), vec3(0.0));
    vec3 t = c - fi;
    ivec3 i = ivec3(fi);
    vec4 wx, wy, wz, dx, dy, dz;
    volume_catmull_rom(t.x, i.x < 1, i.x + 2 > r.x - 1, wx, dx);
    volume_catmull_rom(t.y, i.y < 1, i.y + 2 > r.y - 1, wy, dy);
    volume_catmull_rom(t.z, i.z < 1, i.z + 2 > r.z - 1, wz, dz);
    ivec3 off = ivec3(params.objects[obj].atlas_offset.xyz + vec3(0.5));
    float n = 0.0;
    vec3 g = vec3(0.0);
    for (int z = 0; z < 4; z++) {
        int iz = clamp(i.z - 1 + z, 0, r.z - 1);
        for (int y = 0; y < 4; y++) {
            int iy = clamp(i.y - 1 + y, 0, r.y - 1);
            // The x row: value, d/dx, and the row sum for d/dy and d/dz.
            float row = 0.0, row_dx = 0.0;
            for (int x = 0; x < 4; x++) {
                int ix = clamp(i.x - 1 + x, 0, r.x - 1);
                float f = texelFetch(ior_grad_atlas, off + ivec3(ix, iy, iz), 0).a;
                row += wx[x] * f;
                row_dx += dx[x] * f;
            }
            n += wy[y] * wz[z] * row;
            g += vec3(wy[y] * wz[z] * row_dx, dy[y] * wz[z] * row, wy[y] * dz[z] * row);
        }
    }
    return vec4(g * params.objects[obj].inv_voxel_size.xyz, n);
}
#else
// rgb: grad n in object units (n per object-space unit); a: n. Trilinear.
vec4 volume_sample_ior_grad(int obj, vec3 p)
{
    return textureLod(ior_grad_atlas, volume_sample_coord(obj, p), 0.0);
}
#endif

// The atlas texel of object obj at p, or zero when the object lacks the channel `flag`
// (it then reads the atlas' zero stand-in region or another object's data).
vec4 volume_sample_masked(sampler3D atlas, int obj, vec3 p, int flag)
{
    vec4 t = textureLod(atlas, volume_sample_coord(obj, p), 0.0);
    return (params.objects[obj].resolution.w & flag) != 0 ? t : vec4(0.0);
}

// sigma_a per world unit (tevs2007 eq. 3.4); 0 when the object has no attenuation.
// Objects without the channel are masked by their flag; scenes without it compile the
// fetch out (MARCH_ATTENUATION 0).
vec3 volume_sample_attenuation(int obj, vec3 p)
{
#if MARCH_ATTENUATION
    return volume_sample_masked(attenuation_atlas, obj, p, OBJECT_HAS_ATTENUATION).rgb;
#else
    return vec3(0.0);
#endif
}

// Emitted radiance per world unit, L_e of tevs2007 eq. 5.4.
vec3 volume_sample_emission(int obj, vec3 p)
{
#if MARCH_EMISSION
    return volume_sample_masked(emission_atlas, obj, p, OBJECT_HAS_EMISSION).rgb;
#else
    return vec3(0.0);
#endif
}

// rgb: opaque colour; a: coverage (tevs2007 sect. 6.1, texture T6).
vec4 volume_sample_opaque(int obj, vec3 p)
{
#if MARCH_OPAQUE
    return volume_sample_masked(opaque_atlas, obj, p, OBJECT_HAS_OPAQUE);
#else
    return vec4(0.0);
#endif
}

// rgb: scattering coefficient sigma_s per world unit; a: Henyey-Greenstein g (tevs2007
// eqs. 5.4/5.5). Zero for objects without a scattering channel.
vec4 volume_sample_scattering(int obj, vec3 p)
{
#if MARCH_SCATTERING
    return volume_sample_masked(scattering_atlas, obj, p, OBJECT_HAS_SCATTERING);
#else
    return vec4(0.0);
#endif
}

// Extinction sigma_t = sigma_a + sigma_s per world unit: what the optical depth alpha
// integrates (eq. 5.9 with scattering out of the ray).
vec3 volume_sample_extinction(int obj, vec3 p)
{
    return volume_sample_attenuation(obj, p) + volume_sample_scattering(obj, p).rgb;
}
