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
// Tricubic B-spline of the stored (grad n, n) with 8 trilinear fetches (Sigg & Hadwiger
// 2005, GPU Gems 2 ch. 20): per axis the four B-spline weights w0..w3 of the taps
// i-1..i+2 are merged pairwise into two linear fetches at i-1 + w1/(w0+w1) and
// i+1 + w3/(w2+w3) (all weights are positive, so each pair is a convex blend). Each fetch
// position is clamped to the object's texels, so the atlas neighbour is never read and a
// tap beyond the grid takes the edge voxel, as the CPU twin's clamp-to-edge taps do
// (server/core/voxel_bspline.c). The gradient is the same B-spline of the stored
// central-difference gradient: C2 like n, and 8 fetches in all instead of 32 for the
// spline's analytic derivative (docs/tracing.md "Index filter").
vec4 volume_sample_ior_grad(int obj, vec3 p)
{
    vec3 hi = vec3(params.objects[obj].resolution.xyz) - vec3(0.5);
    vec3 c = volume_sample_texel(obj, p) - vec3(0.5); // voxel-centre coordinates
    vec3 i = floor(c);
    vec3 t = c - i;
    vec3 s = 1.0 - t;
    vec3 t2 = t * t;
    vec3 w0 = s * s * s * (1.0 / 6.0);
    vec3 w1 = (3.0 * t2 * t - 6.0 * t2 + 4.0) * (1.0 / 6.0);
    vec3 w3 = t2 * t * (1.0 / 6.0);
    vec3 g0 = w0 + w1;
    vec3 g1 = 1.0 - g0;
    vec3 h0 = clamp(i - 0.5 + w1 / g0, vec3(0.5), hi); // texel coordinates
    vec3 h1 = clamp(i + 1.5 + w3 / g1, vec3(0.5), hi);
    vec3 off = params.objects[obj].atlas_offset.xyz;
    vec3 inv = params.objects[obj].atlas_inv_size.xyz;
    h0 = (h0 + off) * inv;
    h1 = (h1 + off) * inv;
    vec4 t000 = textureLod(ior_grad_atlas, vec3(h0.x, h0.y, h0.z), 0.0);
    vec4 t100 = textureLod(ior_grad_atlas, vec3(h1.x, h0.y, h0.z), 0.0);
    vec4 t010 = textureLod(ior_grad_atlas, vec3(h0.x, h1.y, h0.z), 0.0);
    vec4 t110 = textureLod(ior_grad_atlas, vec3(h1.x, h1.y, h0.z), 0.0);
    vec4 t001 = textureLod(ior_grad_atlas, vec3(h0.x, h0.y, h1.z), 0.0);
    vec4 t101 = textureLod(ior_grad_atlas, vec3(h1.x, h0.y, h1.z), 0.0);
    vec4 t011 = textureLod(ior_grad_atlas, vec3(h0.x, h1.y, h1.z), 0.0);
    vec4 t111 = textureLod(ior_grad_atlas, vec3(h1.x, h1.y, h1.z), 0.0);
    vec4 y0 = g0.y * (g0.x * t000 + g1.x * t100) + g1.y * (g0.x * t010 + g1.x * t110);
    vec4 y1 = g0.y * (g0.x * t001 + g1.x * t101) + g1.y * (g0.x * t011 + g1.x * t111);
    return g0.z * y0 + g1.z * y1;
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
