/* Constrained Delaunay triangulation of a face's parameter domain: incremental insertion with
 * Lawson flips inside an enclosing triangle, constraint recovery by flips (S. W. Sloan, "A fast
 * algorithm for generating constrained Delaunay triangulations", Computers & Structures 1993),
 * and inside/outside by the parity of constrained edges crossed. Every branch that decides the
 * combinatorics uses the exact cb_tess_orient2d. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "brep/tess_internal.h"

#define NEXT(i) ((i) == 2 ? 0 : (i) + 1)
#define PREV(i) ((i) == 0 ? 2 : (i) - 1)

static const double *pt(const cb_tess_cdt *d, int i)
{
    return d->p + 2 * i;
}

static cb_status grow(void **buf, int *cap, int need, size_t size, cb_error *err)
{
    if (need <= *cap)
        return CB_OK;
    int c = *cap ? *cap : 64;
    while (c < need)
        c *= 2;
    void *nb = realloc(*buf, (size_t)c * size);
    if (!nb)
        return cb_error_set(err, CB_ERR_NOMEM, "triangulation: out of memory (%d items)", c);
    *buf = nb;
    *cap = c;
    return CB_OK;
}

static cb_status add_point(cb_tess_cdt *d, double x, double y, int *index, cb_error *err)
{
    int cap = d->cap_p;
    cb_status st = grow((void **)&d->p, &cap, d->np + 1, 2 * sizeof(double), err);
    if (st)
        return st;
    if (cap != d->cap_p) {
        int *nv = realloc(d->vt, (size_t)cap * sizeof(int));
        if (!nv)
            return cb_error_set(err, CB_ERR_NOMEM, "triangulation: out of memory");
        d->vt = nv;
        d->cap_p = cap;
    }
    d->p[2 * d->np] = x;
    d->p[2 * d->np + 1] = y;
    d->vt[d->np] = -1;
    *index = d->np++;
    return CB_OK;
}

static cb_status add_tri(cb_tess_cdt *d, int *index, cb_error *err)
{
    cb_status st = grow((void **)&d->t, &d->cap_t, d->nt + 1, sizeof(cb_tess_tri), err);
    if (st)
        return st;
    memset(&d->t[d->nt], 0, sizeof(cb_tess_tri));
    *index = d->nt++;
    return CB_OK;
}

static cb_status push(cb_tess_cdt *d, int *n, int value, cb_error *err)
{
    cb_status st = grow((void **)&d->stack, &d->cap_stack, *n + 1, sizeof(int), err);
    if (st)
        return st;
    d->stack[(*n)++] = value;
    return CB_OK;
}

static void set_tri(cb_tess_cdt *d, int t, int a, int b, int c)
{
    cb_tess_tri *T = &d->t[t];
    T->v[0] = a;
    T->v[1] = b;
    T->v[2] = c;
    T->settled = 0;
    d->vt[a] = d->vt[b] = d->vt[c] = t;
}

/* Makes triangle t's side i and triangle u's side j neighbours (u may be -1). */
static void link(cb_tess_cdt *d, int t, int i, int u, int j, unsigned char constrained)
{
    d->t[t].n[i] = u;
    d->t[t].c[i] = constrained;
    d->t[t].settled = 0;
    if (u >= 0) {
        d->t[u].n[j] = t;
        d->t[u].c[j] = constrained;
        d->t[u].settled = 0;
    }
}

/* The side of triangle u that faces triangle t. */
static int side_towards(const cb_tess_cdt *d, int u, int t)
{
    for (int j = 0; j < 3; j++)
        if (d->t[u].n[j] == t)
            return j;
    return -1;
}

cb_status cb_tess_cdt_init(cb_tess_cdt *d, const double box[4], cb_error *err)
{
    memset(d, 0, sizeof *d);
    double cx = 0.5 * (box[0] + box[1]), cy = 0.5 * (box[2] + box[3]);
    double r = fmax(box[1] - box[0], box[3] - box[2]);
    if (!(r > 0) || !isfinite(r))
        return cb_error_set(err, CB_ERR_INVALID, "triangulation: empty or infinite domain box");
    r *= 8;
    int i, t;
    cb_status st;
    if ((st = add_point(d, cx - 3 * r, cy - 2 * r, &i, err)) ||
        (st = add_point(d, cx + 3 * r, cy - 2 * r, &i, err)) ||
        (st = add_point(d, cx, cy + 4 * r, &i, err)) || (st = add_tri(d, &t, err))) {
        cb_tess_cdt_clear(d);
        return st;
    }
    set_tri(d, 0, 0, 1, 2);
    for (int k = 0; k < 3; k++)
        d->t[0].n[k] = -1;
    return CB_OK;
}

void cb_tess_cdt_clear(cb_tess_cdt *d)
{
    free(d->p);
    free(d->vt);
    free(d->t);
    free(d->stack);
    memset(d, 0, sizeof *d);
}

/* Flips the edge opposite v[i] of triangle t. t = (p, a, b) and its neighbour u = (q, b, a)
 * become t = (p, a, q) and u = (p, q, b). The caller checked that the quad is convex. */
static void flip(cb_tess_cdt *d, int t, int i)
{
    cb_tess_tri *T = &d->t[t];
    int u = T->n[i];
    int j = side_towards(d, u, t);
    cb_tess_tri *U = &d->t[u];
    int p = T->v[i], a = T->v[NEXT(i)], b = T->v[PREV(i)], q = U->v[j];
    /* outer neighbours: across (a, q) from u, (q, b) from u, (b, p) from t, (p, a) from t */
    int n_aq = U->n[NEXT(j)], n_qb = U->n[PREV(j)], n_bp = T->n[NEXT(i)], n_pa = T->n[PREV(i)];
    unsigned char c_aq = U->c[NEXT(j)], c_qb = U->c[PREV(j)], c_bp = T->c[NEXT(i)],
                  c_pa = T->c[PREV(i)];
    int s_aq = n_aq >= 0 ? side_towards(d, n_aq, u) : -1;
    int s_qb = n_qb >= 0 ? side_towards(d, n_qb, u) : -1;
    int s_bp = n_bp >= 0 ? side_towards(d, n_bp, t) : -1;
    int s_pa = n_pa >= 0 ? side_towards(d, n_pa, t) : -1;
    set_tri(d, t, p, a, q);
    set_tri(d, u, p, q, b);
    /* t = (p, a, q): side 0 (a, q), side 1 (q, p), side 2 (p, a) */
    link(d, t, 0, n_aq, s_aq, c_aq);
    link(d, t, 1, u, 2, 0);
    link(d, t, 2, n_pa, s_pa, c_pa);
    /* u = (p, q, b): side 0 (q, b), side 1 (b, p), side 2 (p, q) */
    link(d, u, 0, n_qb, s_qb, c_qb);
    link(d, u, 1, n_bp, s_bp, c_bp);
}

/* Whether the edge opposite v[i] of t may be flipped: unconstrained, with a neighbour, and the
 * quad strictly convex (both new triangles counter-clockwise). */
static int flippable(const cb_tess_cdt *d, int t, int i)
{
    const cb_tess_tri *T = &d->t[t];
    int u = T->n[i];
    if (u < 0 || T->c[i])
        return 0;
    int j = side_towards(d, u, t);
    int p = T->v[i], a = T->v[NEXT(i)], b = T->v[PREV(i)], q = d->t[u].v[j];
    return cb_tess_orient2d(pt(d, p), pt(d, a), pt(d, q)) > 0 &&
           cb_tess_orient2d(pt(d, p), pt(d, q), pt(d, b)) > 0;
}

int cb_tess_cdt_flip(cb_tess_cdt *d, int t, int i)
{
    if (!flippable(d, t, i) || !d->t[d->t[t].n[i]].in != !d->t[t].in)
        return 0;
    flip(d, t, i);
    return 1;
}

/* Whether the edge opposite v[i] of t violates the Delaunay property. */
static int illegal(const cb_tess_cdt *d, int t, int i)
{
    const cb_tess_tri *T = &d->t[t];
    int u = T->n[i];
    if (u < 0 || T->c[i])
        return 0;
    int j = side_towards(d, u, t);
    int q = d->t[u].v[j];
    /* The enclosing corners are far away: never let an edge to them stay when a real one
     * can replace it, never create one. */
    int sp = T->v[i] < 3, sq = q < 3, sa = T->v[NEXT(i)] < 3, sb = T->v[PREV(i)] < 3;
    if (sp || sq || sa || sb) {
        if (sa + sb > sp + sq)
            return flippable(d, t, i);
        return 0;
    }
    double r = cb_tess_incircle(pt(d, T->v[0]), pt(d, T->v[1]), pt(d, T->v[2]), pt(d, q));
    return r > 0 && flippable(d, t, i);
}

/* Lawson flips around point p after its insertion: the stack holds triangles whose side
 * opposite p must be checked. */
static cb_status legalize(cb_tess_cdt *d, int n, cb_error *err)
{
    long guard = 0;
    while (n > 0) {
        int t = d->stack[--n];
        if (++guard > 100000000L)
            return cb_error_set(err, CB_ERR_NUMERIC, "triangulation: flips do not terminate");
        const cb_tess_tri *T = &d->t[t];
        int p = d->stack[--n];
        int i = T->v[0] == p ? 0 : T->v[1] == p ? 1 : T->v[2] == p ? 2 : -1;
        if (i < 0 || !illegal(d, t, i))
            continue;
        int u = T->n[i];
        flip(d, t, i);
        /* t = (p, a, q), u = (p, q, b): their sides opposite p are new */
        cb_status st;
        if ((st = push(d, &n, p, err)) || (st = push(d, &n, t, err)) ||
            (st = push(d, &n, p, err)) || (st = push(d, &n, u, err)))
            return st;
    }
    return CB_OK;
}

/* Walks to the triangle holding (x, y). *where: 3 inside, 0..2 on the side opposite v[where],
 * -1 - k on vertex v[k]. CB_ERR_INVALID outside the enclosing triangle. */
/* Where q lies in triangle t: 3 inside, 0..2 on the side opposite v[k], -1 - k on vertex
 * v[k], -4 outside (then *out is a side q lies beyond). */
static int classify_in(const cb_tess_cdt *d, int t, const double q[2], unsigned start, int *out)
{
    const cb_tess_tri *T = &d->t[t];
    int o[3];
    for (unsigned k = 0; k < 3; k++) {
        int i = (int)((start + k) % 3);
        o[i] = cb_tess_orient2d(pt(d, T->v[NEXT(i)]), pt(d, T->v[PREV(i)]), q);
        if (o[i] < 0) {
            *out = i;
            return -4;
        }
    }
    int zeros = (o[0] == 0) + (o[1] == 0) + (o[2] == 0);
    if (zeros == 2)
        return o[0] != 0 ? -1 : o[1] != 0 ? -2 : -3;
    if (zeros == 1)
        return o[0] == 0 ? 0 : o[1] == 0 ? 1 : 2;
    return 3;
}

/* Walks to the triangle holding q (*where as classify_in). The side to leave by is chosen
 * from a pseudo-random start, as a walk in a constrained (non-Delaunay) triangulation may
 * cycle otherwise; a walk that still runs long ends in a scan of all triangles.
 * CB_ERR_INVALID outside the enclosing triangle. */
static cb_status locate(cb_tess_cdt *d, const double q[2], int *tri, int *where, cb_error *err)
{
    int t = d->hint >= 0 && d->hint < d->nt ? d->hint : 0;
    unsigned rng = 0x9e3779b9u ^ (unsigned)d->np;
    for (long guard = 0; guard < 4L * d->nt + 1000; guard++) {
        rng ^= rng << 13;
        rng ^= rng >> 17;
        rng ^= rng << 5;
        int side, w = classify_in(d, t, q, rng % 3, &side);
        if (w != -4) {
            *tri = d->hint = t;
            *where = w;
            return CB_OK;
        }
        if (d->t[t].n[side] < 0)
            break;
        t = d->t[t].n[side];
    }
    for (t = 0; t < d->nt; t++) {
        int side, w = classify_in(d, t, q, 0, &side);
        if (w != -4) {
            *tri = d->hint = t;
            *where = w;
            return CB_OK;
        }
    }
    return cb_error_set(err, CB_ERR_INVALID, "triangulation: point (%g, %g) outside the domain",
                        q[0], q[1]);
}

cb_status cb_tess_cdt_insert(cb_tess_cdt *d, double x, double y, int avoid_constrained,
                             int *index, cb_error *err)
{
    double q[2] = {x, y};
    int t = 0, where = 3;
    cb_status st = locate(d, q, &t, &where, err);
    if (st)
        return st;
    if (where < 0) {
        *index = d->t[t].v[-1 - where];
        return CB_OK;
    }
    if (where < 3 && avoid_constrained && d->t[t].c[where]) {
        *index = -1;
        return CB_OK;
    }
    /* Room first, so nothing below can fail half-way through the relinking. */
    if ((st = grow((void **)&d->t, &d->cap_t, d->nt + 3, sizeof(cb_tess_tri), err)))
        return st;
    int p;
    if ((st = add_point(d, x, y, &p, err)))
        return st;
    int n = 0;
    if (where == 3) {
        cb_tess_tri T = d->t[t];
        int t1, t2;
        add_tri(d, &t1, err);
        add_tri(d, &t2, err);
        int s[3];
        for (int k = 0; k < 3; k++)
            s[k] = T.n[k] >= 0 ? side_towards(d, T.n[k], t) : -1;
        /* t = (p, v1, v2), t1 = (p, v2, v0), t2 = (p, v0, v1) */
        d->t[t1].in = d->t[t2].in = T.in;
        set_tri(d, t, p, T.v[1], T.v[2]);
        set_tri(d, t1, p, T.v[2], T.v[0]);
        set_tri(d, t2, p, T.v[0], T.v[1]);
        link(d, t, 0, T.n[0], s[0], T.c[0]);
        link(d, t1, 0, T.n[1], s[1], T.c[1]);
        link(d, t2, 0, T.n[2], s[2], T.c[2]);
        link(d, t, 1, t1, 2, 0);
        link(d, t1, 1, t2, 2, 0);
        link(d, t2, 1, t, 2, 0);
        int list[3] = {t, t1, t2};
        for (int k = 0; k < 3; k++)
            if ((st = push(d, &n, p, err)) || (st = push(d, &n, list[k], err)))
                return st;
    } else {
        /* On the side opposite v[where] of t, shared with u (or the hull). */
        cb_tess_tri T = d->t[t];
        int i = where, u = T.n[i];
        int a = T.v[NEXT(i)], b = T.v[PREV(i)], c = T.v[i];
        unsigned char cons = T.c[i];
        int n_ca = T.n[PREV(i)], n_bc = T.n[NEXT(i)];
        unsigned char c_ca = T.c[PREV(i)], c_bc = T.c[NEXT(i)];
        int s_ca = n_ca >= 0 ? side_towards(d, n_ca, t) : -1;
        int s_bc = n_bc >= 0 ? side_towards(d, n_bc, t) : -1;
        int t1;
        add_tri(d, &t1, err);
        d->t[t1].in = T.in;
        /* t = (p, b, c), t1 = (p, c, a) */
        set_tri(d, t, p, b, c);
        set_tri(d, t1, p, c, a);
        link(d, t, 0, n_bc, s_bc, c_bc);
        link(d, t1, 0, n_ca, s_ca, c_ca);
        link(d, t, 1, t1, 2, 0);
        int list[4] = {t, t1, -1, -1};
        if (u >= 0) {
            int j = side_towards(d, u, t);
            cb_tess_tri U = d->t[u];
            int e = U.v[j]; /* u = (e, b, a) */
            int n_ae = U.n[NEXT(j)], n_eb = U.n[PREV(j)];
            unsigned char c_ae = U.c[NEXT(j)], c_eb = U.c[PREV(j)];
            int s_ae = n_ae >= 0 ? side_towards(d, n_ae, u) : -1;
            int s_eb = n_eb >= 0 ? side_towards(d, n_eb, u) : -1;
            int u1;
            add_tri(d, &u1, err);
            d->t[u1].in = U.in;
            /* u = (p, a, e), u1 = (p, e, b) */
            set_tri(d, u, p, a, e);
            set_tri(d, u1, p, e, b);
            link(d, u, 0, n_ae, s_ae, c_ae);
            link(d, u1, 0, n_eb, s_eb, c_eb);
            link(d, u, 1, u1, 2, 0);
            /* p-a is shared by t1 (side 1: (a, p)) and u (side 2: (p, a)); p-b by u1 and t */
            link(d, t1, 1, u, 2, cons);
            link(d, u1, 1, t, 2, cons);
            list[2] = u;
            list[3] = u1;
        } else {
            link(d, t1, 1, -1, -1, cons);
            link(d, t, 2, -1, -1, cons);
        }
        for (int k = 0; k < 4; k++)
            if (list[k] >= 0 && ((st = push(d, &n, p, err)) || (st = push(d, &n, list[k], err))))
                return st;
    }
    *index = p;
    return legalize(d, n, err);
}

/* Triangle t and side i such that side i of t runs from a to b (a's triangles are searched by
 * turning about a). Returns 0 when there is no such edge. */
static int find_edge(const cb_tess_cdt *d, int a, int b, int *tri, int *side)
{
    int t = d->vt[a];
    for (int dir = 0; dir < 2; dir++) {
        int cur = t;
        for (int guard = 0; cur >= 0 && guard < d->nt + 1; guard++) {
            const cb_tess_tri *T = &d->t[cur];
            int j = T->v[0] == a ? 0 : T->v[1] == a ? 1 : 2;
            if (T->v[NEXT(j)] == b) {
                *tri = cur;
                *side = PREV(j);
                return 1;
            }
            cur = dir == 0 ? T->n[NEXT(j)] : T->n[PREV(j)];
            if (cur == t)
                return 0;
        }
    }
    return 0;
}

/* Marks the edge a-b constrained on both sides. */
static void mark(cb_tess_cdt *d, int t, int i)
{
    d->t[t].c[i] = 1;
    d->t[t].settled = 0;
    int u = d->t[t].n[i];
    if (u >= 0) {
        d->t[u].c[side_towards(d, u, t)] = 1;
        d->t[u].settled = 0;
    }
}

/* Whether segment p-q crosses segment a-b at a point interior to both. */
static int crosses(const cb_tess_cdt *d, int a, int b, int p, int q)
{
    if (p == a || p == b || q == a || q == b)
        return 0;
    int o1 = cb_tess_orient2d(pt(d, a), pt(d, b), pt(d, p));
    int o2 = cb_tess_orient2d(pt(d, a), pt(d, b), pt(d, q));
    if (o1 * o2 >= 0)
        return 0;
    int o3 = cb_tess_orient2d(pt(d, p), pt(d, q), pt(d, a));
    int o4 = cb_tess_orient2d(pt(d, p), pt(d, q), pt(d, b));
    return o3 * o4 < 0;
}

/* Walks from a towards b collecting, on the stack as pairs, the edges the segment crosses. If
 * a point lies on the segment first, *on receives it (else -1). */
static cb_status crossed_edges(cb_tess_cdt *d, int a, int b, int *n, int *on, cb_error *err)
{
    *n = 0;
    *on = -1;
    const double *A = pt(d, a), *B = pt(d, b);
    /* The triangle about a whose wedge holds the direction to b. */
    int t = d->vt[a], l = -1, r = -1;
    for (int guard = 0; guard < d->nt + 1; guard++) {
        const cb_tess_tri *T = &d->t[t];
        int j = T->v[0] == a ? 0 : T->v[1] == a ? 1 : 2;
        int v1 = T->v[NEXT(j)], v2 = T->v[PREV(j)];
        int o1 = cb_tess_orient2d(A, pt(d, v1), B), o2 = cb_tess_orient2d(A, pt(d, v2), B);
        const double *P1 = pt(d, v1), *P2 = pt(d, v2);
        if (o1 == 0 && (P1[0] - A[0]) * (B[0] - A[0]) + (P1[1] - A[1]) * (B[1] - A[1]) > 0) {
            *on = v1;
            return CB_OK;
        }
        if (o2 == 0 && (P2[0] - A[0]) * (B[0] - A[0]) + (P2[1] - A[1]) * (B[1] - A[1]) > 0) {
            *on = v2;
            return CB_OK;
        }
        if (o1 > 0 && o2 < 0) {
            r = v1;
            l = v2;
            t = T->n[j];
            break;
        }
        t = T->n[NEXT(j)];
        if (t < 0)
            return cb_error_set(err, CB_ERR_NUMERIC, "triangulation: segment leaves the domain");
    }
    if (l < 0)
        return cb_error_set(err, CB_ERR_NUMERIC, "triangulation: no triangle about a point "
                                                 "faces the segment");
    cb_status st;
    if ((st = push(d, n, l, err)) || (st = push(d, n, r, err)))
        return st;
    for (int guard = 0; guard < d->nt + 1; guard++) {
        if (t < 0)
            return cb_error_set(err, CB_ERR_NUMERIC, "triangulation: segment leaves the domain");
        const cb_tess_tri *T = &d->t[t];
        int w = -1;
        for (int k = 0; k < 3; k++)
            if (T->v[k] != l && T->v[k] != r)
                w = T->v[k];
        if (w == b)
            return CB_OK;
        int o = cb_tess_orient2d(A, B, pt(d, w));
        if (o == 0) {
            *n = 0;
            *on = w;
            return CB_OK;
        }
        /* Entered through (l, r): the segment leaves through (w, r) when w is on its left,
         * through (l, w) otherwise, i.e. through the side opposite the end left behind. */
        int behind = o > 0 ? l : r;
        int side = T->v[0] == behind ? 0 : T->v[1] == behind ? 1 : 2;
        if (o > 0)
            l = w;
        else
            r = w;
        t = T->n[side];
        if ((st = push(d, n, l, err)) || (st = push(d, n, r, err)))
            return st;
    }
    return cb_error_set(err, CB_ERR_NUMERIC, "triangulation: segment walk does not end");
}

cb_status cb_tess_cdt_constrain(cb_tess_cdt *d, int a, int b, cb_error *err)
{
    for (int piece = 0; piece < d->np + 1; piece++) {
        int t, i;
        if (a == b)
            return CB_OK;
        if (find_edge(d, a, b, &t, &i)) {
            mark(d, t, i);
            return CB_OK;
        }
        int n, on;
        cb_status st = crossed_edges(d, a, b, &n, &on, err);
        if (st)
            return st;
        if (on >= 0) {
            if ((st = cb_tess_cdt_constrain(d, a, on, err)))
                return st;
            a = on;
            continue;
        }
        /* Queue of crossing edges as pairs (stack[head..n)), flipped until none crosses. */
        int head = 0;
        long guard = 0, limit = 64L * (n / 2 + 4) * (n / 2 + 4) + 1000;
        while (head < n) {
            if (++guard > limit)
                return cb_error_set(err, CB_ERR_NUMERIC,
                                    "triangulation: constraint recovery stalls");
            int p = d->stack[head], q = d->stack[head + 1];
            head += 2;
            if (!find_edge(d, p, q, &t, &i) && !find_edge(d, q, p, &t, &i))
                continue;
            if (!flippable(d, t, i)) {
                if ((st = push(d, &n, p, err)) || (st = push(d, &n, q, err)))
                    return st;
                continue;
            }
            int u = d->t[t].n[i];
            flip(d, t, i);
            /* the new edge joins t.v[0] and u.v[1] (see flip) */
            int e0 = d->t[t].v[0], e1 = d->t[u].v[1];
            if (crosses(d, a, b, e0, e1) &&
                ((st = push(d, &n, e0, err)) || (st = push(d, &n, e1, err))))
                return st;
            /* Keep the queue compact. */
            if (head > 4096 && head * 2 > n) {
                memmove(d->stack, d->stack + head, (size_t)(n - head) * sizeof(int));
                n -= head;
                head = 0;
            }
        }
        if (find_edge(d, a, b, &t, &i)) {
            mark(d, t, i);
            return CB_OK;
        }
        return cb_error_set(err, CB_ERR_NUMERIC, "triangulation: segment %d-%d not recovered",
                            a, b);
    }
    return CB_OK;
}

void cb_tess_cdt_delaunay(cb_tess_cdt *d)
{
    for (int pass = 0; pass < 100; pass++) {
        int flips = 0;
        for (int t = 0; t < d->nt; t++)
            for (int i = 0; i < 3; i++)
                if (d->t[t].n[i] > t && illegal(d, t, i)) {
                    flip(d, t, i);
                    flips++;
                }
        if (!flips)
            return;
    }
}

cb_status cb_tess_cdt_classify(cb_tess_cdt *d, cb_error *err)
{
    int *depth = malloc((size_t)d->nt * sizeof(int));
    int *queue = malloc((size_t)(4 * d->nt + 4) * sizeof(int));
    if (!depth || !queue) {
        free(depth);
        free(queue);
        return cb_error_set(err, CB_ERR_NOMEM, "triangulation: out of memory");
    }
    for (int t = 0; t < d->nt; t++)
        depth[t] = -1;
    /* Breadth first by depth: the current level is flooded through unconstrained sides, the
     * triangles across constrained sides start the next level. */
    int cur = 0, n_cur = 0, n_next = 0;
    int *next = queue + d->nt + 1; /* up to three entries per triangle of a level */
    for (int t = 0; t < d->nt; t++)
        for (int k = 0; k < 3; k++)
            if (d->t[t].v[k] < 3 && depth[t] < 0) {
                depth[t] = 0;
                queue[n_cur++] = t;
            }
    while (n_cur > 0) {
        for (int h = 0; h < n_cur; h++) {
            int t = queue[h];
            for (int k = 0; k < 3; k++) {
                int u = d->t[t].n[k];
                if (u < 0 || depth[u] >= 0)
                    continue;
                if (d->t[t].c[k]) {
                    next[n_next++] = u;
                } else {
                    depth[u] = cur;
                    queue[n_cur++] = u;
                }
            }
        }
        cur++;
        n_cur = 0;
        for (int h = 0; h < n_next; h++)
            if (depth[next[h]] < 0) {
                depth[next[h]] = cur;
                queue[n_cur++] = next[h];
            }
        n_next = 0;
    }
    for (int t = 0; t < d->nt; t++)
        d->t[t].in = depth[t] > 0 && (depth[t] & 1);
    free(depth);
    free(queue);
    return CB_OK;
}
