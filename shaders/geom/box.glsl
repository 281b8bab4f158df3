// box.glsl - twin of server/core/geom/box.c: the slab test; prim = axis * 2 + (1 on +).
bool box_intersect(vec3 c, vec3 size, vec3 o, vec3 d, float tmin, float tmax, out geom_hit h)
{
    h.t = 0.0;
    h.normal = vec3(0.0);
    h.shading = vec3(0.0);
    h.prim = 0;
    float t_near = -1e30, t_far = 1e30;
    int ax_near = 0, ax_far = 0;
    for (int a = 0; a < 3; a++) {
        float lo = c[a] - 0.5 * size[a], hi = c[a] + 0.5 * size[a];
        if (d[a] == 0.0) {
            if (o[a] < lo || o[a] > hi)
                return false;
            continue;
        }
        float t0 = (lo - o[a]) / d[a], t1 = (hi - o[a]) / d[a];
        float tn = min(t0, t1), tf = max(t0, t1);
        if (tn > t_near) {
            t_near = tn;
            ax_near = a;
        }
        if (tf < t_far) {
            t_far = tf;
            ax_far = a;
        }
    }
    if (t_near > t_far)
        return false;
    float t;
    int axis;
    float sgn;
    if (t_near > tmin) {
        t = t_near;
        axis = ax_near;
        sgn = d[axis] > 0.0 ? -1.0 : 1.0;
    } else {
        t = t_far;
        axis = ax_far;
        sgn = d[axis] > 0.0 ? 1.0 : -1.0;
    }
    if (!(t > tmin && t < tmax))
        return false;
    h.t = t;
    h.normal[axis] = sgn;
    h.shading = h.normal;
    h.prim = axis * 2 + (sgn > 0.0 ? 1 : 0);
    return true;
}

bool box_inside(vec3 c, vec3 size, vec3 p)
{
    return all(lessThan(abs(p - c), 0.5 * size));
}
