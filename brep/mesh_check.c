/* mesh_check.c — the combinatorial checks of mesh_check.h on the triangle soup; the geometric
 * ones are CGAL's, in tess_check_cgal.cpp. */
#include "brep/mesh_check.h"

#include <math.h>
#include <stdlib.h>

#include "brep/tess_check_cgal.h"

/* Three ints compared lexicographically: an edge (lo, hi, direction) or a corner (vertex,
 * neighbour, triangle). */
typedef struct {
    int k[3];
} triple;

static int triple_cmp(const void *x, const void *y)
{
    const triple *a = x, *b = y;
    for (int i = 0; i < 3; i++)
        if (a->k[i] != b->k[i])
            return a->k[i] < b->k[i] ? -1 : 1;
    return 0;
}

static int uf_find(int *parent, int t)
{
    while (parent[t] != t) {
        parent[t] = parent[parent[t]];
        t = parent[t];
    }
    return t;
}

/* Counts boundary, non-manifold and misoriented edges: every triangle side as (lo, hi, +1 when
 * the triangle runs lo -> hi), sorted so that the sides of one edge are adjacent. */
static void count_edges(cb_mesh_check_report *r, const cb_mesh_t m, triple *e)
{
    size_t n = 3 * (size_t)m->n_triangles;
    for (size_t f = 0; f < (size_t)m->n_triangles; f++)
        for (int s = 0; s < 3; s++) {
            int a = m->tri[3 * f + s], b = m->tri[3 * f + (s + 1) % 3];
            e[3 * f + s] = (triple){{a < b ? a : b, a < b ? b : a, a < b ? 1 : -1}};
        }
    qsort(e, n, sizeof *e, triple_cmp);
    for (size_t i = 0, j; i < n; i = j) {
        for (j = i + 1; j < n && e[j].k[0] == e[i].k[0] && e[j].k[1] == e[i].k[1]; j++)
            ;
        if (j - i == 1)
            r->boundary_edges++;
        else if (j - i > 2)
            r->nonmanifold_edges++;
        else if (e[i].k[2] == e[i + 1].k[2])
            r->misoriented_edges++;
    }
}

/* Counts vertices whose triangles form more than one fan. Each corner (v, f) gives two entries
 * (v, w, f), one per neighbour w of v in f; sorted, the triangles around v that share the edge
 * vw are adjacent and are joined in a union-find over triangles, which is reset after each
 * vertex so that fans only connect through edges at that vertex. */
static void count_fans(cb_mesh_check_report *r, const cb_mesh_t m, triple *c, int *parent)
{
    size_t n = 6 * (size_t)m->n_triangles;
    for (size_t f = 0; f < (size_t)m->n_triangles; f++) {
        parent[f] = (int)f;
        for (int s = 0; s < 3; s++) {
            int v = m->tri[3 * f + s];
            c[6 * f + 2 * s] = (triple){{v, m->tri[3 * f + (s + 1) % 3], (int)f}};
            c[6 * f + 2 * s + 1] = (triple){{v, m->tri[3 * f + (s + 2) % 3], (int)f}};
        }
    }
    qsort(c, n, sizeof *c, triple_cmp);
    for (size_t i = 0, j; i < n; i = j) {
        for (j = i + 1; j < n && c[j].k[0] == c[i].k[0]; j++)
            if (c[j].k[1] == c[j - 1].k[1])
                parent[uf_find(parent, c[j].k[2])] = uf_find(parent, c[j - 1].k[2]);
        /* Every triangle at the vertex appears twice, so each fan's root does too. */
        size_t roots = 0;
        for (size_t k = i; k < j; k++)
            roots += uf_find(parent, c[k].k[2]) == c[k].k[2];
        if (roots > 2)
            r->nonmanifold_vertices++;
        for (size_t k = i; k < j; k++)
            parent[c[k].k[2]] = c[k].k[2];
    }
}

cb_status cb_mesh_check(cb_mesh_check_report *r, const cb_mesh_t m, cb_error *err)
{
    *r = (cb_mesh_check_report){.vertices = m->n_vertices,
                                .triangles = m->n_triangles,
                                .triangle_mesh = -1,
                                .self_intersections = -1,
                                .bounds_volume = -1,
                                .outward = -1,
                                .volume = NAN};
    size_t nt = (size_t)m->n_triangles;
    triple *work = malloc((6 * nt + 1) * sizeof *work);
    int *parent = malloc((nt + 1) * sizeof *parent);
    if (!work || !parent) {
        free(work);
        free(parent);
        return cb_error_set(err, CB_ERR_NOMEM, "mesh check: no memory for %zu triangles", nt);
    }
    count_edges(r, m, work);
    count_fans(r, m, work, parent);
    free(work);
    free(parent);
    r->closed = nt > 0 && r->boundary_edges == 0 && r->nonmanifold_edges == 0;
    r->edge_manifold = r->nonmanifold_edges == 0;
    r->vertex_manifold = r->nonmanifold_vertices == 0;
    r->oriented = r->misoriented_edges == 0;
    if (!r->edge_manifold || !r->vertex_manifold || !r->oriented || nt == 0)
        return CB_OK;
    return cb_tess_check_cgal(r, m, err);
}

/* CB_OK when m is closed, edge-manifold and consistently oriented and eps a positive distance,
 * as the contact checks need. */
static cb_status contacts_ready(const cb_mesh_t m, double eps, cb_error *err)
{
    if (!(eps > 0) || !isfinite(eps))
        return cb_error_set(err, CB_ERR_INVALID, "mesh contacts: eps %g is not a positive distance",
                            eps);
    cb_mesh_check_report r = {0};
    triple *work = malloc((3 * (size_t)m->n_triangles + 1) * sizeof *work);
    if (!work)
        return cb_error_set(err, CB_ERR_NOMEM, "mesh contacts: no memory for %d triangles",
                            m->n_triangles);
    count_edges(&r, m, work);
    free(work);
    if (m->n_triangles == 0 || r.boundary_edges || r.nonmanifold_edges || r.misoriented_edges)
        return cb_error_set(err, CB_ERR_INVALID,
                            "mesh contacts: the mesh is not closed, edge-manifold and oriented "
                            "(%d triangles; %d boundary, %d non-manifold, %d misoriented edges)",
                            m->n_triangles, r.boundary_edges, r.nonmanifold_edges,
                            r.misoriented_edges);
    return CB_OK;
}

cb_status cb_mesh_check_contacts(cb_mesh_contacts *c, const cb_mesh_t m, double eps,
                                 cb_error *err)
{
    c->touching = c->crossing = -1;
    cb_status st = contacts_ready(m, eps, err);
    return st ? st : cb_tess_check_cgal_contacts(&c->touching, &c->crossing, NULL, m, eps, err);
}

cb_status cb_mesh_check_crossings(int **pairs, int *n_pairs, const cb_mesh_t m, double eps,
                                  cb_error *err)
{
    *pairs = NULL;
    *n_pairs = 0;
    int touching;
    cb_status st = contacts_ready(m, eps, err);
    if (!st)
        st = cb_tess_check_cgal_contacts(&touching, n_pairs, pairs, m, eps, err);
    if (st) {
        free(*pairs);
        *pairs = NULL;
        *n_pairs = 0;
    }
    return st;
}

int cb_mesh_check_passed(const cb_mesh_check_report *r)
{
    return r->closed == 1 && r->edge_manifold == 1 && r->vertex_manifold == 1 &&
           r->oriented == 1 && r->triangle_mesh == 1 && r->self_intersections == 0 &&
           r->bounds_volume == 1 && r->outward == 1;
}
