// fresnel.glsl - Fresnel reflectance and Snell refraction (frisvad2010, "The Fresnel
// equations for reflection", "The law of refraction"). Double twins with the same names
// in server/core/fresnel.c; docs/tracing.md fixes the formulas. Directions are unit
// vectors along propagation.

// Unpolarised reflectance R = (R_perp + R_par) / 2 from index n_i to n_t; 1 under total
// internal reflection. (tevs2007 eq. 3.6 is not a reflectance and is not used.)
float fresnel_unpolarized(float cos_i, float n_i, float n_t)
{
    cos_i = clamp(cos_i, 0.0, 1.0);
    float eta = n_i / n_t;
    float sin_t2 = eta * eta * (1.0 - cos_i * cos_i);
    if (sin_t2 >= 1.0)
        return 1.0;
    float cos_t = sqrt(1.0 - sin_t2);
    float r_perp = (n_i * cos_i - n_t * cos_t) / (n_i * cos_i + n_t * cos_t);
    float r_par = (n_t * cos_i - n_i * cos_t) / (n_t * cos_i + n_i * cos_t);
    return 0.5 * (r_perp * r_perp + r_par * r_par);
}

// Refracts d at a surface with unit normal nrm (either orientation). Returns false under
// total internal reflection; else t is the unit transmitted direction.
bool snell_refract(vec3 d, vec3 nrm, float n_i, float n_t, out vec3 t)
{
    vec3 n = dot(d, nrm) > 0.0 ? -nrm : nrm; // face the incident side
    float c = -dot(d, n);
    float eta = n_i / n_t;
    float k = 1.0 - eta * eta * (1.0 - c * c);
    t = d;
    if (k < 0.0)
        return false;
    t = normalize(eta * d + (eta * c - sqrt(k)) * n);
    return true;
}
