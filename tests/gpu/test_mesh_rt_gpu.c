/*
 * test_mesh_rt_gpu.c - the GLSL mesh_rt_intersect (shaders/geom/mesh.glsl, float, run by
 * shaders/mesh_rays_test.comp) against the C double version (server/mesh/mesh_rt_trace.c)
 * on two meshes concatenated in the same three storage buffers, as a renderer would
 * upload them: an icosphere and a bumpy (random-radius, non-convex) one moved aside.
 * Rays: at random points of each mesh's box, exactly at icosphere vertices (watertight
 * in float too: none may miss), and continuations from the C hit (tmin = t, skip_tri).
 *
 * Bounds, from float32 (unit roundoff 6e-8) on coordinates of size ~1-3:
 *   t: 1e-5 relative, or for grazing hits (|cos| < 0.01) 1e-6 of the mesh size over |cos|;
 *   normals: 1e-4 rad (geometric: rounding of ~0.05-long edges, ~1e-6; shading: the
 *   snorm16 octahedral coding, 4.3e-5 rad at worst, test_mesh_rt_bvh.c, magnified by
 *   1 / |interpolated normal| where a bumpy mesh's vertex normals diverge, so the bound
 *   is on the angle times that length; 1e-3 for grazing hits, whose point slides with t);
 *   triangle: the same, except where the C hit is within 1e-4 (barycentric) of an edge
 *   of its triangle, where float and double may pick either side (a near-tie);
 *   hit versus miss: only at such near-edge or grazing (|cos| < 0.01) rays, at most 0.5%.
 * Also reports and bounds the GPU bytes per triangle (<= 64).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gpu/program.h"
#include "gpu/queue.h"
#include "gpu/resources.h"
#include "mesh/mesh.h"
#include "mesh/mesh_rt.h"
#include "bindings.h"
#include "gpu_test_util.h"
#include "test.h"

struct ray_rec {
    float origin[4];    /* w: tmin */
    float direction[4]; /* w: tmax */
    int32_t mesh[4];    /* first node, triangle, vertex; w: skip_tri */
};
struct hit_rec {
    float t_geom[4]; /* t (-1: missed), geometric normal */
    float shade[4];  /* shading normal; w: int bits of the triangle */
};
_Static_assert(sizeof(struct ray_rec) == 48 && sizeof(struct hit_rec) == 32, "std430");

struct cpu_ray {
    vec3 o, d;
    double tmin;
    int64_t skip;
    int mesh;      /* 0 or 1 */
    bool must_hit; /* aimed at a vertex through the interior */
};

struct rays_work {
    struct gpu_work work;
    const struct mesh *meshes[2];
    const struct cpu_ray *rays;
    int n;
    struct hit_rec *out;
    size_t gpu_bytes[2];   /* node + triangle + vertex bytes of each mesh as uploaded */
    int compiled_from_dir; /* 1: compiled from $REFRACT_SOURCE_DIR/shaders, -1: failed */
};

static void rays_run(struct gpu_work *w, struct gpu *gpu)
{
    (void)gpu;
    struct rays_work *rw = w->user;
    struct gpu_program_desc desc = {.label = "mesh rays test", .main = "mesh_rays_test.comp"};
    GLuint prog = gpu_program_create(&desc, NULL, &w->err);
    if (prog == 0)
        return;
    /* the same kernel read from shaders/ (refractd --shader-dir): "geom/mesh.glsl" resolves
     * there as in the embedded table */
    const char *src = getenv("REFRACT_SOURCE_DIR");
    if (src != NULL) {
        char dir[1024];
        snprintf(dir, sizeof dir, "%s/shaders", src);
        struct err e2 = {0};
        GLuint from_dir = gpu_program_create(&desc, dir, &e2);
        rw->compiled_from_dir = from_dir != 0 ? 1 : -1;
        if (from_dir == 0)
            fprintf(stderr, "from %s: %s\n", dir, e2.msg);
        glDeleteProgram(from_dir);
    }
    struct mesh_rt_gpu g[2] = {mesh_rt_gpu_arrays(rw->meshes[0]->rt),
                               mesh_rt_gpu_arrays(rw->meshes[1]->rt)};
    /* concatenated: mesh 1's records follow mesh 0's in each buffer */
    size_t nb = g[0].node_bytes + g[1].node_bytes, tb = g[0].tri_bytes + g[1].tri_bytes,
           vb = g[0].vertex_bytes + g[1].vertex_bytes;
    char *nodes = malloc(nb), *tris = malloc(tb), *verts = malloc(vb);
    memcpy(nodes, g[0].nodes, g[0].node_bytes);
    memcpy(nodes + g[0].node_bytes, g[1].nodes, g[1].node_bytes);
    memcpy(tris, g[0].tris, g[0].tri_bytes);
    memcpy(tris + g[0].tri_bytes, g[1].tris, g[1].tri_bytes);
    memcpy(verts, g[0].verts, g[0].vertex_bytes);
    memcpy(verts + g[0].vertex_bytes, g[1].verts, g[1].vertex_bytes);
    for (int i = 0; i < 2; i++)
        rw->gpu_bytes[i] = g[i].total_bytes;
    struct ray_rec *in = calloc((size_t)rw->n, sizeof *in);
    for (int i = 0; i < rw->n; i++) {
        const struct cpu_ray *r = &rw->rays[i];
        in[i] = (struct ray_rec){{(float)r->o.x, (float)r->o.y, (float)r->o.z, (float)r->tmin},
                                 {(float)r->d.x, (float)r->d.y, (float)r->d.z, INFINITY},
                                 {r->mesh ? (int32_t)g[0].node_count : 0,
                                  r->mesh ? (int32_t)g[0].tri_count : 0,
                                  r->mesh ? (int32_t)g[0].vertex_count : 0, (int32_t)r->skip}};
    }
    struct gpu_buffer bn = {0}, bt = {0}, bv = {0}, bi = {0}, bo = {0};
    size_t out_bytes = (size_t)rw->n * sizeof *rw->out;
    if (gpu_buffer_create("mesh nodes", nb, nodes, &bn, &w->err) == REFRACT_E_OK &&
        gpu_buffer_create("mesh tris", tb, tris, &bt, &w->err) == REFRACT_E_OK &&
        gpu_buffer_create("mesh verts", vb, verts, &bv, &w->err) == REFRACT_E_OK &&
        gpu_buffer_create("mesh rays", (size_t)rw->n * sizeof *in, in, &bi, &w->err) ==
            REFRACT_E_OK &&
        gpu_buffer_create("mesh hits", out_bytes, NULL, &bo, &w->err) == REFRACT_E_OK) {
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SSBO_MESH_NODES, bn.buf);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SSBO_MESH_TRIS, bt.buf);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SSBO_MESH_VERTS, bv.buf);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SSBO_RAYS_IN, bi.buf);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SSBO_HITS_OUT, bo.buf);
        glUseProgram(prog);
        glProgramUniform1i(prog, glGetUniformLocation(prog, "u_ray_count"), rw->n);
        glDispatchCompute(gpu_groups(rw->n, TRACE_LOCAL_X), 1, 1);
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
        if (gpu_check("mesh rays test", &w->err) == REFRACT_E_OK)
            gpu_buffer_read(&bo, rw->out, out_bytes, &w->err);
    }
    glUseProgram(0);
    gpu_buffer_destroy(&bn);
    gpu_buffer_destroy(&bt);
    gpu_buffer_destroy(&bv);
    gpu_buffer_destroy(&bi);
    gpu_buffer_destroy(&bo);
    glDeleteProgram(prog);
    free(nodes);
    free(tris);
    free(verts);
    free(in);
}

static uint64_t rng = 0x9e3779b97f4a7c15ull;
static double uniform(void)
{
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    return (double)(rng >> 11) / 9007199254740992.0;
}
static vec3 unit(void)
{
    double z = 2 * uniform() - 1, phi = 6.283185307179586 * uniform(), s = sqrt(1 - z * z);
    return vec3_make(s * cos(phi), s * sin(phi), z);
}

/* The smallest barycentric coordinate of the ray's crossing of triangle tri's plane
 * (negative outside): how near the ray passes to the triangle's edges. */
static double bary_margin(const struct mesh *m, uint32_t tri, vec3 o, vec3 d)
{
    const uint32_t *t = m->triangles[tri];
    vec3 a = v3(m->vertices[t[0]]), b = v3(m->vertices[t[1]]), c = v3(m->vertices[t[2]]);
    vec3 e1 = vec3_sub(b, a), e2 = vec3_sub(c, a), p = vec3_cross(d, e2);
    double det = vec3_dot(e1, p);
    if (det == 0.0)
        return 0.0;
    vec3 s = vec3_sub(o, a), q = vec3_cross(s, e1);
    double u = vec3_dot(s, p) / det, v = vec3_dot(d, q) / det;
    return fmin(fmin(u, v), 1.0 - u - v);
}

/* |cos| of the angle between the ray and triangle tri's normal. */
static double grazing_cos(const struct mesh *m, uint32_t tri, vec3 d)
{
    const uint32_t *t = m->triangles[tri];
    vec3 a = v3(m->vertices[t[0]]), b = v3(m->vertices[t[1]]), c = v3(m->vertices[t[2]]);
    vec3 n = vec3_cross(vec3_sub(b, a), vec3_sub(c, a));
    return fabs(vec3_dot(vec3_normalize(n), vec3_normalize(d)));
}

/* Length of the interpolated (unnormalised) vertex normal at a C hit: where the three
 * vertex normals diverge it is below 1, and normalising magnifies their coding error. */
static double shade_length(const struct mesh *m, const struct mesh_rt_hit *h)
{
    const uint32_t *t = m->triangles[h->tri];
    const double w[3] = {1.0 - h->b1 - h->b2, h->b1, h->b2};
    vec3 s = {0, 0, 0};
    for (int k = 0; k < 3; k++)
        s = vec3_madd(s, v3(m->rt->normals[t[k]]), w[k]);
    return vec3_length(s);
}

/* A closed, non-convex mesh: an icosphere with every vertex at a random radius. */
static struct mesh *bumpy(void)
{
    struct mesh *ico = NULL;
    struct err e = {0};
    if (mesh_make_icosphere(4, 1.0, &ico, &e) != REFRACT_E_OK)
        return NULL;
    double(*v)[3] = malloc(ico->vertex_count * sizeof *v);
    uint32_t(*t)[3] = malloc(ico->triangle_count * sizeof *t);
    for (size_t i = 0; i < ico->vertex_count; i++)
        for (int k = 0; k < 3; k++)
            v[i][k] = ico->vertices[i][k] * (0.8 + 0.4 * uniform()) + (k == 0 ? 3.0 : 0.5);
    memcpy(t, ico->triangles, ico->triangle_count * sizeof *t);
    struct mesh *m = NULL;
    mesh_create(v, ico->vertex_count, t, ico->triangle_count, NULL, &m, &e);
    mesh_destroy(ico);
    return m;
}

int main(void)
{
    struct gpu *gpu = test_gpu_create("test_mesh_rt_gpu");
    struct mesh *meshes[2] = {NULL, bumpy()};
    struct err e = {0};
    CHECK_INT(mesh_make_icosphere(4, 1.5, &meshes[0], &e), REFRACT_E_OK);
    CHECK(meshes[1] != NULL);
    if (meshes[0] == NULL || meshes[1] == NULL) {
        gpu_destroy(gpu, NULL);
        return test_summary("test_mesh_rt_gpu");
    }
    enum { PER_MESH = 3000, AT_VERTICES = 2000 };
    int n = 2 * PER_MESH + AT_VERTICES;
    int n_all = n + n; /* each ray, then its continuation from the C hit */
    struct cpu_ray *rays = calloc((size_t)n_all, sizeof *rays);
    struct mesh_rt_hit *ref = calloc((size_t)n_all, sizeof *ref);
    bool *ref_hit = calloc((size_t)n_all, sizeof *ref_hit);
    for (int i = 0; i < n; i++) {
        int mi = i < PER_MESH ? 0 : (i < 2 * PER_MESH ? 1 : 0);
        const struct mesh *m = meshes[mi];
        vec3 c = vec3_scale(vec3_add(m->lo, m->hi), 0.5), ext = vec3_sub(m->hi, m->lo);
        vec3 o = vec3_madd(c, unit(), vec3_length(ext) * (0.7 + uniform()));
        vec3 target = vec3_add(c, vec3_make((uniform() - 0.5) * ext.x, (uniform() - 0.5) * ext.y,
                                            (uniform() - 0.5) * ext.z));
        bool at_vertex = i >= 2 * PER_MESH;
        if (at_vertex) /* exactly at a vertex of the icosphere, from outside */
            target = v3(m->vertices[(size_t)(uniform() * (double)m->vertex_count)]);
        /* the float ray the GPU gets, so both trace the same ray */
        vec3 of = vec3_make((float)o.x, (float)o.y, (float)o.z);
        vec3 d = vec3_sub(target, of);
        vec3 df = vec3_make((float)d.x, (float)d.y, (float)d.z);
        double dist = vec3_length(vec3_cross(of, vec3_normalize(df)));
        rays[i] = (struct cpu_ray){of, df, 0.0, -1, mi, at_vertex && dist < 1.5 * 0.99};
        ref_hit[i] = mesh_rt_intersect(m->rt, of, df, 0.0, INFINITY, -1, &ref[i]);
        /* the continuation: from the C hit on, skipping its triangle (tmin in float) */
        struct cpu_ray cont = rays[i];
        if (ref_hit[i]) {
            cont.tmin = (float)ref[i].t;
            cont.skip = ref[i].tri;
        }
        cont.must_hit = false;
        rays[n + i] = cont;
        ref_hit[n + i] =
            mesh_rt_intersect(m->rt, cont.o, cont.d, cont.tmin, INFINITY, cont.skip, &ref[n + i]);
    }
    struct rays_work rw = {.meshes = {meshes[0], meshes[1]}, .rays = rays, .n = n_all};
    rw.out = calloc((size_t)n_all, sizeof *rw.out);
    rw.work = (struct gpu_work){.priority = GPU_PRIORITY_INTERACTIVE, .run = rays_run, .user = &rw};
    CHECK_INT(gpu_run_sync(gpu, &rw.work), REFRACT_E_OK);
    if (rw.work.err.code != REFRACT_E_OK)
        fprintf(stderr, "%s\n", rw.work.err.msg);

    int hits = 0, hit_miss = 0, hit_miss_unexplained = 0, tri_diff = 0, tri_unexplained = 0;
    int bad_t = 0, bad_ng = 0, bad_ns = 0, vertex_leaks = 0, vertex_rays = 0;
    double worst_t = 0, worst_ng = 0, worst_ns = 0, worst_ns_scaled = 0, worst_ns_steep = 0;
    for (int i = 0; i < n_all; i++) {
        const struct cpu_ray *r = &rays[i];
        const struct mesh *m = meshes[r->mesh];
        const struct hit_rec *h = &rw.out[i];
        int32_t gtri;
        memcpy(&gtri, &h->shade[3], sizeof gtri);
        bool ghit = gtri >= 0;
        if (r->must_hit) {
            vertex_rays++;
            vertex_leaks += !ghit;
        }
        if (ghit != ref_hit[i]) {
            hit_miss++;
            uint32_t t = ref_hit[i] ? ref[i].tri : (uint32_t)gtri;
            /* near an edge, or grazing (a silhouette: the ray touches the surface) */
            if (t >= m->triangle_count ||
                (fabs(bary_margin(m, t, r->o, r->d)) > 1e-4 && grazing_cos(m, t, r->d) > 0.01))
                hit_miss_unexplained++;
            continue;
        }
        if (!ghit)
            continue;
        hits++;
        const struct mesh_rt_hit *c = &ref[i];
        if ((uint32_t)gtri != c->tri) {
            tri_diff++;
            /* a near-tie: the ray passes within 1e-4 of an edge of either triangle (at a
             * shared edge or vertex, or a continuation re-hitting the entry's neighbour) */
            if (fmin(fabs(bary_margin(m, c->tri, r->o, r->d)),
                     fabs(bary_margin(m, (uint32_t)gtri, r->o, r->d))) > 1e-4)
                tri_unexplained++;
            continue; /* a different triangle: its normals differ by design */
        }
        double dl = vec3_length(r->d);
        double cosang = fabs(vec3_dot(c->n_geom, r->d)) / dl;
        double dt = fabs(h->t_geom[0] - c->t);
        double rel = dt / c->t;
        worst_t = fmax(worst_t, rel);
        if (rel > 1e-5 && !(cosang < 0.01 && dt * dl * cosang <= 1e-6 * 3.0))
            bad_t++;
        double ang = angle_between(vec3_make(h->t_geom[1], h->t_geom[2], h->t_geom[3]), c->n_geom);
        double ans = angle_between(vec3_make(h->shade[0], h->shade[1], h->shade[2]), c->n_shade);
        worst_ng = fmax(worst_ng, ang);
        double shrink = shade_length(m, c);
        worst_ns = fmax(worst_ns, ans);
        worst_ns_scaled = fmax(worst_ns_scaled, ans * shrink);
        bad_ng += ang > 1e-4;
        /* a grazing hit's point slides along the ray with t (above), and its
         * interpolated normal with it: 1e-3 there */
        bad_ns += ans * fmin(1.0, shrink) > (cosang < 0.01 ? 1e-3 : 1e-4);
        if (cosang >= 0.01)
            worst_ns_steep = fmax(worst_ns_steep, ans * shrink);
    }
    double bpt = (double)rw.gpu_bytes[0] / (double)meshes[0]->triangle_count;
    double bpt1 = (double)rw.gpu_bytes[1] / (double)meshes[1]->triangle_count;
    printf("%d rays (%d continuations), %d hits compared: worst t rel %.2e, geometric normal "
           "%.2e rad, shading normal %.2e rad (times the interpolated length %.2e, %.2e "
           "where |cos| >= 0.01); %d other triangle (%d unexplained), %d hit/miss "
           "(%d unexplained); %d vertex rays, %d leaked\n",
           n_all, n, hits, worst_t, worst_ng, worst_ns, worst_ns_scaled, worst_ns_steep, tri_diff,
           tri_unexplained, hit_miss, hit_miss_unexplained, vertex_rays, vertex_leaks);
    printf("GPU bytes per triangle: icosphere %.1f, bumpy %.1f (nodes + triangles + vertices)\n",
           bpt, bpt1);
    CHECK(hits > n_all / 4);
    CHECK_INT(bad_t, 0);
    CHECK_INT(bad_ng, 0);
    CHECK_INT(bad_ns, 0);
    CHECK_INT(tri_unexplained, 0);
    CHECK_INT(hit_miss_unexplained, 0);
    CHECK(hit_miss * 200 <= n_all);
    CHECK(vertex_rays > AT_VERTICES / 2);
    CHECK_INT(vertex_leaks, 0);
    CHECK(bpt <= 64.0 && bpt1 <= 64.0);
    CHECK(rw.compiled_from_dir >= 0); /* 0 when run by hand without ctest's environment */
    free(rays);
    free(ref);
    free(ref_hit);
    free(rw.out);
    mesh_destroy(meshes[0]);
    mesh_destroy(meshes[1]);
    gpu_destroy(gpu, NULL);
    return test_summary("test_mesh_rt_gpu");
}
