// sphere.glsl - twin of server/core/geom/sphere.c (same names, float): the roots in the
// precision-keeping form of Ray Tracing Gems ch. 7 (closest-approach discriminant, second
// root from the product of the roots). d is a unit vector.
bool sphere_intersect(vec3 c, float r, vec3 o, vec3 d, float tmin, float tmax, out geom_hit h)
{
    h.t = 0.0;
    h.normal = vec3(0.0);
    h.shading = vec3(0.0);
    h.prim = 0;
    vec3 oc = o - c;
    float b = dot(oc, d);
    vec3 f = oc - b * d;
    float disc = r * r - dot(f, f);
    if (disc < 0.0)
        return false;
    float cc = dot(oc, oc) - r * r;
    float q = -b - (b >= 0.0 ? sqrt(disc) : -sqrt(disc));
    float t0 = q, t1 = q != 0.0 ? cc / q : q;
    float lo = min(t0, t1), hi = max(t0, t1);
    bool near_root = lo > tmin;
    float t = near_root ? lo : hi;
    if (!(t > tmin && t < tmax))
        return false;
    h.t = t;
    // The roots are -b -+ sqrt(disc), so the hit relative to the centre is f -+ sqrt(disc) d:
    // exact to the precision of f, where o + t d - c would lose |o - c| / r of it.
    h.normal = normalize(f + (near_root ? -sqrt(disc) : sqrt(disc)) * d);
    h.shading = h.normal;
    return true;
}

bool sphere_inside(vec3 c, float r, vec3 p)
{
    vec3 v = p - c;
    return dot(v, v) < r * r;
}
