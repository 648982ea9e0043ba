/* The body: entity arrays, incidence index, adjacency queries, summaries. */
#include <stdlib.h>
#include <string.h>

#include "brep/topo.h"

cb_topo_body *cb_topo_body_new(void)
{
    cb_topo_body *b = calloc(1, sizeof *b);
    if (b)
        b->length_unit_mm = 1.0;
    return b;
}

void cb_topo_body_transform(cb_topo_body *b, const cb_xform *x)
{
    for (int k = 0; k < b->n_vertices; k++)
        cb_xform_apply_point(b->vertices[k].p, x, b->vertices[k].p);
    for (int k = 0; k < b->n_curves; k++)
        cb_topo_curve_transform(&b->curves[k], x);
    for (int k = 0; k < b->n_surfaces; k++)
        cb_topo_surface_transform(&b->surfaces[k], x);
}

void cb_topo_body_free(cb_topo_body *b)
{
    if (!b)
        return;
    for (int k = 0; k < b->n_curves; k++)
        cb_topo_curve_clear(&b->curves[k]);
    for (int k = 0; k < b->n_pcurves; k++)
        cb_topo_curve_clear(&b->pcurves[k]);
    for (int k = 0; k < b->n_surfaces; k++)
        cb_topo_surface_clear(&b->surfaces[k]);
    free(b->vertices);
    free(b->edges);
    free(b->coedges);
    free(b->loops);
    free(b->faces);
    free(b->shells);
    free(b->solids);
    free(b->curves);
    free(b->pcurves);
    free(b->surfaces);
    free(b->edge_start);
    free(b->edge_coedges);
    free(b->vertex_start);
    free(b->vertex_edges);
    free(b);
}

/* Drops the incidence index, which any change of the entity arrays makes stale. */
static void drop_index(cb_topo_body *b)
{
    free(b->edge_start);
    free(b->edge_coedges);
    free(b->vertex_start);
    free(b->vertex_edges);
    b->edge_start = b->edge_coedges = b->vertex_start = b->vertex_edges = NULL;
}

/* Appends one zeroed element of size sz to *arr (count *n, capacity *cap). */
static int append(void **arr, int *n, int *cap, size_t sz)
{
    if (*n == *cap) {
        if (*cap > (1 << 28))
            return -1;
        int c = *cap ? 2 * *cap : 16;
        void *p = realloc(*arr, (size_t)c * sz);
        if (!p)
            return -1;
        *arr = p;
        *cap = c;
    }
    memset((char *)*arr + (size_t)*n * sz, 0, sz);
    return (*n)++;
}

#define APPENDER(fn, field, count, slot)                                                           \
    int fn(cb_topo_body *b)                                                                        \
    {                                                                                              \
        drop_index(b);                                                                             \
        return append((void **)&b->field, &b->count, &b->cap[slot], sizeof *b->field);             \
    }
APPENDER(cb_topo_body_add_vertex, vertices, n_vertices, 0)
APPENDER(cb_topo_body_add_edge, edges, n_edges, 1)
APPENDER(cb_topo_body_add_coedge, coedges, n_coedges, 2)
APPENDER(cb_topo_body_add_loop, loops, n_loops, 3)
APPENDER(cb_topo_body_add_face, faces, n_faces, 4)
APPENDER(cb_topo_body_add_shell, shells, n_shells, 5)
APPENDER(cb_topo_body_add_solid, solids, n_solids, 6)
#undef APPENDER

int cb_topo_body_add_curve(cb_topo_body *b)
{
    int k = append((void **)&b->curves, &b->n_curves, &b->cap[7], sizeof *b->curves);
    if (k >= 0)
        cb_topo_curve_init(&b->curves[k]);
    return k;
}

int cb_topo_body_add_pcurve(cb_topo_body *b)
{
    int k = append((void **)&b->pcurves, &b->n_pcurves, &b->cap[8], sizeof *b->pcurves);
    if (k >= 0)
        cb_topo_curve_init(&b->pcurves[k]);
    return k;
}

int cb_topo_body_add_surface(cb_topo_body *b)
{
    int k = append((void **)&b->surfaces, &b->n_surfaces, &b->cap[9], sizeof *b->surfaces);
    if (k >= 0)
        cb_topo_surface_init(&b->surfaces[k]);
    return k;
}

/* ---------------------------------------------------------------- index -------------------- */

static int in_range(int i, int n) { return i >= 0 && i < n; }

/* Checks that the ranges [first, first + count) fit in n. */
static cb_status check_range(int first, int count, int n, const char *what, int k,
                             const char *child, cb_error *err)
{
    if (first < 0 || count < 0 || first > n - count)
        return cb_error_set(err, CB_ERR_INVALID, "%s %d: %s range [%d, %d) outside [0, %d)", what,
                            k, child, first, first + count, n);
    return CB_OK;
}

static cb_status check_indices(const cb_topo_body *b, cb_error *err)
{
    cb_status st = CB_OK;
    for (int k = 0; k < b->n_edges && !st; k++) {
        const cb_topo_edge *e = &b->edges[k];
        if (!in_range(e->curve, b->n_curves) || !in_range(e->v[0], b->n_vertices) ||
            !in_range(e->v[1], b->n_vertices))
            st =
                cb_error_set(err, CB_ERR_INVALID, "edge %d: curve or vertex index out of range", k);
    }
    for (int k = 0; k < b->n_coedges && !st; k++) {
        const cb_topo_coedge *c = &b->coedges[k];
        if (!in_range(c->edge, b->n_edges) || !in_range(c->loop, b->n_loops) ||
            (c->pcurve != -1 && !in_range(c->pcurve, b->n_pcurves)))
            st = cb_error_set(err, CB_ERR_INVALID,
                              "coedge %d: edge, loop or pcurve index out of range", k);
    }
    for (int k = 0; k < b->n_loops && !st; k++) {
        st = check_range(b->loops[k].first, b->loops[k].count, b->n_coedges, "loop", k, "coedge",
                         err);
        if (!st && !in_range(b->loops[k].face, b->n_faces))
            st = cb_error_set(err, CB_ERR_INVALID, "loop %d: face index out of range", k);
    }
    for (int k = 0; k < b->n_faces && !st; k++) {
        st = check_range(b->faces[k].first, b->faces[k].count, b->n_loops, "face", k, "loop", err);
        if (!st && (!in_range(b->faces[k].surface, b->n_surfaces) ||
                    !in_range(b->faces[k].shell, b->n_shells)))
            st = cb_error_set(err, CB_ERR_INVALID, "face %d: surface or shell index out of range",
                              k);
    }
    for (int k = 0; k < b->n_shells && !st; k++) {
        st = check_range(b->shells[k].first, b->shells[k].count, b->n_faces, "shell", k, "face",
                         err);
        if (!st && b->shells[k].solid != -1 && !in_range(b->shells[k].solid, b->n_solids))
            st = cb_error_set(err, CB_ERR_INVALID, "shell %d: solid index out of range", k);
    }
    for (int k = 0; k < b->n_solids && !st; k++)
        st = check_range(b->solids[k].first, b->solids[k].count, b->n_shells, "solid", k, "shell",
                         err);
    return st;
}

/* Counting sort of (key, value) pairs into start[0 .. n_keys] and vals. */
static cb_status bucket(int **start, int **vals, int n_keys, const int *keys, const int *values,
                        int n_pairs, cb_error *err)
{
    int *s = calloc((size_t)n_keys + 1, sizeof *s), *v = malloc(((size_t)n_pairs + 1) * sizeof *v);
    if (!s || !v) {
        free(s);
        free(v);
        return cb_error_set(err, CB_ERR_NOMEM, "topology index: out of memory");
    }
    for (int k = 0; k < n_pairs; k++)
        s[keys[k] + 1]++;
    for (int k = 0; k < n_keys; k++)
        s[k + 1] += s[k];
    int *fill = malloc(((size_t)n_keys + 1) * sizeof *fill);
    if (!fill) {
        free(s);
        free(v);
        return cb_error_set(err, CB_ERR_NOMEM, "topology index: out of memory");
    }
    memcpy(fill, s, ((size_t)n_keys + 1) * sizeof *fill);
    for (int k = 0; k < n_pairs; k++)
        v[fill[keys[k]]++] = values[k];
    free(fill);
    *start = s;
    *vals = v;
    return CB_OK;
}

cb_status cb_topo_body_index(cb_topo_body *b, cb_error *err)
{
    drop_index(b);
    cb_status st = check_indices(b, err);
    if (st)
        return st;
    int n = b->n_coedges > 2 * b->n_edges ? b->n_coedges : 2 * b->n_edges;
    int *keys = malloc(((size_t)n + 1) * sizeof *keys),
        *vals = malloc(((size_t)n + 1) * sizeof *vals);
    if (!keys || !vals) {
        free(keys);
        free(vals);
        return cb_error_set(err, CB_ERR_NOMEM, "topology index: out of memory");
    }
    for (int k = 0; k < b->n_coedges; k++) {
        keys[k] = b->coedges[k].edge;
        vals[k] = k;
    }
    st = bucket(&b->edge_start, &b->edge_coedges, b->n_edges, keys, vals, b->n_coedges, err);
    int m = 0;
    for (int k = 0; k < b->n_edges; k++)
        for (int j = 0; j < 2; j++)
            if (!j || b->edges[k].v[1] != b->edges[k].v[0]) {
                keys[m] = b->edges[k].v[j];
                vals[m++] = k;
            }
    if (!st)
        st = bucket(&b->vertex_start, &b->vertex_edges, b->n_vertices, keys, vals, m, err);
    free(keys);
    free(vals);
    if (st)
        drop_index(b);
    return st;
}

/* ---------------------------------------------------------------- queries ------------------ */

static int int_cmp(const void *a, const void *b)
{
    int x = *(const int *)a, y = *(const int *)b;
    return (x > y) - (x < y);
}

/* Sorts and dedups tmp[0 .. n), drops `skip`, copies at most max to out; returns the count. */
static int emit(int *out, int max, int *tmp, int n, int skip)
{
    qsort(tmp, (size_t)n, sizeof *tmp, int_cmp);
    int m = 0;
    for (int k = 0; k < n; k++)
        if ((k == 0 || tmp[k] != tmp[k - 1]) && tmp[k] != skip) {
            if (m < max)
                out[m] = tmp[k];
            m++;
        }
    return m;
}

int cb_topo_edge_faces(int *out, int max, const cb_topo_body *b, int edge)
{
    int first = b->edge_start[edge], n = b->edge_start[edge + 1] - first;
    int small[16], *tmp = n <= 16 ? small : malloc((size_t)n * sizeof *tmp);
    if (!tmp)
        return -1;
    for (int k = 0; k < n; k++)
        tmp[k] = b->loops[b->coedges[b->edge_coedges[first + k]].loop].face;
    int m = emit(out, max, tmp, n, -1);
    if (tmp != small)
        free(tmp);
    return m;
}

int cb_topo_vertex_edges(int *out, int max, const cb_topo_body *b, int vertex)
{
    int first = b->vertex_start[vertex], n = b->vertex_start[vertex + 1] - first;
    for (int k = 0; k < n && k < max; k++)
        out[k] = b->vertex_edges[first + k];
    return n;
}

int cb_topo_face_neighbours(int *out, int max, const cb_topo_body *b, int face)
{
    const cb_topo_face *f = &b->faces[face];
    int n = 0;
    for (int l = f->first; l < f->first + f->count; l++)
        for (int c = b->loops[l].first; c < b->loops[l].first + b->loops[l].count; c++) {
            int e = b->coedges[c].edge;
            n += b->edge_start[e + 1] - b->edge_start[e];
        }
    int *tmp = malloc(((size_t)n + 1) * sizeof *tmp), m = 0;
    if (!tmp)
        return -1;
    for (int l = f->first; l < f->first + f->count; l++)
        for (int c = b->loops[l].first; c < b->loops[l].first + b->loops[l].count; c++) {
            int e = b->coedges[c].edge;
            for (int k = b->edge_start[e]; k < b->edge_start[e + 1]; k++)
                tmp[m++] = b->loops[b->coedges[b->edge_coedges[k]].loop].face;
        }
    int r = emit(out, max, tmp, m, face);
    free(tmp);
    return r;
}

void cb_topo_coedge_ends(double start[3], double end[3], const cb_topo_body *b, int coedge)
{
    const cb_topo_coedge *c = &b->coedges[coedge];
    const cb_topo_edge *e = &b->edges[c->edge];
    const cb_topo_curve *cv = &b->curves[e->curve];
    int forward = c->sense == e->same_sense;
    cb_topo_curve_eval(start, cv, forward ? e->t0 : e->t1);
    cb_topo_curve_eval(end, cv, forward ? e->t1 : e->t0);
}

void cb_topo_body_edge_box(cb_aabb *box, const cb_topo_body *b)
{
    for (int i = 0; i < 3; i++) {
        box->lo[i] = HUGE_VAL;
        box->hi[i] = -HUGE_VAL;
    }
    for (int k = 0; k < b->n_vertices + b->n_edges * 17; k++) {
        double p[3];
        if (k < b->n_vertices) {
            memcpy(p, b->vertices[k].p, sizeof p);
        } else {
            int e = (k - b->n_vertices) / 17, j = (k - b->n_vertices) % 17;
            const cb_topo_edge *ed = &b->edges[e];
            cb_topo_curve_eval(p, &b->curves[ed->curve], ed->t0 + (ed->t1 - ed->t0) * j / 16.0);
        }
        for (int i = 0; i < 3; i++) {
            box->lo[i] = fmin(box->lo[i], p[i]);
            box->hi[i] = fmax(box->hi[i], p[i]);
        }
    }
}

int cb_topo_body_surface_types(const char *names[8], int counts[8], const cb_topo_body *b)
{
    int n = 0;
    for (int k = 0; k < b->n_faces; k++) {
        const char *name = cb_topo_surface_type_name(&b->surfaces[b->faces[k].surface]);
        int j = 0;
        while (j < n && strcmp(names[j], name))
            j++;
        if (j == n) {
            if (n == 8)
                continue;
            names[n] = name;
            counts[n++] = 0;
        }
        counts[j]++;
    }
    return n;
}

double cb_topo_edge_length(const cb_topo_body *b, int e)
{
    const cb_topo_edge *ed = &b->edges[e];
    double prev[3], len = 0;
    for (int k = 0; k <= 16; k++) {
        double p[3];
        cb_topo_curve_eval(p, &b->curves[ed->curve], ed->t0 + (ed->t1 - ed->t0) * k / 16.0);
        if (k)
            len += cb_vec3_dist(p, prev);
        memcpy(prev, p, sizeof p);
    }
    return len;
}
