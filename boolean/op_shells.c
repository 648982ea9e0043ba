/* op_shells.c — the result's faces grouped into shells (connected by shared edges) and the
 * shells into solids: an outer shell each, with the voids it holds (_cb_bool_split_shells). */
#include "boolean/op_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static int find(int *parent, int x)
{
    while (parent[x] != x) {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    return x;
}

/* Moves the faces into the order `order` (order[i]: the old index of the face now at i). */
static cb_status permute_faces(cb_topo_body *b, const int *order, cb_error *err)
{
    int n = b->n_faces;
    cb_topo_face *copy = malloc((size_t)n * sizeof *copy);
    int *pos = malloc((size_t)n * sizeof *pos);
    if (!copy || !pos) {
        free(copy);
        free(pos);
        return cb_error_set(err, CB_ERR_NOMEM, "bool: out of memory");
    }
    memcpy(copy, b->faces, (size_t)n * sizeof *copy);
    for (int i = 0; i < n; i++) {
        b->faces[i] = copy[order[i]];
        pos[order[i]] = i;
    }
    for (int l = 0; l < b->n_loops; l++)
        b->loops[l].face = pos[b->loops[l].face];
    free(copy);
    free(pos);
    return CB_OK;
}

/* Shells from consecutive face ranges: shell s holds the faces [start[s], start[s + 1]). */
static cb_status make_shells(cb_topo_body *b, const int *start, int n_shells, cb_error *err)
{
    while (b->n_shells < n_shells)
        if (cb_topo_body_add_shell(b) < 0)
            return cb_error_set(err, CB_ERR_NOMEM, "bool: out of memory");
    b->n_shells = n_shells;
    for (int s = 0; s < n_shells; s++) {
        b->shells[s].first = start[s];
        b->shells[s].count = start[s + 1] - start[s];
        b->shells[s].closed = 1;
        b->shells[s].solid = -1;
        for (int f = start[s]; f < start[s + 1]; f++)
            b->faces[f].shell = s;
    }
    return CB_OK;
}

static int box_inside(const cb_aabb *in, const cb_aabb *out)
{
    for (int k = 0; k < 3; k++)
        if (in->lo[k] < out->lo[k] || in->hi[k] > out->hi[k])
            return 0;
    return 1;
}

/* The box of the vertices of the edges of shell s. */
static void shell_box(cb_aabb *box, const cb_topo_body *b, int s)
{
    for (int k = 0; k < 3; k++) {
        box->lo[k] = HUGE_VAL;
        box->hi[k] = -HUGE_VAL;
    }
    const cb_topo_shell *sh = b->shells + s;
    for (int f = sh->first; f < sh->first + sh->count; f++)
        for (int l = b->faces[f].first; l < b->faces[f].first + b->faces[f].count; l++)
            for (int c = b->loops[l].first; c < b->loops[l].first + b->loops[l].count; c++) {
                const cb_topo_edge *e = b->edges + b->coedges[c].edge;
                for (int v = 0; v < 2; v++)
                    for (int k = 0; k < 3; k++) {
                        double x = b->vertices[e->v[v]].p[k];
                        box->lo[k] = x < box->lo[k] ? x : box->lo[k];
                        box->hi[k] = x > box->hi[k] ? x : box->hi[k];
                    }
            }
}

cb_status _cb_bool_split_shells(cb_topo_body *b, cb_error *err)
{
    int n = b->n_faces;
    if (n == 0)
        return CB_OK;
    int *parent = malloc((size_t)n * sizeof *parent), *comp = malloc((size_t)n * sizeof *comp);
    int *order = calloc((size_t)n, sizeof *order), *start = malloc((size_t)(n + 1) * sizeof *start);
    double *vol = malloc((size_t)n * sizeof *vol);
    int *owner = malloc((size_t)(n + 1) * sizeof *owner), *rank = malloc((size_t)n * sizeof *rank);
    cb_aabb *box = malloc((size_t)n * sizeof *box);
    cb_status st = CB_OK;
    if (!parent || !comp || !order || !start || !vol || !owner || !rank || !box) {
        st = cb_error_set(err, CB_ERR_NOMEM, "bool: out of memory");
        goto done;
    }
    for (int f = 0; f < n; f++)
        parent[f] = f;
    for (int e = 0; e < b->n_edges; e++) {
        int first = -1;
        for (int k = b->edge_start[e]; k < b->edge_start[e + 1]; k++) {
            int f = find(parent, b->loops[b->coedges[b->edge_coedges[k]].loop].face);
            if (first < 0)
                first = f;
            else if (f != first)
                parent[f > first ? f : first] = f > first ? first : f;
        }
    }
    /* Components numbered by their first face; faces grouped by component, in order. */
    int m = 0;
    for (int f = 0; f < n; f++)
        comp[f] = -1;
    for (int f = 0; f < n; f++) {
        int r = find(parent, f);
        if (comp[r] < 0)
            comp[r] = m++;
        comp[f] = comp[r];
    }
    if (m == 1)
        goto done;
    int k = 0;
    for (int c = 0; c < m; c++) {
        start[c] = k;
        for (int f = 0; f < n; f++)
            if (comp[f] == c)
                order[k++] = f;
    }
    start[m] = n;
    st = permute_faces(b, order, err);
    if (!st)
        st = make_shells(b, start, m, err);
    /* Outer shells (outward: positive volume) and voids (negative), by a coarse integration
     * whose sign is all that is used. */
    for (int s = 0; s < m && !st; s++) {
        st = cb_topo_shell_volume(vol + s, b, s, 16, b->tol, err);
        shell_box(box + s, b, s);
    }
    if (st)
        goto done;
    /* Each void belongs to the smallest outer shell whose box holds its box: shells of a
     * Boolean's result do not cross, so the outer shell around a void is among these. */
    for (int s = 0; s < m && !st; s++) {
        owner[s] = -1;
        if (vol[s] > 0)
            continue;
        for (int o = 0; o < m; o++)
            if (vol[o] > 0 && box_inside(box + s, box + o) &&
                (owner[s] < 0 || vol[o] < vol[owner[s]]))
                owner[s] = o;
        if (owner[s] < 0)
            st = cb_error_set(err, CB_ERR_NUMERIC,
                              "bool: the result has an inward shell (%d faces) inside no outer "
                              "shell",
                              b->shells[s].count);
    }
    if (st)
        goto done;
    /* Final order: each outer shell followed by its voids; faces follow the shells. */
    int n_solids = 0, r = 0;
    for (int o = 0; o < m; o++) {
        if (vol[o] <= 0)
            continue;
        n_solids++;
        rank[r++] = o;
        for (int s = 0; s < m; s++)
            if (vol[s] <= 0 && owner[s] == o)
                rank[r++] = s;
    }
    k = 0;
    int *start2 = owner; /* owner is no longer needed once rank is made */
    for (int i = 0; i < m; i++) {
        const cb_topo_shell *sh = b->shells + rank[i];
        start2[i] = k;
        for (int f = sh->first; f < sh->first + sh->count; f++)
            order[k++] = f;
    }
    start2[m] = n;
    st = permute_faces(b, order, err);
    if (!st)
        st = make_shells(b, start2, m, err);
    while (!st && b->n_solids < n_solids)
        if (cb_topo_body_add_solid(b) < 0)
            st = cb_error_set(err, CB_ERR_NOMEM, "bool: out of memory");
    if (st)
        goto done;
    b->n_solids = n_solids;
    for (int i = 0, sol = -1; i < m; i++) {
        if (vol[rank[i]] > 0) {
            sol++;
            b->solids[sol].first = i;
            b->solids[sol].count = 0;
        }
        b->solids[sol].count++;
        b->shells[i].solid = sol;
    }
done:
    free(parent);
    free(comp);
    free(order);
    free(start);
    free(vol);
    free(owner);
    free(rank);
    free(box);
    return st;
}
