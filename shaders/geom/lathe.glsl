// lathe.glsl - twin of server/core/geom/lathe.c: a solid of revolution of the profile
// polygon lathe_points[first .. first + count) ((r, h) pairs, read from the
// BIND_SSBO_SURFACE_PROFILES buffer declared in surface.glsl); each edge sweeps a cone
// frustum (a quadratic in t), a cylinder or an annulus. orient: +1 for a
// counter-clockwise polygon (precomputed on the CPU from its signed area).
void lathe_consider(float t, float tmin, inout float best, vec3 nrm, int prim, inout geom_hit h)
{
    if (t > tmin && t < best) {
        best = t;
        h.t = t;
        h.normal = nrm;
        h.shading = nrm;
        h.prim = prim;
    }
}

vec3 lathe_edge_normal(int axis, float x, float y, float n_r, float n_h)
{
    int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    float rho = sqrt(x * x + y * y);
    vec3 n = vec3(0.0);
    if (rho > 0.0) {
        n[a1] = n_r * x / rho;
        n[a2] = n_r * y / rho;
    }
    n[axis] = n_h;
    return normalize(n);
}

bool lathe_intersect(vec3 base, int axis, int first, int count, float orient, vec3 o, vec3 d,
                     float tmin, float tmax, out geom_hit h)
{
    h.t = 0.0;
    h.normal = vec3(0.0);
    h.shading = vec3(0.0);
    h.prim = 0;
    int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    vec3 v = o - base;
    float ox = v[a1], oy = v[a2], oh = v[axis];
    float dx = d[a1], dy = d[a2], dh = d[axis];
    float best = tmax;
    for (int i = 0; i < count; i++) {
        vec2 p0 = lathe_points[first + i];
        vec2 p1 = lathe_points[first + (i + 1) % count];
        float er = p1.x - p0.x, eh = p1.y - p0.y;
        float n_r = orient * eh, n_h = -orient * er;
        if (p0.x == 0.0 && p1.x == 0.0)
            continue;
        if (eh == 0.0) {
            if (dh == 0.0)
                continue;
            float t = (p0.y - oh) / dh;
            float x = ox + t * dx, y = oy + t * dy, rr = x * x + y * y;
            float lo = min(p0.x, p1.x), hi = max(p0.x, p1.x);
            if (rr >= lo * lo && rr <= hi * hi)
                lathe_consider(t, tmin, best, lathe_edge_normal(axis, x, y, 0.0, n_h), i, h);
            continue;
        }
        float k = er / eh;
        float alpha = p0.x + k * (oh - p0.y), beta = k * dh;
        float A = dx * dx + dy * dy - beta * beta;
        float B = ox * dx + oy * dy - alpha * beta;
        float C = ox * ox + oy * oy - alpha * alpha;
        float roots[2] = float[2](-1e30, -1e30);
        if (abs(A) < 1e-30) {
            if (B != 0.0)
                roots[0] = -C / (2.0 * B);
        } else {
            float disc = B * B - A * C;
            if (disc < 0.0)
                continue;
            float q = -B - (B >= 0.0 ? sqrt(disc) : -sqrt(disc));
            roots[0] = q / A;
            if (q != 0.0)
                roots[1] = C / q;
        }
        for (int j = 0; j < 2; j++) {
            float t = roots[j];
            float s = (oh + t * dh - p0.y) / eh;
            if (t == -1e30 || s < 0.0 || s > 1.0 || alpha + beta * t < 0.0)
                continue;
            lathe_consider(t, tmin, best,
                           lathe_edge_normal(axis, ox + t * dx, oy + t * dy, n_r, n_h), i, h);
        }
    }
    return best < tmax;
}
