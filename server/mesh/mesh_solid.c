/*
 * mesh_solid.c - whether a mesh can bound a medium (mesh_check_solid), and its signed
 * volume.
 *
 * A surface that separates an inside medium from an outside one must be closed (a ray
 * that enters must leave), manifold (every edge between exactly two faces, so inside is
 * on one side of each face) and consistently wound (so "inside" is the same side
 * everywhere), and its faces must have an area (a zero-area face has no normal to refract
 * about). Each test names the first offender in triangle order, so a user can find it.
 *
 * The edge tests sort the 3n directed edges by their undirected key: O(n log n), about
 * 0.5 s for 1M triangles. Inside-out (negative volume) meshes are common (exporters that
 * mirror an axis) and unambiguous, so they are flipped rather than refused.
 */
#include <math.h>
#include <stdlib.h>

#include "mesh_internal.h"
#include "mesh_rt.h"

double mesh_signed_volume(const struct mesh *m)
{
    /* about the box centre: the terms stay the size of the mesh, not of its position */
    vec3 c0 = vec3_scale(vec3_add(m->lo, m->hi), 0.5);
    double sum = 0.0;
    for (size_t t = 0; t < m->triangle_count; t++) {
        vec3 p[3];
        for (int k = 0; k < 3; k++) {
            const double *v = m->vertices[m->triangles[t][k]];
            p[k] = vec3_make(v[0] - c0.x, v[1] - c0.y, v[2] - c0.z);
        }
        sum += vec3_dot(p[0], vec3_cross(p[1], p[2]));
    }
    return sum / 6.0;
}

struct edge_use {
    uint64_t key;  /* min << 32 | max */
    uint32_t tri;  /* the triangle using it */
    uint32_t a, b; /* its direction in that triangle: a -> b */
};

static int compare_uses(const void *x, const void *y)
{
    const struct edge_use *a = x, *b = y;
    if (a->key != b->key)
        return (a->key > b->key) - (a->key < b->key);
    return (a->tri > b->tri) - (a->tri < b->tri);
}

static enum refract_code degenerate_error(const struct mesh *m, struct err *e)
{
    for (size_t t = 0; t < m->triangle_count; t++) {
        const uint32_t *tr = m->triangles[t];
        const double *a = m->vertices[tr[0]], *b = m->vertices[tr[1]], *c = m->vertices[tr[2]];
        vec3 e1 = vec3_make(b[0] - a[0], b[1] - a[1], b[2] - a[2]);
        vec3 e2 = vec3_make(c[0] - a[0], c[1] - a[1], c[2] - a[2]);
        bool repeated = tr[0] == tr[1] || tr[1] == tr[2] || tr[0] == tr[2];
        /* collinear: sin of the angle at a below 1e-12 (rounding of exactly collinear
         * doubles leaves about 1e-16; a real sliver is far above 1e-12) */
        double cross = vec3_length(vec3_cross(e1, e2));
        if (repeated || !(cross > 1e-12 * vec3_length(e1) * vec3_length(e2)))
            return err_set(e, REFRACT_E_INVALID_MESH,
                           "triangle %zu (vertices %u, %u, %u) has zero area (%s), so it has "
                           "no normal to refract about; remove degenerate faces (merge by "
                           "distance, dissolve degenerate) in the modelling tool and upload "
                           "it again",
                           t, tr[0], tr[1], tr[2],
                           repeated ? "a vertex is repeated" : "its vertices are collinear");
    }
    return REFRACT_E_OK;
}

/* The first offending edge group in triangle order, reported; OK when none. */
static enum refract_code edge_error(const struct edge_use *u, size_t n, struct err *e)
{
    size_t worst = SIZE_MAX, worst_end = 0;
    for (size_t i = 0; i < n;) {
        size_t j = i + 1;
        while (j < n && u[j].key == u[i].key)
            j++;
        bool bad = j - i != 2 || (u[i].a == u[i + 1].a); /* one, three+, or same direction */
        if (bad && (worst == SIZE_MAX || u[i].tri < u[worst].tri)) {
            worst = i;
            worst_end = j;
        }
        i = j;
    }
    if (worst == SIZE_MAX)
        return REFRACT_E_OK;
    const struct edge_use *w = &u[worst];
    size_t uses = worst_end - worst;
    if (uses == 1)
        return err_set(e, REFRACT_E_INVALID_MESH,
                       "edge %u-%u of triangle %u belongs to no other triangle: the mesh is "
                       "open (a hole or a border), so it encloses no medium; close it (fill "
                       "holes in the modelling tool), or use it where an open mesh is allowed "
                       "(a voxelized object)",
                       w->a, w->b, w->tri);
    if (uses > 2)
        return err_set(e, REFRACT_E_INVALID_MESH,
                       "edge %u-%u is shared by %zu triangles (%u, %u, %u%s): the mesh is "
                       "non-manifold there, so its inside is ambiguous; separate the shells "
                       "that touch along this edge so each edge joins exactly two triangles",
                       w->a, w->b, uses, w[0].tri, w[1].tri, w[2].tri, uses > 3 ? ", ..." : "");
    return err_set(e, REFRACT_E_INVALID_MESH,
                   "edge %u-%u is used in the same direction by triangles %u and %u: their "
                   "winding is inconsistent (one of them faces the other way); make the "
                   "normals consistent (recalculate outside) in the modelling tool",
                   w[0].a, w[0].b, w[0].tri, w[1].tri);
}

/* Reverses every triangle's winding: mesh arrays, the tracing hierarchy (triangles,
 * normals, packed vertices) and the winding hierarchy's oriented data (the area vectors
 * and their moments change sign; boxes, centres and radii do not). */
static void flip(struct mesh *m)
{
    for (size_t t = 0; t < m->triangle_count; t++) {
        uint32_t s = m->triangles[t][1];
        m->triangles[t][1] = m->triangles[t][2];
        m->triangles[t][2] = s;
    }
    struct mesh_rt *rt = m->rt;
    if (rt != NULL) {
        for (size_t i = 0; i < rt->tri_count; i++) {
            uint32_t s = rt->tris[i].v[1];
            rt->tris[i].v[1] = rt->tris[i].v[2];
            rt->tris[i].v[2] = s;
        }
        for (size_t v = 0; v < rt->vertex_count; v++)
            for (int k = 0; k < 3; k++)
                rt->normals[v][k] = -rt->normals[v][k];
        mesh_rt_pack_vertices(rt);
    }
    if (m->bvh != NULL) {
        for (size_t i = 0; i < m->bvh->node_count; i++) {
            struct mesh_bvh_node *nd = &m->bvh->nodes[i];
            for (int r = 0; r < 3; r++) {
                nd->area_normal[r] = -nd->area_normal[r];
                for (int c = 0; c < 3; c++)
                    nd->moment[r][c] = -nd->moment[r][c];
            }
        }
    }
}

enum refract_code mesh_check_solid(struct mesh *m, bool *flipped, struct err *e)
{
    bool inside_out = false;
    *flipped = false;
    enum refract_code rc = mesh_solid_status(m, &inside_out, e);
    if (rc == REFRACT_E_OK && inside_out) {
        flip(m);
        *flipped = true;
    }
    return rc;
}

enum refract_code mesh_solid_status(const struct mesh *m, bool *inside_out, struct err *e)
{
    *inside_out = false;
    enum refract_code rc = degenerate_error(m, e);
    if (rc != REFRACT_E_OK)
        return rc;
    size_t n = 3 * m->triangle_count;
    struct edge_use *u = malloc(n * sizeof *u);
    if (u == NULL)
        return err_set(e, REFRACT_E_OUT_OF_MEMORY,
                       "out of memory checking the edges of a mesh of %zu triangles",
                       m->triangle_count);
    for (size_t t = 0; t < m->triangle_count; t++) {
        for (int c = 0; c < 3; c++) {
            uint32_t a = m->triangles[t][c], b = m->triangles[t][(c + 1) % 3];
            uint64_t lo = a < b ? a : b, hi = a < b ? b : a;
            u[3 * t + (size_t)c] = (struct edge_use){lo << 32 | hi, (uint32_t)t, a, b};
        }
    }
    qsort(u, n, sizeof *u, compare_uses);
    rc = edge_error(u, n, e);
    free(u);
    if (rc != REFRACT_E_OK)
        return rc;
    double vol = mesh_signed_volume(m);
    vec3 ext = vec3_sub(m->hi, m->lo);
    double scale = ext.x * ext.y * ext.z;
    if (!(fabs(vol) > 1e-12 * scale))
        return err_set(e, REFRACT_E_INVALID_MESH,
                       "the mesh is closed but encloses no volume (signed volume %g, its box "
                       "%g): its faces cancel out (coincident or self-intersecting shells); "
                       "upload a mesh that bounds a solid",
                       vol, scale);
    *inside_out = vol < 0.0;
    return REFRACT_E_OK;
}
