// geom_hit.glsl - the hit record of the exact surfaces (server/core/geom/geom.h's struct
// geom_hit, in float): distance, geometric normal out of the solid, shading normal, and
// the primitive (mesh triangle, lathe edge, box face).
struct geom_hit {
    float t;
    vec3 normal;
    vec3 shading;
    int prim;
};

// Keeps the hit at t when it is past tmin and nearer than best (the twin of geom.h's
// geom_hit_consider).
void geom_hit_consider(float t, float tmin, inout float best, vec3 nrm, int prim,
                       inout geom_hit h)
{
    if (t > tmin && t < best) {
        best = t;
        h.t = t;
        h.normal = nrm;
        h.shading = nrm;
        h.prim = prim;
    }
}
