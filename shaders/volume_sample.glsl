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
// Three taps along x at atlas coordinates qx (x of each), y, z with weights wx.
vec4 volume_fetch_x3(vec3 qx, float y, float z, vec3 wx)
{
    return wx.x * textureLod(ior_grad_atlas, vec3(qx.x, y, z), 0.0) +
           wx.y * textureLod(ior_grad_atlas, vec3(qx.y, y, z), 0.0) +
           wx.z * textureLod(ior_grad_atlas, vec3(qx.z, y, z), 0.0);
}

// A 3 x 3 plane of taps at z.
vec4 volume_fetch_xy9(mat3 q, mat3 w, float z)
{
    return w[1].x * volume_fetch_x3(q[0], q[1].x, z, w[0]) +
           w[1].y * volume_fetch_x3(q[0], q[1].y, z, w[0]) +
           w[1].z * volume_fetch_x3(q[0], q[1].z, z, w[0]);
}

// Tricubic Catmull-Rom of the stored (grad n, n) with 27 trilinear fetches: per axis the
// four weights w0..w3 of the taps i-1..i+2 (Catmull & Rom 1974; Keys 1981 with a = -1/2)
// have positive middle weights, so the middle pair merges into one linear fetch at
// i + w2 / (w1 + w2) (Sigg & Hadwiger 2005, GPU Gems 2 ch. 20, applied to the pair that
// allows it); the outer taps, whose weights are negative, are fetched at texel centres.
// The kernel interpolates (it returns the voxel at voxel centres), reproduces quadratics,
// and is C1, so grad n is continuous across voxel faces. Each fetch position is clamped to
// the object's texels, so the atlas neighbour is never read and a tap beyond the grid
// takes the edge voxel, as the CPU twin's clamp-to-edge taps do
// (server/core/voxel_tricubic.c). grad n is the same filter of the stored
// central-difference gradient (docs/tracing.md "Index filter").
vec4 volume_sample_ior_grad(int obj, vec3 p)
{
    vec3 hi = vec3(params.objects[obj].resolution.xyz) - vec3(0.5);
    vec3 c = volume_sample_texel(obj, p) - vec3(0.5); // voxel-centre coordinates
    vec3 i = floor(c);
    vec3 t = c - i;
    vec3 t2 = t * t;
    vec3 t3 = t2 * t;
    vec3 w0 = 0.5 * (-t3 + 2.0 * t2 - t);
    vec3 w1 = 0.5 * (3.0 * t3 - 5.0 * t2 + 2.0);
    vec3 w2 = 0.5 * (-3.0 * t3 + 4.0 * t2 + t);
    vec3 w3 = 0.5 * (t3 - t2);
    vec3 wm = w1 + w2; // >= 1 on [0, 1]
    vec3 off = params.objects[obj].atlas_offset.xyz;
    vec3 inv = params.objects[obj].atlas_inv_size.xyz;
    vec3 q0 = (clamp(i - 0.5, vec3(0.5), hi) + off) * inv; // texel i-1's centre
    vec3 q1 = (clamp(i + 0.5 + w2 / wm, vec3(0.5), hi) + off) * inv;
    vec3 q2 = (clamp(i + 2.5, vec3(0.5), hi) + off) * inv; // texel i+2's centre
    // Columns: per axis (x, y, z) the three positions and their weights.
    mat3 q = transpose(mat3(q0, q1, q2));
    mat3 w = transpose(mat3(w0, wm, w3));
    return w[2].x * volume_fetch_xy9(q, w, q[2].x) + w[2].y * volume_fetch_xy9(q, w, q[2].y) +
           w[2].z * volume_fetch_xy9(q, w, q[2].z);
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
