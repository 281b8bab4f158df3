// geom_hit.glsl - the hit record of the exact surfaces (server/core/geom/geom.h's struct
// geom_hit, in float): distance, geometric normal out of the solid, shading normal, and
// the primitive (mesh triangle, lathe edge, box face).
struct geom_hit {
    float t;
    vec3 normal;
    vec3 shading;
    int prim;
};
