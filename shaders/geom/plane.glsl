// plane.glsl - twin of server/core/geom/plane.c: the solid is the half-space behind n.
bool plane_intersect(vec3 c, vec3 n, vec3 o, vec3 d, float tmin, float tmax, out geom_hit h)
{
    h.t = 0.0;
    h.normal = n;
    h.shading = n;
    h.prim = 0;
    float dn = dot(d, n);
    if (dn == 0.0)
        return false;
    float t = dot(c - o, n) / dn;
    if (!(t > tmin && t < tmax))
        return false;
    h.t = t;
    return true;
}

bool plane_inside(vec3 c, vec3 n, vec3 p)
{
    return dot(p - c, n) < 0.0;
}
