/* mesh.c — the triangle mesh value type: storage, measures, vertex merging. */
#include "brep/mesh.h"

#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

void cb_mesh_init(cb_mesh_t m)
{
    memset(m, 0, sizeof *m);
}

void cb_mesh_clear(cb_mesh_t m)
{
    free(m->xyz);
    free(m->tri);
    cb_mesh_init(m);
}

cb_status cb_mesh_reserve(cb_mesh_t m, int nv, int nt, cb_error *err)
{
    if (nv < 0 || nt < 0)
        return cb_error_set(err, CB_ERR_INVALID, "mesh: cannot reserve %d vertices, %d triangles",
                            nv, nt);
    if (nv > m->cap_vertices) {
        double *p = realloc(m->xyz, 3 * (size_t)nv * sizeof *p);
        if (!p)
            return cb_error_set(err, CB_ERR_NOMEM, "mesh: no memory for %d vertices", nv);
        m->xyz = p;
        m->cap_vertices = nv;
    }
    if (nt > m->cap_triangles) {
        int *t = realloc(m->tri, 3 * (size_t)nt * sizeof *t);
        if (!t)
            return cb_error_set(err, CB_ERR_NOMEM, "mesh: no memory for %d triangles", nt);
        m->tri = t;
        m->cap_triangles = nt;
    }
    return CB_OK;
}

/* Capacity for one more than n: doubling keeps appends amortised O(1). */
static int grown(int n)
{
    return n < 16 ? 16 : n > INT_MAX / 2 ? INT_MAX : 2 * n;
}

cb_status cb_mesh_append_vertex(cb_mesh_t m, const double p[3], cb_error *err)
{
    if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2]))
        return cb_error_set(err, CB_ERR_INVALID, "mesh: vertex %d has a non-finite coordinate",
                            m->n_vertices);
    if (m->n_vertices == INT_MAX)
        return cb_error_set(err, CB_ERR_NOMEM, "mesh: more than %d vertices", INT_MAX);
    if (m->n_vertices == m->cap_vertices) {
        cb_status st = cb_mesh_reserve(m, grown(m->n_vertices), m->cap_triangles, err);
        if (st)
            return st;
    }
    memcpy(m->xyz + 3 * (size_t)m->n_vertices++, p, 3 * sizeof *p);
    return CB_OK;
}

cb_status cb_mesh_append_triangle(cb_mesh_t m, int a, int b, int c, cb_error *err)
{
    int n = m->n_vertices;
    if (a < 0 || a >= n || b < 0 || b >= n || c < 0 || c >= n)
        return cb_error_set(err, CB_ERR_INVALID,
                            "mesh: triangle %d (%d, %d, %d) refers to a vertex outside 0..%d",
                            m->n_triangles, a, b, c, n - 1);
    if (a == b || b == c || c == a)
        return cb_error_set(err, CB_ERR_INVALID, "mesh: triangle %d (%d, %d, %d) repeats a vertex",
                            m->n_triangles, a, b, c);
    if (m->n_triangles == INT_MAX)
        return cb_error_set(err, CB_ERR_NOMEM, "mesh: more than %d triangles", INT_MAX);
    if (m->n_triangles == m->cap_triangles) {
        cb_status st = cb_mesh_reserve(m, m->cap_vertices, grown(m->n_triangles), err);
        if (st)
            return st;
    }
    int *t = m->tri + 3 * (size_t)m->n_triangles++;
    t[0] = a;
    t[1] = b;
    t[2] = c;
    return CB_OK;
}

cb_status cb_mesh_append(cb_mesh_t dst, const cb_mesh_t src, cb_error *err)
{
    if ((long long)dst->n_vertices + src->n_vertices > INT_MAX ||
        (long long)dst->n_triangles + src->n_triangles > INT_MAX)
        return cb_error_set(err, CB_ERR_NOMEM, "mesh: appending exceeds %d elements", INT_MAX);
    cb_status st = cb_mesh_reserve(dst, dst->n_vertices + src->n_vertices,
                                   dst->n_triangles + src->n_triangles, err);
    if (st)
        return st;
    int off = dst->n_vertices;
    memcpy(dst->xyz + 3 * (size_t)off, src->xyz, 3 * (size_t)src->n_vertices * sizeof *src->xyz);
    int *t = dst->tri + 3 * (size_t)dst->n_triangles;
    for (size_t k = 0; k < 3 * (size_t)src->n_triangles; k++)
        t[k] = src->tri[k] + off;
    dst->n_vertices += src->n_vertices;
    dst->n_triangles += src->n_triangles;
    return CB_OK;
}

void cb_mesh_bbox(cb_aabb *box, const cb_mesh_t m)
{
    cb_aabb_of_points(box, m->xyz, (size_t)m->n_vertices, 3);
}

double cb_mesh_volume(const cb_mesh_t m)
{
    if (m->n_triangles == 0)
        return 0;
    cb_aabb box;
    cb_mesh_bbox(&box, m);
    double c[3];
    for (int k = 0; k < 3; k++)
        c[k] = 0.5 * (box.lo[k] + box.hi[k]);
    double six_v = 0;
    for (int f = 0; f < m->n_triangles; f++) {
        const int *t = m->tri + 3 * (size_t)f;
        double a[3], b[3], d[3];
        for (int k = 0; k < 3; k++) {
            a[k] = m->xyz[3 * (size_t)t[0] + k] - c[k];
            b[k] = m->xyz[3 * (size_t)t[1] + k] - c[k];
            d[k] = m->xyz[3 * (size_t)t[2] + k] - c[k];
        }
        six_v += a[0] * (b[1] * d[2] - b[2] * d[1]) + a[1] * (b[2] * d[0] - b[0] * d[2]) +
                 a[2] * (b[0] * d[1] - b[1] * d[0]);
    }
    return six_v / 6;
}

double cb_mesh_area(const cb_mesh_t m)
{
    double area = 0;
    for (int f = 0; f < m->n_triangles; f++) {
        const int *t = m->tri + 3 * (size_t)f;
        const double *p = m->xyz + 3 * (size_t)t[0], *q = m->xyz + 3 * (size_t)t[1],
                     *r = m->xyz + 3 * (size_t)t[2];
        double u[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
        double v[3] = {r[0] - p[0], r[1] - p[1], r[2] - p[2]};
        double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                       u[0] * v[1] - u[1] * v[0]};
        area += 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    }
    return area;
}

/* ---------------------------------------------------------------- vertex merging ----------- */

typedef struct {
    int64_t cell[3];
    int v;
} cell_entry;

static int cell_cmp(const int64_t a[3], const int64_t b[3])
{
    for (int k = 0; k < 3; k++)
        if (a[k] != b[k])
            return a[k] < b[k] ? -1 : 1;
    return 0;
}

static int entry_cmp(const void *x, const void *y)
{
    const cell_entry *a = x, *b = y;
    int c = cell_cmp(a->cell, b->cell);
    return c ? c : (a->v > b->v) - (a->v < b->v);
}

/* First entry whose cell is not below key. */
static size_t lower_bound(const cell_entry *e, size_t n, const int64_t key[3])
{
    size_t lo = 0, hi = n;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (cell_cmp(e[mid].cell, key) < 0)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

static int find_root(int *parent, int v)
{
    while (parent[v] != v) {
        parent[v] = parent[parent[v]];
        v = parent[v];
    }
    return v;
}

/* Order-preserving integer image of a double, so that with tol = 0 a "cell" is one exact point
 * (adding 0.0 first makes -0 and +0 the same point). */
static int64_t ordered_bits(double x)
{
    x += 0.0;
    int64_t i;
    memcpy(&i, &x, sizeof i);
    return i < 0 ? INT64_MIN - i - 1 : i;
}

cb_status cb_mesh_merge_vertices(cb_mesh_t m, double tol, int *collapsed, cb_error *err)
{
    if (!(tol >= 0) || !isfinite(tol))
        return cb_error_set(err, CB_ERR_INVALID, "mesh: merge tolerance %g is not a finite "
                                                 "number >= 0", tol);
    int n = m->n_vertices;
    cb_aabb box;
    cb_mesh_bbox(&box, m);
    for (int k = 0; k < 3 && n > 0 && tol > 0; k++)
        if ((box.hi[k] - box.lo[k]) / tol >= 0x1p62)
            return cb_error_set(err, CB_ERR_INVALID,
                                "mesh: merge tolerance %g is too small for a mesh %g wide", tol,
                                box.hi[k] - box.lo[k]);
    cell_entry *e = malloc(((size_t)n + 1) * sizeof *e);
    int *parent = malloc(((size_t)n + 1) * sizeof *parent);
    if (!e || !parent) {
        free(e);
        free(parent);
        return cb_error_set(err, CB_ERR_NOMEM, "mesh: no memory to merge %d vertices", n);
    }
    for (int v = 0; v < n; v++) {
        const double *p = m->xyz + 3 * (size_t)v;
        for (int k = 0; k < 3; k++)
            e[v].cell[k] = tol > 0 ? (int64_t)floor((p[k] - box.lo[k]) / tol) : ordered_bits(p[k]);
        e[v].v = v;
        parent[v] = v;
    }
    qsort(e, (size_t)n, sizeof *e, entry_cmp);
    /* Close points lie in the same or adjacent cells; with tol = 0 only the same "cell". */
    int reach = tol > 0 ? 1 : 0;
    double tol2 = tol * tol;
    for (int i = 0; i < n; i++) {
        const double *p = m->xyz + 3 * (size_t)e[i].v;
        for (int dx = -reach; dx <= reach; dx++)
            for (int dy = -reach; dy <= reach; dy++)
                for (int dz = -reach; dz <= reach; dz++) {
                    int64_t key[3] = {e[i].cell[0] + dx, e[i].cell[1] + dy, e[i].cell[2] + dz};
                    for (size_t j = lower_bound(e, (size_t)n, key);
                         j < (size_t)n && !cell_cmp(e[j].cell, key); j++) {
                        const double *q = m->xyz + 3 * (size_t)e[j].v;
                        double d2 = (p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
                                    (p[2] - q[2]) * (p[2] - q[2]);
                        if (d2 > tol2)
                            continue;
                        int a = find_root(parent, e[i].v), b = find_root(parent, e[j].v);
                        if (a < b)
                            parent[b] = a;
                        else
                            parent[a] = b;
                    }
                }
    }
    /* Roots are the lowest index of their group, so a root precedes every vertex it absorbs and
     * the compaction below only ever moves data towards the front. */
    int *renum = (int *)e; /* e is no longer needed and holds at least n ints */
    int nv = 0;
    for (int v = 0; v < n; v++) {
        int r = find_root(parent, v);
        if (r == v) {
            memmove(m->xyz + 3 * (size_t)nv, m->xyz + 3 * (size_t)v, 3 * sizeof *m->xyz);
            renum[v] = nv++;
        } else {
            renum[v] = renum[r];
        }
    }
    int nt = 0;
    for (int f = 0; f < m->n_triangles; f++) {
        const int *t = m->tri + 3 * (size_t)f;
        int a = renum[t[0]], b = renum[t[1]], c = renum[t[2]];
        if (a == b || b == c || c == a)
            continue;
        int *u = m->tri + 3 * (size_t)nt++;
        u[0] = a;
        u[1] = b;
        u[2] = c;
    }
    if (collapsed)
        *collapsed = m->n_triangles - nt;
    m->n_vertices = nv;
    m->n_triangles = nt;
    free(e);
    free(parent);
    return CB_OK;
}
