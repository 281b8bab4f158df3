// lathe.glsl - twin of server/core/geom/lathe.c: a solid of revolution of the profile
// polygon lathe_points[first .. first + count) ((r, h) pairs, read from the
// BIND_SSBO_SURFACE_PROFILES buffer declared in surface.glsl); each edge sweeps a cone
// frustum (a quadratic in t), a cylinder or an annulus. orient: +1 for a
// counter-clockwise polygon (precomputed on the CPU from its signed area).
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

// The heights the ray spans inside the bounding cylinder (bounds: x r_max, y h_min,
// z h_max), as lathe.c's lathe_span; false when it misses the cylinder.
bool lathe_span(float ox, float oy, float oh, float dx, float dy, float dh, vec3 bounds,
                float tmin, float tmax, out float span_lo, out float span_hi)
{
    float margin = 1e-5 * (bounds.x + abs(bounds.y) + abs(bounds.z));
    float r = bounds.x + margin;
    float t0 = tmin, t1 = tmax;
    span_lo = bounds.y - margin;
    span_hi = bounds.z + margin;
    float A = dx * dx + dy * dy;
    if (A > 0.0) {
        float b = (ox * dx + oy * dy) / A;
        float fx = ox - b * dx, fy = oy - b * dy;
        float disc = (r * r - (fx * fx + fy * fy)) / A;
        if (disc < 0.0)
            return false;
        float q = sqrt(disc);
        t0 = max(t0, -b - q);
        t1 = min(t1, -b + q);
    } else if (ox * ox + oy * oy > r * r) {
        return false;
    }
    if (dh != 0.0) {
        float ta = (bounds.y - margin - oh) / dh, tb = (bounds.z + margin - oh) / dh;
        t0 = max(t0, min(ta, tb));
        t1 = min(t1, max(ta, tb));
    } else if (oh < bounds.y - margin || oh > bounds.z + margin) {
        return false;
    }
    if (t0 > t1)
        return false;
    float ha = oh + t0 * dh, hb = oh + t1 * dh;
    if (abs(t0) < 1e29 && abs(t1) < 1e29) {
        span_lo = min(ha, hb) - margin;
        span_hi = max(ha, hb) + margin;
    }
    return true;
}

bool lathe_intersect(vec3 base, int axis, int first, int count, float orient, vec3 bounds,
                     vec3 o, vec3 d, float tmin, float tmax, out geom_hit h)
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
    float span_lo, span_hi;
    if (!lathe_span(ox, oy, oh, dx, dy, dh, bounds, tmin, tmax, span_lo, span_hi))
        return false;
    for (int i = 0; i < count; i++) {
        vec2 p0 = lathe_points[first + i];
        vec2 p1 = lathe_points[first + (i + 1) % count];
        if (max(p0.y, p1.y) < span_lo || min(p0.y, p1.y) > span_hi)
            continue;
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
                geom_hit_consider(t, tmin, best, lathe_edge_normal(axis, x, y, 0.0, n_h), i, h);
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
            geom_hit_consider(t, tmin, best,
                           lathe_edge_normal(axis, ox + t * dx, oy + t * dy, n_r, n_h), i, h);
        }
    }
    return best < tmax;
}
