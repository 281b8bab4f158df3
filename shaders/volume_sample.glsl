// volume_sample.glsl - sampling an object's voxel fields at an object-space point.
//
// All objects of a scene share one atlas texture per channel: object i occupies the box
// starting at objects[i].atlas_offset. Continuous voxel coordinates are clamped to
// [0.5, res - 0.5] texels so trilinear filtering never reads a neighbour object
// (clamp-to-edge, docs/tracing.md "Conventions"). Needs `params` and the samplers
// ior_grad_atlas, attenuation_atlas, emission_atlas, opaque_atlas, scattering_atlas.

vec3 volume_sample_coord(int obj, vec3 p)
{
    vec3 v = (p - params.objects[obj].bounds_min.xyz) * params.objects[obj].inv_voxel_size.xyz;
    v = clamp(v, vec3(0.5), vec3(params.objects[obj].resolution.xyz) - vec3(0.5));
    return (v + params.objects[obj].atlas_offset.xyz) * params.objects[obj].atlas_inv_size.xyz;
}

// rgb: grad n in object units (n per object-space unit); a: n.
vec4 volume_sample_ior_grad(int obj, vec3 p)
{
    return textureLod(ior_grad_atlas, volume_sample_coord(obj, p), 0.0);
}

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
