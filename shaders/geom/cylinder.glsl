// cylinder.glsl - twin of server/core/geom/cylinder.c: the side quadratic across the
// axis and the two caps; prim 0 side, 1 lower cap, 2 upper cap.
bool cylinder_intersect(vec3 c, float r, float height, int axis, vec3 o, vec3 d, float tmin,
                        float tmax, out geom_hit h)
{
    h.t = 0.0;
    h.normal = vec3(0.0);
    h.shading = vec3(0.0);
    h.prim = 0;
    int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    vec3 oc = o - c;
    float half_h = 0.5 * height;
    float best = tmax;
    float ox = oc[a1], oy = oc[a2], dx = d[a1], dy = d[a2];
    float A = dx * dx + dy * dy;
    if (A > 0.0) {
        float b = (ox * dx + oy * dy) / A;
        float fx = ox - b * dx, fy = oy - b * dy;
        float disc = (r * r - (fx * fx + fy * fy)) / A;
        if (disc >= 0.0) {
            float cc = (ox * ox + oy * oy - r * r) / A;
            float q = -b - (b >= 0.0 ? sqrt(disc) : -sqrt(disc));
            float roots[2] = float[2](q, q != 0.0 ? cc / q : q);
            for (int i = 0; i < 2; i++) {
                float t = roots[i];
                if (abs(oc[axis] + t * d[axis]) > half_h)
                    continue;
                vec3 nrm = vec3(0.0);
                nrm[a1] = (ox + t * dx) / r;
                nrm[a2] = (oy + t * dy) / r;
                geom_hit_consider(t, tmin, best, normalize(nrm), 0, h);
            }
        }
    }
    if (d[axis] != 0.0) {
        for (int s = 0; s < 2; s++) {
            float level = s == 1 ? half_h : -half_h;
            float t = (level - oc[axis]) / d[axis];
            float x = ox + t * dx, y = oy + t * dy;
            if (x * x + y * y > r * r)
                continue;
            vec3 nrm = vec3(0.0);
            nrm[axis] = s == 1 ? 1.0 : -1.0;
            geom_hit_consider(t, tmin, best, nrm, 1 + s, h);
        }
    }
    return best < tmax;
}

bool cylinder_inside(vec3 c, float r, float height, int axis, vec3 p)
{
    vec3 v = p - c;
    float x = v[(axis + 1) % 3], y = v[(axis + 2) % 3];
    return abs(v[axis]) < 0.5 * height && x * x + y * y < r * r;
}
