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

/* A box holding shell s: the union of its faces' conservative boxes (cb_face_box). The
 * vertices alone do not do: a sphere bounded by a vertex loop has one vertex, at a pole. */
static void shell_box(cb_aabb *box, const cb_bool_solid *S, const cb_topo_body *b, int s)
{
    for (int k = 0; k < 3; k++) {
        box->lo[k] = HUGE_VAL;
        box->hi[k] = -HUGE_VAL;
    }
    const cb_topo_shell *sh = b->shells + s;
    for (int f = sh->first; f < sh->first + sh->count; f++) {
        cb_aabb fb;
        cb_face_box(&fb, cb_bool_solid_face(S, f));
        for (int k = 0; k < 3; k++) {
            box->lo[k] = fb.lo[k] < box->lo[k] ? fb.lo[k] : box->lo[k];
            box->hi[k] = fb.hi[k] > box->hi[k] ? fb.hi[k] : box->hi[k];
        }
    }
}

/* A point of face F well inside it: of a 9 x 9 grid over its (u, v) box, the point IN the
 * face farthest from its boundary edges; 0 when no grid point is IN. */
static int face_inner_point(double X[3], const cb_face *F, double tol)
{
    const double *bx = F->uv_box;
    double best = -1;
    for (int i = 1; i < 10; i++)
        for (int j = 1; j < 10; j++) {
            double u = bx[0] + (bx[1] - bx[0]) * i / 10, v = bx[2] + (bx[3] - bx[2]) * j / 10;
            if (cb_face_classify_uv(F, u, v, tol) != CB_FACE_IN)
                continue;
            double p[3];
            cb_topo_inverter_eval(p, &F->inv, u, v);
            double d = cb_face_boundary_distance(F, p);
            if (d > best) {
                best = d;
                memcpy(X, p, sizeof p);
            }
        }
    return best >= 0;
}

/* *owner: the smallest outward shell (by volume) that void s lies inside, or -1. Shells of a
 * Boolean's result do not cross, so one point of the void tells: a point inside one of its
 * faces, classified against each outward shell alone (rays counting that shell's faces only);
 * a point ON an outward shell (voids may touch their shell) is replaced by one of the next
 * face. */
static cb_status void_owner(int *owner, const cb_bool_solid *S, const cb_topo_body *b, int s,
                            const double *vol, const cb_aabb *box, int m, cb_error *err)
{
    *owner = -1;
    const cb_topo_shell *sh = b->shells + s;
    for (int f = sh->first; f < sh->first + sh->count; f++) {
        double X[3];
        if (!face_inner_point(X, cb_bool_solid_face(S, f), b->tol))
            continue;
        int on = 0, own = -1;
        for (int o = 0; o < m && !on; o++) {
            if (!(vol[o] > 0) || !cb_aabb_overlap(box + s, box + o, b->tol))
                continue;
            cb_bool_where w;
            cb_status st = cb_bool_solid_classify_faces(&w, S, X, b->shells[o].first,
                                                        b->shells[o].count, err);
            if (st)
                return st;
            on = w == CB_BOOL_ON;
            if (w == CB_BOOL_IN && (own < 0 || vol[o] < vol[own]))
                own = o;
        }
        if (!on) {
            *owner = own;
            return CB_OK;
        }
    }
    return CB_OK;
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
    cb_bool_solid *S = NULL;
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
    for (int s = 0; s < m && !st; s++)
        st = cb_topo_shell_volume(vol + s, b, s, 16, b->tol, err);
    int any_void = 0;
    for (int s = 0; s < m && !st; s++)
        any_void |= !(vol[s] > 0);
    if (!st && any_void)
        st = cb_bool_solid_new(&S, b, b->tol, err);
    for (int s = 0; s < m && !st && any_void; s++)
        shell_box(box + s, S, b, s);
    if (st)
        goto done;
    /* Each void belongs to the smallest outer shell around it. */
    for (int s = 0; s < m && !st; s++) {
        owner[s] = -1;
        if (vol[s] > 0)
            continue;
        st = void_owner(owner + s, S, b, s, vol, box, m, err);
        if (!st && owner[s] < 0)
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
    cb_bool_solid_free(S);
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
