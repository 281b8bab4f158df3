// interface.glsl - the one interface event and the medium rule, twins of
// server/core/interface.c with the same names (docs/tracing.md "Surfaces"): unpolarised
// Fresnel and Snell from fresnel.glsl (frisvad2010), total internal reflection, and the
// nesting priority (the medium of a ray's inside set is its lowest set bit: surfaces are
// numbered by priority, 0 the highest; -1 the ambient medium).

struct interface_event {
    float R;         // unpolarised Fresnel reflectance; 1 under total internal reflection
    bool tir;        // no refracted ray
    vec3 reflected;  // mirror direction
    vec3 refracted;  // Snell (unit); = reflected under total internal reflection
};

interface_event interface_cross(vec3 d, vec3 N, float n_i, float n_t)
{
    interface_event ev;
    ev.R = fresnel_unpolarized(abs(dot(d, N)), n_i, n_t);
    ev.reflected = reflect(d, N);
    vec3 t;
    ev.tir = ev.R >= 1.0 || !snell_refract(d, N, n_i, n_t, t);
    ev.refracted = t;
    if (ev.tir) {
        ev.R = 1.0;
        ev.refracted = ev.reflected;
    }
    return ev;
}

int interface_medium(uint inside)
{
    return inside == 0u ? -1 : findLSB(inside);
}
