// rounded_box.glsl - twin of server/core/geom/rounded_box.c (same names, float): the box of
// full sizes size with edges and corners rounded to radius r, as the union of three slabs,
// twelve edge cylinders and eight corner balls. The solid is convex, so the ray's interval
// in it runs from the smallest entry to the largest exit over the parts; the normal is
// (p - q) / r with q the nearest point of the inner box.

bool rounded_box_slab(vec3 hs, vec3 o, vec3 d, out float t0, out float t1)
{
    t0 = -1e30;
    t1 = 1e30;
    for (int a = 0; a < 3; a++) {
        if (d[a] == 0.0) {
            if (abs(o[a]) > hs[a])
                return false;
            continue;
        }
        float ta = (-hs[a] - o[a]) / d[a], tb = (hs[a] - o[a]) / d[a];
        t0 = max(t0, min(ta, tb));
        t1 = min(t1, max(ta, tb));
    }
    return t0 <= t1;
}

// |oc + t dd| < r: a ball (dd = d) or a cylinder across its axis (dd = d without it).
bool rounded_box_ball(vec3 oc, vec3 dd, float r, out float t0, out float t1)
{
    t0 = 0.0;
    t1 = 0.0;
    float a = dot(dd, dd);
    float c = dot(oc, oc) - r * r;
    if (a < 1e-20) {
        t0 = -1e30;
        t1 = 1e30;
        return c <= 0.0;
    }
    float b = dot(oc, dd) / a;
    vec3 f = oc - b * dd;
    float disc = (r * r - dot(f, f)) / a;
    if (disc < 0.0)
        return false;
    float q = -b - (b >= 0.0 ? sqrt(disc) : -sqrt(disc));
    float other = q != 0.0 ? (c / a) / q : q;
    t0 = min(q, other);
    t1 = max(q, other);
    return true;
}

bool rounded_box_intersect(vec3 c, vec3 size, float r, vec3 o, vec3 d, float tmin, float tmax,
                           out geom_hit h)
{
    if (!(r > 0.0))
        return box_intersect(c, size, o, d, tmin, tmax, h);
    h.t = 0.0;
    h.normal = vec3(0.0);
    h.shading = vec3(0.0);
    h.prim = 0;
    vec3 b = 0.5 * size - vec3(r);
    vec3 oc = o - c;
    float t0, t1;
    if (!rounded_box_slab(0.5 * size, oc, d, t0, t1) || t1 <= tmin || t0 >= tmax)
        return false;
    float tin = 1e30, tout = -1e30;
    for (int a = 0; a < 3; a++) {
        vec3 hs = b;
        hs[a] += r;
        if (rounded_box_slab(hs, oc, d, t0, t1)) {
            tin = min(tin, t0);
            tout = max(tout, t1);
        }
        int u = (a + 1) % 3, v = (a + 2) % 3;
        vec3 dd = d;
        dd[a] = 0.0;
        for (int s = 0; s < 4; s++) {
            vec3 e = vec3(0.0);
            e[u] = (s & 1) != 0 ? b[u] : -b[u];
            e[v] = (s & 2) != 0 ? b[v] : -b[v];
            vec3 oe = oc - e;
            oe[a] = 0.0;
            if (!rounded_box_ball(oe, dd, r, t0, t1))
                continue;
            if (d[a] != 0.0) {
                float ta = (-b[a] - oc[a]) / d[a], tb = (b[a] - oc[a]) / d[a];
                t0 = max(t0, min(ta, tb));
                t1 = min(t1, max(ta, tb));
            } else if (abs(oc[a]) > b[a]) {
                continue;
            }
            if (t0 <= t1) {
                tin = min(tin, t0);
                tout = max(tout, t1);
            }
        }
    }
    for (int k = 0; k < 8; k++) {
        vec3 corner = vec3((k & 1) != 0 ? b.x : -b.x, (k & 2) != 0 ? b.y : -b.y,
                           (k & 4) != 0 ? b.z : -b.z);
        if (rounded_box_ball(oc - corner, d, r, t0, t1)) {
            tin = min(tin, t0);
            tout = max(tout, t1);
        }
    }
    if (!(tin <= tout))
        return false;
    float t = tin > tmin ? tin : tout;
    if (!(t > tmin && t < tmax))
        return false;
    vec3 p = oc + t * d;
    h.t = t;
    h.normal = normalize(p - clamp(p, -b, b));
    h.shading = h.normal;
    return true;
}

bool rounded_box_inside(vec3 c, vec3 size, float r, vec3 p)
{
    if (!(r > 0.0))
        return box_inside(c, size, p);
    vec3 e = max(abs(p - c) - (0.5 * size - vec3(r)), vec3(0.0));
    return dot(e, e) < r * r;
}
