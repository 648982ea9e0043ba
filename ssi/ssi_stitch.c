/* ssi_stitch.c — stitching the pieces of all patch pairs into maximal curves, by the identity of
 * their ends (the certified graphs' vertices and boundary roots, ssi/ssi.h _cb_ssi_stitch),
 * never by distance alone; the within-tolerance and refusal rules are those of ssi/ssi_tol.h. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ssi/ssi.h"
#include "ssi/ssi_tol.h"

/* ---------------------------------------------------------------- piece ends --------------- */

void _cb_ssi_end_init(_cb_ssi_end *e)
{
    memset(e, 0, sizeof(*e));
    e->vid = -1;
    e->region = -1;
}

void _cb_ssi_end_clear(_cb_ssi_end *e)
{
    for (int k = 0; k < e->nl; k++) {
        _cb_ssi_side_root *r = e->ln[k].root;
        if (!r)
            continue;
        if (r->p) {
            fmpz_poly_clear(r->p);
            free(r->p);
        }
        fmpq_clear(r->lo);
        fmpq_clear(r->hi);
        free(r);
    }
    _cb_ssi_end_init(e);
}

_cb_ssi_end_line *_cb_ssi_end_add_line(_cb_ssi_end *e, int sigma, int dir, int half, double c,
                                       double lo, double hi)
{
    if (e->nl >= 2)
        return NULL;
    _cb_ssi_end_line *l = e->ln + e->nl++;
    l->sigma = sigma;
    l->dir = dir;
    l->half = half;
    l->c = c;
    l->lo = lo;
    l->hi = hi;
    l->range[0] = 0;
    l->range[1] = 1;
    l->root = NULL;
    return l;
}

/* Outward double bounds of an exact rational. */
static double fmpq_down(const fmpq_t x)
{
    double d = fmpq_get_d(x);
    return d - (fabs(d) * 0x1p-51 + 0x1p-1070);
}

static double fmpq_up(const fmpq_t x)
{
    double d = fmpq_get_d(x);
    return d + (fabs(d) * 0x1p-51 + 0x1p-1070);
}

/* phi(var = c) as a univariate polynomial in the other variable of ctx. */
static void restrict_side(fmpz_poly_t out, const fmpz_mpoly_t phi, const fmpz_mpoly_ctx_t ctx,
                          int var, int c)
{
    fmpz_mpoly_t r;
    fmpz_mpoly_init(r, ctx);
    fmpz_t cz;
    fmpz_init_set_si(cz, c);
    fmpz_mpoly_evaluate_one_fmpz(r, phi, var, cz, ctx);
    if (!fmpz_mpoly_get_fmpz_poly(out, r, 1 - var, ctx))
        fmpz_poly_zero(out);
    fmpz_clear(cz);
    fmpz_mpoly_clear(r, ctx);
}

cb_status _cb_ssi_ends_from_graph(_cb_ssi_piece_set *ps, slong first, const cb_ctopo_t T,
                                  const fmpz_mpoly_t phi, const fmpz_mpoly_ctx_t ctx, int swap)
{
    for (slong k = first; k < ps->n; k++) {
        _cb_ssi_piece *pc = ps->p + k;
        for (int e = 0; e < (pc->isolated ? 1 : 2); e++) {
            _cb_ssi_end *end = pc->end + e;
            if (end->vid < 0 || end->vid >= T->n_vertices)
                continue;
            const cb_ctopo_vertex_struct *V = T->vertex + end->vid;
            for (int side = 0; side < 4; side++) {
                if (!(V->sides & (1u << side)))
                    continue;
                /* Sides S0, S1 hold T's s (the free coordinate is t); T0, T1 hold t. */
                int tfix = side >= 2, c = side & 1;
                int qdir = swap ? !tfix : tfix;
                _cb_ssi_side_root *root = malloc(sizeof *root);
                fmpz_poly_struct *p = malloc(sizeof *p);
                if (!root || !p) {
                    free(root);
                    free(p);
                    return CB_ERR_NOMEM;
                }
                fmpz_poly_init(p);
                fmpq_init(root->lo);
                fmpq_init(root->hi);
                fmpq_t cq;
                fmpq_init(cq);
                fmpq_set_si(cq, c, 1);
                /* The curve's points on the side are the roots of phi there (vertical lines
                 * of phi's content included); a side s = c that is itself such a line: the
                 * roots of h (the branches crossing it; its ends are box corners). */
                restrict_side(p, phi, ctx, tfix, c);
                if (fmpz_poly_is_zero(p) && !tfix)
                    cb_bipoly_eval_s_fmpq(p, T->h, cq);
                if (tfix) {
                    fmpq_set(root->lo, V->s_lo);
                    fmpq_set(root->hi, V->s_hi);
                } else {
                    fmpq_set(root->lo, V->t_lo);
                    fmpq_set(root->hi, V->t_hi);
                }
                fmpq_clear(cq);
                if (fmpz_poly_is_zero(p)) {
                    /* The side lies on the curve: only exact points compare. */
                    fmpz_poly_clear(p);
                    free(p);
                    p = NULL;
                } else {
                    fmpz_poly_primitive_part(p, p);
                }
                root->p = p;
                _cb_ssi_end_line *l = _cb_ssi_end_add_line(end, 1, qdir, c ? -1 : 1, c,
                                                           fmpq_down(root->lo),
                                                           fmpq_up(root->hi));
                if (!l) {
                    if (p) {
                        fmpz_poly_clear(p);
                        free(p);
                    }
                    fmpq_clear(root->lo);
                    fmpq_clear(root->hi);
                    free(root);
                    continue;
                }
                l->root = root;
            }
        }
    }
    return CB_OK;
}

/* 1: the exact roots a and b (same line, same patch strip) are the same point, 0: different
 * points, -1: not decided (no polynomial where one is needed). */
static int exact_same(const _cb_ssi_side_root *a, const _cb_ssi_side_root *b)
{
    if (fmpq_cmp(a->hi, b->lo) < 0 || fmpq_cmp(b->hi, a->lo) < 0)
        return 0;
    int ea = fmpq_equal(a->lo, a->hi), eb = fmpq_equal(b->lo, b->hi);
    if (ea && eb)
        return fmpq_equal(a->lo, b->lo);
    if (ea || eb) {
        /* The exact point r lies in the other's interval: the same point iff it is the
         * other's (only) root there. */
        const _cb_ssi_side_root *x = ea ? a : b, *y = ea ? b : a;
        if (!y->p)
            return -1;
        fmpq_t v;
        fmpq_init(v);
        fmpz_poly_evaluate_fmpq(v, y->p, x->lo);
        int z = fmpq_is_zero(v);
        fmpq_clear(v);
        return z;
    }
    if (!a->p || !b->p)
        return -1;
    /* Both roots in open intervals, each the only root of its polynomial there: they are one
     * point iff gcd(a.p, b.p) vanishes in the intersection of the intervals. */
    fmpq_t lo, hi;
    fmpq_init(lo);
    fmpq_init(hi);
    fmpq_set(lo, fmpq_cmp(a->lo, b->lo) > 0 ? a->lo : b->lo);
    fmpq_set(hi, fmpq_cmp(a->hi, b->hi) < 0 ? a->hi : b->hi);
    fmpz_poly_t g;
    fmpz_poly_init(g);
    fmpz_poly_gcd(g, a->p, b->p);
    int same = 0;
    if (fmpz_poly_degree(g) >= 1) {
        if (fmpq_equal(lo, hi)) {
            fmpq_t v;
            fmpq_init(v);
            fmpz_poly_evaluate_fmpq(v, g, lo);
            same = fmpq_is_zero(v);
            fmpq_clear(v);
        } else {
            cb_roots_t rt;
            cb_roots_init(rt);
            cb_error err;
            same = cb_roots_isolate(rt, g, lo, hi, &err) == CB_OK ? rt->n > 0 : -1;
            cb_roots_clear(rt);
        }
    }
    fmpz_poly_clear(g);
    fmpq_clear(lo);
    fmpq_clear(hi);
    return same;
}

void _cb_ssi_seams(double seam[2][2], const cb_nurbs_surface_struct *s)
{
    double dom[4];
    cb_nurbs_surface_domain(s, dom);
    for (int dir = 0; dir < 2; dir++) {
        seam[dir][0] = seam[dir][1] = NAN;
        int n = dir ? s->n_v : s->n_u, m = dir ? s->n_u : s->n_v, ok = 1;
        /* Control point k of the first and last row in direction dir. */
#define CP(row, k) (s->cw + 4 * (dir ? (k) * s->n_v + (row) : (row) * s->n_v + (k)))
        double w0 = CP(0, 0)[3], w1 = CP(n - 1, 0)[3];
        int e;
        double f = w1 / w0;
        ok = w0 > 0 && w1 > 0 && frexp(f, &e) == 0.5; /* a power of two: exact products */
        for (int k = 0; k < m && ok; k++)
            for (int q = 0; q < 4 && ok; q++)
                ok = CP(n - 1, k)[q] == f * CP(0, k)[q];
#undef CP
        if (ok) {
            seam[dir][0] = dom[2 * dir];
            seam[dir][1] = dom[2 * dir + 1];
        }
    }
}

/* Whether the exact local coordinates a in range ra and b in rb (each mapped affinely from
 * [0, 1], ranges taken as the dyadic rationals they are) are one domain value. */
static int exact_point_same(const fmpq_t a, const double ra[2], const fmpq_t b,
                            const double rb[2])
{
    if (!isfinite(ra[0]) || !isfinite(ra[1]) || !isfinite(rb[0]) || !isfinite(rb[1]))
        return -1;
    fmpq_t x[2], d0, d1;
    fmpq_init(d0);
    fmpq_init(d1);
    for (int k = 0; k < 2; k++) {
        const double *r = k ? rb : ra;
        fmpq_init(x[k]);
        _cb_fmpq_set_d(d0, r[0]);
        _cb_fmpq_set_d(d1, r[1]);
        fmpq_sub(d1, d1, d0);
        fmpq_mul(x[k], k ? b : a, d1);
        fmpq_add(x[k], x[k], d0);
    }
    int same = fmpq_equal(x[0], x[1]);
    fmpq_clear(x[0]);
    fmpq_clear(x[1]);
    fmpq_clear(d0);
    fmpq_clear(d1);
    return same;
}

/* ---------------------------------------------------------------- helpers ------------------ */

static double d3(const double *a, const double *b)
{
    return sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                (a[2] - b[2]) * (a[2] - b[2]));
}

/* Distance from p to the polyline of n points x. */
static double polyline_dist(const double *p, const double *x, slong n)
{
    double best = d3(p, x);
    for (slong i = 0; i + 1 < n; i++) {
        const double *a = x + 3 * i, *b = x + 3 * i + 3;
        double ab[3], ap[3], l2 = 0, dot = 0;
        for (int k = 0; k < 3; k++) {
            ab[k] = b[k] - a[k];
            ap[k] = p[k] - a[k];
            l2 += ab[k] * ab[k];
            dot += ab[k] * ap[k];
        }
        double f = l2 > 0 ? fmin(1, fmax(0, dot / l2)) : 0, q[3];
        for (int k = 0; k < 3; k++)
            q[k] = a[k] + f * ab[k];
        best = fmin(best, d3(p, q));
    }
    return best;
}

static slong uf_find(slong *par, slong x)
{
    while (par[x] != x) {
        par[x] = par[par[x]];
        x = par[x];
    }
    return x;
}

/* Unites the classes of x and y, the lower index the root (so a node's first end is its
 * root). */
static void uf_union(slong *par, slong x, slong y)
{
    x = uf_find(par, x);
    y = uf_find(par, y);
    if (x == y)
        return;
    if (x < y)
        par[y] = x;
    else
        par[x] = y;
}

typedef struct {
    const _cb_ssi_piece *p;
    slong set;
    slong node[2];
    int dropped, used;
} item;

typedef struct {
    double X[3];
    _cb_ssi_pq pq;
    slong deg;
    int within; /* joined within tolerance */
} node;

/* The point and parameters of end e (2 i + side) of the items. */
static const double *end_xyz(const item *it, slong e)
{
    const _cb_ssi_piece *p = it[e / 2].p;
    return p->xyz + 3 * (e % 2 ? p->n - 1 : 0);
}

static const _cb_ssi_pq *end_pq(const item *it, slong e)
{
    const _cb_ssi_piece *p = it[e / 2].p;
    return p->pt + (e % 2 ? p->n - 1 : 0);
}

static void out_point(cb_ssi_point *o, const double X[3], const _cb_ssi_pq *q, int swapped)
{
    memcpy(o->xyz, X, 3 * sizeof(double));
    const double *uv = q->uv, *st = q->st;
    memcpy(o->uv_a, swapped ? st : uv, 2 * sizeof(double));
    memcpy(o->uv_b, swapped ? uv : st, 2 * sizeof(double));
}

static cb_status curve_append(cb_ssi_curve *c, slong *alloc, const double X[3],
                              const _cb_ssi_pq *q, int swapped)
{
    if (c->n == *alloc) {
        slong a = *alloc ? 2 * *alloc : 64;
        cb_ssi_point *pt = realloc(c->pt, (size_t)a * sizeof(cb_ssi_point));
        if (!pt)
            return CB_ERR_NOMEM;
        c->pt = pt;
        *alloc = a;
    }
    out_point(c->pt + c->n++, X, q, swapped);
    return CB_OK;
}

/* Appends piece it in direction rev (0: as stored), skipping its first point when the curve
 * already ends there, with its end points snapped to their nodes. */
static cb_status append_piece(cb_ssi_curve *c, slong *alloc, const item *it, int rev,
                              const node *nodes, int swapped)
{
    const _cb_ssi_piece *p = it->p;
    cb_status st = CB_OK;
    for (slong k = 0; k < p->n && st == CB_OK; k++) {
        slong i = rev ? p->n - 1 - k : k;
        if (k == 0 && c->n > 0)
            continue;
        if (i == 0 && it->node[0] >= 0)
            st = curve_append(c, alloc, nodes[it->node[0]].X, &nodes[it->node[0]].pq, swapped);
        else if (i == p->n - 1 && it->node[1] >= 0)
            st = curve_append(c, alloc, nodes[it->node[1]].X, &nodes[it->node[1]].pq, swapped);
        else
            st = curve_append(c, alloc, p->xyz + 3 * i, p->pt + i, swapped);
    }
    return st;
}

/* ---------------------------------------------------------------- joining ends ------------- */

/* One end on one line, for the sweep along the line; c the line's value with a seam's upper
 * side taken as its lower one. */
typedef struct {
    slong e;
    const _cb_ssi_end_line *l;
    double c;
} entry;

static int cmp_entry(const void *va, const void *vb)
{
    const entry *a = va, *b = vb;
    if (a->l->sigma != b->l->sigma)
        return a->l->sigma - b->l->sigma;
    if (a->l->dir != b->l->dir)
        return a->l->dir - b->l->dir;
    if (a->c != b->c)
        return a->c < b->c ? -1 : 1;
    if (a->l->lo != b->l->lo)
        return a->l->lo < b->l->lo ? -1 : 1;
    return a->e < b->e ? -1 : (a->e > b->e);
}

typedef struct {
    item *it;
    slong ni;
    slong *par;            /* union-find over ends 2 i + side */
    char *decided;         /* per end: it had candidates and a rule decided */
    char *within;          /* per end: joined within tolerance */
    _cb_ssi_stitch_set *sets;
    const _cb_ssi_stitch_opts *o;
    cb_ssi_result_struct *r;
} joiner;

/* Relation of the ends of entries x and y: 1 the same point, 0 different points, -1 not
 * decided by certified data. */
static int entry_rel(const joiner *J, const entry *x, const entry *y)
{
    const _cb_ssi_end *ex = &J->it[x->e / 2].p->end[x->e % 2];
    const _cb_ssi_end *ey = &J->it[y->e / 2].p->end[y->e % 2];
    if (J->it[x->e / 2].set == J->it[y->e / 2].set && ex->vid >= 0 && ey->vid >= 0)
        return ex->vid == ey->vid;
    const _cb_ssi_side_root *a = x->l->root, *b = y->l->root;
    if (a && b && x->l->range[0] == y->l->range[0] && x->l->range[1] == y->l->range[1])
        return exact_same(a, b);
    if (a && b && fmpq_equal(a->lo, a->hi) && fmpq_equal(b->lo, b->hi))
        return exact_point_same(a->lo, x->l->range, b->lo, y->l->range);
    return -1;
}

/* The box of the ends of entries E[0..m) into region or failure boxes; returns the diameter of
 * the 3D box. Patch indices: the set's when all ends are of one set, else -1. */
static double group_box(const joiner *J, const entry *E, slong m, double lo[3], double hi[3],
                        double ba[4], double bb[4], int *pa, int *pb)
{
    for (int k = 0; k < 3; k++) {
        lo[k] = HUGE_VAL;
        hi[k] = -HUGE_VAL;
    }
    for (int k = 0; k < 2; k++) {
        ba[2 * k] = bb[2 * k] = HUGE_VAL;
        ba[2 * k + 1] = bb[2 * k + 1] = -HUGE_VAL;
    }
    slong set0 = J->it[E[0].e / 2].set;
    int one = 1;
    for (slong x = 0; x < m; x++) {
        const double *X = end_xyz(J->it, E[x].e);
        const _cb_ssi_pq *q = end_pq(J->it, E[x].e);
        cb_ssi_point pt;
        out_point(&pt, X, q, J->o->swapped);
        for (int k = 0; k < 3; k++) {
            lo[k] = fmin(lo[k], X[k]);
            hi[k] = fmax(hi[k], X[k]);
        }
        for (int k = 0; k < 2; k++) {
            ba[2 * k] = fmin(ba[2 * k], pt.uv_a[k]);
            ba[2 * k + 1] = fmax(ba[2 * k + 1], pt.uv_a[k]);
            bb[2 * k] = fmin(bb[2 * k], pt.uv_b[k]);
            bb[2 * k + 1] = fmax(bb[2 * k + 1], pt.uv_b[k]);
        }
        one &= J->it[E[x].e / 2].set == set0;
    }
    *pa = one ? J->sets[set0].patch_a : -1;
    *pb = one ? J->sets[set0].patch_b : -1;
    return sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                (hi[2] - lo[2]) * (hi[2] - lo[2]));
}

static void set_outcome(_cb_ssi_stitch_set *sets, slong set, cb_ssi_outcome o)
{
    if (o > sets[set].outcome)
        sets[set].outcome = o;
}

/* The ambiguous group E[0..m): joined within tolerance when small, else refused (keeping the
 * certified merges already made). kind names the cause in the failure message. */
static cb_status ambiguous(joiner *J, const entry *E, slong m, const char *why)
{
    double lo[3], hi[3], ba[4], bb[4];
    int pa, pb;
    double diam = group_box(J, E, m, lo, hi, ba, bb, &pa, &pb);
    const _cb_ssi_stitch_opts *o = J->o;
    if (diam <= CB_SSI_NEAR_NODE * o->tol) {
        cb_ssi_region *g =
            _cb_ssi_add_region(J->r, CB_SSI_REGION_NEAR_NODE, o->face_a, o->face_b, pa, pb, diam);
        if (!g)
            return CB_ERR_NOMEM;
        memcpy(g->lo, lo, sizeof lo);
        memcpy(g->hi, hi, sizeof hi);
        memcpy(g->box_a, ba, sizeof ba);
        memcpy(g->box_b, bb, sizeof bb);
        for (slong x = 0; x < m; x++) {
            uf_union(J->par, E[0].e, E[x].e);
            J->within[E[x].e] = 1;
            set_outcome(J->sets, J->it[E[x].e / 2].set, CB_SSI_WITHIN_TOL);
        }
        return CB_OK;
    }
    char msg[200];
    snprintf(msg, sizeof msg,
             "stitching: %ld curve ends %s span %.3g (more than tol %.3g): not joined",
             (long)m, why, diam, o->tol);
    if (_cb_ssi_add_failure(J->r, o->face_a, o->face_b, pa, pb, CB_ERR_UNSUPPORTED, msg) !=
        CB_OK)
        return CB_ERR_NOMEM;
    cb_ssi_failure *f = J->r->failed + J->r->n_failed - 1;
    f->has_box = 1;
    memcpy(f->box_a, ba, sizeof ba);
    memcpy(f->box_b, bb, sizeof bb);
    for (slong x = 0; x < m; x++)
        set_outcome(J->sets, J->it[E[x].e / 2].set, CB_SSI_REFUSED);
    return CB_OK;
}

/* The candidate group E[0..m) of one line (enclosures overlapping in a chain). Ends already in
 * one class (the same vertex, or joined on another line) stay so; certified relations merge
 * or separate the rest; a pair of classes left undecided is joined when one lies wholly on
 * each side of the line (the bound-match), and anything else makes the group ambiguous. */
static cb_status group(joiner *J, entry *E, slong m)
{
    slong *loc = malloc((size_t)m * sizeof(slong));
    signed char *rel = malloc((size_t)m * (size_t)m);
    if (!loc || !rel) {
        free(loc);
        free(rel);
        return CB_ERR_NOMEM;
    }
    int ncls = 0;
    for (slong x = 0; x < m; x++) {
        slong cx = uf_find(J->par, E[x].e);
        loc[x] = x;
        for (slong y = 0; y < x; y++)
            if (uf_find(J->par, E[y].e) == cx) {
                loc[x] = loc[y];
                break;
            }
        ncls += loc[x] == x;
    }
    cb_status st = CB_OK;
    if (ncls > 1) {
        for (slong x = 0; x < m; x++)
            J->decided[E[x].e] = 1;
        /* Pairwise relations: 1 the same point, 0 different, -1 undecided. */
        for (slong x = 0; x < m; x++) {
            rel[x * m + x] = 1;
            for (slong y = x + 1; y < m; y++) {
                signed char v = loc[x] == loc[y] ? 1 : (signed char)entry_rel(J, E + x, E + y);
                rel[x * m + y] = rel[y * m + x] = v;
            }
        }
        /* Classes merged by "the same point" (transitively). */
        for (int changed = 1; changed;) {
            changed = 0;
            for (slong x = 0; x < m; x++)
                for (slong y = 0; y < m; y++)
                    if (rel[x * m + y] == 1 && loc[x] != loc[y]) {
                        slong lo = FLINT_MIN(loc[x], loc[y]), hi = FLINT_MAX(loc[x], loc[y]);
                        for (slong z = 0; z < m; z++)
                            if (loc[z] == hi)
                                loc[z] = lo;
                        changed = 1;
                    }
        }
        /* Two ends of one class certified different: contradiction. Per pair of classes
         * (indexed by their first entry): different when some pair of their ends is, else
         * undecided; the side of the line each class lies on (0 none yet, 2 mixed). */
        int conflict = 0, ok = 1;
        slong *mate = malloc((size_t)m * sizeof(slong));
        int *half = calloc((size_t)m, sizeof(int));
        if (!mate || !half) {
            free(mate);
            free(half);
            free(loc);
            free(rel);
            return CB_ERR_NOMEM;
        }
        for (slong x = 0; x < m; x++) {
            mate[x] = -1;
            int *h = half + loc[x];
            *h = *h == 0 ? E[x].l->half : (*h == E[x].l->half ? *h : 2);
        }
        /* rel between classes: reuse rel's rows at the representatives (0 once any pair is). */
        for (slong x = 0; x < m; x++)
            for (slong y = 0; y < m; y++) {
                if (loc[x] == loc[y]) {
                    conflict |= rel[x * m + y] == 0;
                    continue;
                }
                if (rel[x * m + y] == 0) {
                    rel[loc[x] * m + loc[y]] = 0;
                    rel[loc[y] * m + loc[x]] = 0;
                }
            }
        for (slong a = 0; a < m && !conflict && ok; a++) {
            if (loc[a] != a)
                continue;
            for (slong b = a + 1; b < m && ok; b++) {
                if (loc[b] != b || rel[a * m + b] == 0)
                    continue;
                /* Undecided: the bound-match needs one whole class on each side of the line,
                 * each class undecided with no other. */
                if (half[a] == 0 || half[a] == 2 || half[a] != -half[b] || mate[a] >= 0 ||
                    mate[b] >= 0)
                    ok = 0;
                else {
                    mate[a] = b;
                    mate[b] = a;
                }
            }
        }
        free(half);
        if (!conflict)
            for (slong x = 0; x < m; x++)
                uf_union(J->par, E[loc[x]].e, E[x].e);
        if (!conflict && ok) {
            for (slong a = 0; a < m; a++)
                if (mate[a] > a)
                    uf_union(J->par, E[a].e, E[mate[a]].e);
        } else {
            st = ambiguous(J, E, m, conflict ? "with contradicting identities on a patch side"
                                             : "on a patch side within their bounds");
        }
        free(mate);
    }
    free(loc);
    free(rel);
    return st;
}

/* Steps 1-3 of _cb_ssi_stitch for the patch routes. */
static cb_status join_ends(joiner *J)
{
    item *it = J->it;
    slong ni = J->ni;
    /* 0. Ends moved onto the point of one tangent region resolved within the tolerance
     * (_cb_ssi_tiny_resolve; its region is listed already). */
    for (slong i = 0; i < ni; i++)
        for (int e = 0; e < (it[i].p->isolated ? 1 : 2); e++) {
            slong rg = it[i].p->end[e].region;
            if (rg < 0 || it[i].p->closed)
                continue;
            J->decided[2 * i + e] = J->within[2 * i + e] = 1;
            set_outcome(J->sets, it[i].set, CB_SSI_WITHIN_TOL);
            for (slong j = 0; j < i; j++)
                for (int f = 0; f < (it[j].p->isolated ? 1 : 2); f++)
                    if (!it[j].p->closed && it[j].p->end[f].region == rg) {
                        uf_union(J->par, 2 * j + f, 2 * i + e);
                        j = i; /* one union suffices: the earlier ones are joined already */
                        break;
                    }
        }
    /* 1. The same vertex of one pair's graph. */
    for (slong i = 0; i < ni; i++)
        for (int e = 0; e < (it[i].p->isolated ? 1 : 2); e++) {
            slong vid = it[i].p->end[e].vid;
            if (vid < 0 || it[i].p->closed)
                continue;
            for (slong j = i; j >= 0 && it[j].set == it[i].set; j--)
                for (int f = 0; f < (it[j].p->isolated ? 1 : 2); f++)
                    if ((j < i || f < e) && !it[j].p->closed && it[j].p->end[f].vid == vid)
                        uf_union(J->par, 2 * j + f, 2 * i + e);
        }
    /* 2. Lines. */
    slong ne = 0;
    for (slong i = 0; i < ni; i++)
        if (!it[i].p->closed)
            for (int e = 0; e < (it[i].p->isolated ? 1 : 2); e++)
                ne += it[i].p->end[e].nl;
    entry *E = malloc((size_t)(ne + 1) * sizeof(entry));
    if (!E)
        return CB_ERR_NOMEM;
    ne = 0;
    for (slong i = 0; i < ni; i++)
        if (!it[i].p->closed)
            for (int e = 0; e < (it[i].p->isolated ? 1 : 2); e++)
                for (int k = 0; k < it[i].p->end[e].nl; k++) {
                    const _cb_ssi_end_line *l = it[i].p->end[e].ln + k;
                    const double *sm = J->o->seam[l->sigma][l->dir];
                    E[ne].e = 2 * i + e;
                    E[ne].l = l;
                    E[ne].c = l->c == sm[1] ? sm[0] : l->c;
                    ne++;
                }
    qsort(E, (size_t)ne, sizeof(entry), cmp_entry);
    cb_status st = CB_OK;
    for (slong a = 0; a < ne && st == CB_OK;) {
        slong b = a + 1;
        double top = E[a].l->hi;
        while (b < ne && E[b].l->sigma == E[a].l->sigma && E[b].l->dir == E[a].l->dir &&
               E[b].c == E[a].c && E[b].l->lo <= top) {
            top = fmax(top, E[b].l->hi);
            b++;
        }
        if (b - a >= 2)
            st = group(J, E + a, b - a);
        a = b;
    }
    free(E);
    /* 3. Ends alone in their class and undecided (on no line, or with no candidate on it):
     * joined with the ends of other pairs within CB_SSI_FREE_JOIN tol, within tolerance. */
    slong *cnt = calloc((size_t)(2 * ni + 1), sizeof(slong));
    entry *G = malloc((size_t)(2 * ni + 1) * sizeof(entry));
    if (!cnt || !G) {
        free(cnt);
        free(G);
        return CB_ERR_NOMEM;
    }
    for (slong e = 0; e < 2 * ni; e++)
        if (!it[e / 2].p->closed && !(it[e / 2].p->isolated && e % 2))
            cnt[uf_find(J->par, e)]++;
    for (slong e = 0; e < 2 * ni && st == CB_OK; e++) {
        if (it[e / 2].p->closed || (it[e / 2].p->isolated && e % 2) || J->decided[e] ||
            cnt[uf_find(J->par, e)] != 1)
            continue;
        slong m = 0;
        G[m++] = (entry){e, NULL, 0};
        for (slong f = 0; f < 2 * ni; f++) {
            if (f == e || it[f / 2].p->closed || (it[f / 2].p->isolated && f % 2) ||
                it[f / 2].set == it[e / 2].set ||
                uf_find(J->par, f) == uf_find(J->par, e))
                continue;
            if (d3(end_xyz(it, e), end_xyz(it, f)) <= CB_SSI_FREE_JOIN * J->o->tol)
                G[m++] = (entry){f, NULL, 0};
        }
        if (m < 2)
            continue;
        st = ambiguous(J, G, m, "on no common patch side");
        for (slong x = 0; x < m; x++)
            J->decided[G[x].e] = 1;
    }
    free(cnt);
    free(G);
    return st;
}

/* 1 when every point of piece p lies on the side of sigma's patch (domain box dom) in
 * direction dir at value c (within CB_SSI_ON_SIDE_EPS of the box). */
static int along(const _cb_ssi_piece *p, int sigma, int dir, double c, const double dom[4])
{
    double w = dom[2 * dir + 1] - dom[2 * dir];
    if (!(w > 0))
        return 0;
    for (slong k = 0; k < p->n; k++) {
        double x = sigma ? p->pt[k].st[dir] : p->pt[k].uv[dir];
        if (!(fabs(x - c) <= CB_SSI_ON_SIDE_EPS * w))
            return 0;
    }
    return 1;
}

/* Whether pieces a (set sa) and b (set sb) both run along one side of a patch of the same
 * surface. */
static int along_same_side(const _cb_ssi_stitch_set *sa, const _cb_ssi_piece *a,
                           const _cb_ssi_stitch_set *sb, const _cb_ssi_piece *b)
{
    for (int sigma = 0; sigma < 2; sigma++) {
        const double *da = sigma ? sa->qdom : sa->pdom, *db = sigma ? sb->qdom : sb->pdom;
        for (int dir = 0; dir < 2; dir++)
            for (int end = 0; end < 2; end++) {
                double c = da[2 * dir + end];
                if (!isfinite(c))
                    continue;
                if (!along(a, sigma, dir, c, da))
                    continue;
                for (int eb = 0; eb < 2; eb++)
                    if (db[2 * dir + eb] == c && along(b, sigma, dir, c, db))
                        return 1;
            }
    }
    return 0;
}

/* Drops the folds of curve c (ssi_tol.h, CB_SSI_FOLD): a run of points that leaves a point
 * and comes back to it, every point of the run within CB_SSI_FOLD_REACH tol of it and within
 * CB_SSI_FOLD tol of the chord from it to the run's farthest point, which is farther than
 * CB_SSI_FOLD tol. */
static void drop_folds(cb_ssi_curve *c, double tol)
{
    double eps = CB_SSI_FOLD * tol, reach = CB_SSI_FOLD_REACH * tol;
    slong m = 0; /* points kept: c->pt[0 .. m) */
    for (slong k = 0; k < c->n; k++) {
        const double *x = c->pt[k].xyz;
        slong back = -1;
        for (slong i = m - 2; i >= 0 && d3(c->pt[i].xyz, x) <= reach; i--)
            if (d3(c->pt[i].xyz, x) <= eps) {
                back = i;
                break;
            }
        if (back >= 0) {
            slong far = back + 1;
            for (slong i = back + 1; i < m; i++)
                if (d3(c->pt[i].xyz, x) > d3(c->pt[far].xyz, x))
                    far = i;
            /* (points that only repeat pt[back], as a seam's two lifts do, are no fold) */
            int thin = d3(c->pt[far].xyz, x) > eps;
            double chord[6];
            memcpy(chord, c->pt[back].xyz, sizeof c->pt[back].xyz);
            memcpy(chord + 3, c->pt[far].xyz, sizeof c->pt[far].xyz);
            for (slong i = back + 1; i < m && thin; i++)
                thin = polyline_dist(c->pt[i].xyz, chord, 2) <= eps;
            /* The fold goes, and pt[k], at pt[back] within tol, takes its place: the curve's
             * last point stays (a closed curve's repeats its first), its first stays. */
            if (thin && !(back == 0 && k == c->n - 1)) {
                m = back > 0 ? back : 1;
                if (back > 0)
                    c->pt[m++] = c->pt[k];
                continue;
            }
        }
        c->pt[m++] = c->pt[k];
    }
    c->n = m;
}

cb_status _cb_ssi_stitch(cb_ssi_result_t r, _cb_ssi_stitch_set *sets, slong nsets,
                         const _cb_ssi_stitch_opts *o)
{
    slong ni = 0;
    for (slong s = 0; s < nsets; s++) {
        ni += sets[s].ps->n;
        sets[s].outcome = CB_SSI_CERTIFIED;
    }
    item *it = calloc((size_t)ni + 1, sizeof(item));
    node *nodes = malloc((size_t)(2 * ni + 1) * sizeof(node));
    slong *par = malloc((size_t)(2 * ni + 1) * sizeof(slong));
    slong *nid = malloc((size_t)(2 * ni + 1) * sizeof(slong));
    char *decided = calloc((size_t)(2 * ni + 1), 1), *within = calloc((size_t)(2 * ni + 1), 1);
    if (!it || !nodes || !par || !nid || !decided || !within) {
        free(it);
        free(nodes);
        free(par);
        free(nid);
        free(decided);
        free(within);
        return CB_ERR_NOMEM;
    }
    cb_status st = CB_OK;
    slong m = 0;
    for (slong s = 0; s < nsets; s++)
        for (slong k = 0; k < sets[s].ps->n; k++) {
            it[m].p = sets[s].ps->p + k;
            it[m].set = s;
            it[m].node[0] = it[m].node[1] = -1;
            m++;
        }
    for (slong e = 0; e < 2 * ni; e++)
        par[e] = e;
    double jtol = CB_SSI_CLOSED_FORM_JOIN * o->tol;
    if (o->closed_form) {
        /* The closed forms' rule: ends within jtol are one node (in piece order). */
        for (slong e = 0; e < 2 * ni; e++) {
            const _cb_ssi_piece *p = it[e / 2].p;
            if (p->isolated || p->closed)
                continue;
            for (slong f = 0; f < e; f++) {
                const _cb_ssi_piece *q = it[f / 2].p;
                if (q->isolated || q->closed || uf_find(par, f) != f)
                    continue;
                if (d3(end_xyz(it, f), end_xyz(it, e)) <= jtol) {
                    uf_union(par, f, e);
                    break;
                }
            }
        }
    } else {
        joiner J = {it, ni, par, decided, within, sets, o, r};
        st = join_ends(&J);
    }
    /* Patch routes: a piece whose points all stay within CB_SSI_DEGENERATE_PIECE tol of its
     * first one (a curve through a corner of the patch grid, seen by the pairs beside it as a
     * piece of round-off length) is dropped and its ends made one node, within tolerance. */
    /* Per class: the set of its first end, or -2 when it holds ends of several sets. */
    slong *cset = NULL;
    if (!o->closed_form) {
        cset = malloc((size_t)(2 * ni + 1) * sizeof(slong));
        if (!cset)
            st = CB_ERR_NOMEM;
        for (slong e = 0; e < 2 * ni && cset; e++)
            cset[e] = -1;
        for (slong e = 0; e < 2 * ni && cset; e++) {
            const _cb_ssi_piece *p = it[e / 2].p;
            if (p->closed || (p->isolated && e % 2))
                continue;
            slong rt = uf_find(par, e);
            cset[rt] = cset[rt] == -1 || cset[rt] == it[e / 2].set ? it[e / 2].set : -2;
        }
    }
    for (slong i = 0; i < ni && st == CB_OK && !o->closed_form; i++) {
        const _cb_ssi_piece *p = it[i].p;
        if (p->isolated || p->closed)
            continue;
        int moves = 0, zero = 1;
        for (slong k = 1; k < p->n && !moves; k++) {
            moves = d3(p->xyz + 3 * k, p->xyz) > CB_SSI_DEGENERATE_PIECE * o->tol;
            zero &= !memcmp(p->xyz + 3 * k, p->xyz, 3 * sizeof(double));
        }
        if (moves)
            continue;
        it[i].dropped = 1;
        /* A piece of no extent at all, one end a vertex of its graph whose class is already
         * joined to another pair's ends: the curve runs on through that vertex without it (a
         * curve through a corner of the patch grid, seen by the pair beside it as a single
         * point); dropped, its other end left out, nothing merged. */
        int redundant = 0;
        for (int e = 0; e < 2 && zero; e++)
            redundant |= p->end[e].vid >= 0 && cset[uf_find(par, 2 * i + e)] == -2;
        if (redundant)
            continue;
        double lo[3], hi[3], ba[4], bb[4], diam = 0;
        for (int k = 0; k < 3; k++) {
            lo[k] = HUGE_VAL;
            hi[k] = -HUGE_VAL;
        }
        for (int k = 0; k < 4; k++)
            ba[k] = bb[k] = (k % 2) ? -HUGE_VAL : HUGE_VAL;
        for (slong k = 0; k < p->n; k++) {
            cb_ssi_point pt;
            out_point(&pt, p->xyz + 3 * k, p->pt + k, o->swapped);
            for (int q = 0; q < 3; q++) {
                lo[q] = fmin(lo[q], pt.xyz[q]);
                hi[q] = fmax(hi[q], pt.xyz[q]);
            }
            for (int q = 0; q < 2; q++) {
                ba[2 * q] = fmin(ba[2 * q], pt.uv_a[q]);
                ba[2 * q + 1] = fmax(ba[2 * q + 1], pt.uv_a[q]);
                bb[2 * q] = fmin(bb[2 * q], pt.uv_b[q]);
                bb[2 * q + 1] = fmax(bb[2 * q + 1], pt.uv_b[q]);
            }
        }
        for (int q = 0; q < 3; q++)
            diam += (hi[q] - lo[q]) * (hi[q] - lo[q]);
        const _cb_ssi_stitch_set *S = sets + it[i].set;
        cb_ssi_region *g = _cb_ssi_add_region(r, CB_SSI_REGION_NEAR_NODE, o->face_a, o->face_b,
                                              S->patch_a, S->patch_b, sqrt(diam));
        if (!g) {
            st = CB_ERR_NOMEM;
            break;
        }
        memcpy(g->lo, lo, sizeof lo);
        memcpy(g->hi, hi, sizeof hi);
        memcpy(g->box_a, ba, sizeof ba);
        memcpy(g->box_b, bb, sizeof bb);
        uf_union(par, 2 * i, 2 * i + 1);
        within[2 * i] = within[2 * i + 1] = 1;
        set_outcome(sets, it[i].set, CB_SSI_WITHIN_TOL);
    }
    free(cset);
    /* Nodes: classes of open pieces' ends, numbered in order of their first end. */
    slong nn = 0;
    for (slong e = 0; e < 2 * ni; e++)
        nid[e] = -1;
    for (slong e = 0; e < 2 * ni && st == CB_OK; e++) {
        const _cb_ssi_piece *p = it[e / 2].p;
        if (p->isolated || p->closed)
            continue;
        slong rt = uf_find(par, e);
        if (nid[rt] < 0) {
            nid[rt] = nn;
            memcpy(nodes[nn].X, end_xyz(it, rt), 3 * sizeof(double));
            nodes[nn].pq = *end_pq(it, rt);
            nodes[nn].deg = 0;
            nodes[nn].within = 0;
            nn++;
        }
        it[e / 2].node[e % 2] = nid[rt];
        nodes[nid[rt]].within |= within[e];
    }
    /* A piece that never leaves its node (a touch at a patch side) adds nothing. */
    double dtol = (o->closed_form ? jtol : CB_SSI_DEGENERATE_PIECE * o->tol);
    for (slong i = 0; i < ni && st == CB_OK; i++) {
        const _cb_ssi_piece *p = it[i].p;
        if (p->isolated || p->closed || it[i].node[0] != it[i].node[1])
            continue;
        int moves = 0;
        for (slong k = 0; k < p->n && !moves; k++)
            moves = d3(p->xyz + 3 * k, nodes[it[i].node[0]].X) > dtol;
        if (!moves)
            it[i].dropped = 1;
    }
    /* Duplicates: a curve on a patch side shared by two pairs is found by both. */
    for (slong i = 0; i < ni && st == CB_OK; i++) {
        if (it[i].dropped || it[i].p->isolated || it[i].p->closed)
            continue;
        const _cb_ssi_piece *p = it[i].p;
        const double *mid = p->xyz + 3 * (p->n / 2);
        for (slong j = 0; j < i; j++) {
            if (it[j].dropped || it[j].p->isolated || it[j].p->closed)
                continue;
            int same = (it[j].node[0] == it[i].node[0] && it[j].node[1] == it[i].node[1]) ||
                       (it[j].node[0] == it[i].node[1] && it[j].node[1] == it[i].node[0]);
            if (!same)
                continue;
            if (o->closed_form ? polyline_dist(mid, it[j].p->xyz, it[j].p->n) <= o->chord + jtol
                               : along_same_side(sets + it[j].set, it[j].p, sets + it[i].set,
                                                 p)) {
                it[i].dropped = 1;
                break;
            }
        }
    }
    for (slong i = 0; i < ni; i++)
        if (!it[i].dropped && it[i].node[0] >= 0) {
            nodes[it[i].node[0]].deg++;
            nodes[it[i].node[1]].deg++;
        }
    /* Chains through nodes of degree 2. */
    slong nc0 = r->n_curves;
    for (slong i = 0; i < ni && st == CB_OK; i++) {
        if (it[i].dropped || it[i].used || it[i].p->isolated)
            continue;
        slong alloc = 0;
        cb_ssi_curve *c = _cb_ssi_add_curve(r, o->face_a, o->face_b);
        if (!c) {
            st = CB_ERR_NOMEM;
            break;
        }
        if (it[i].p->closed) {
            it[i].used = 1;
            st = append_piece(c, &alloc, it + i, 0, nodes, o->swapped);
            c->closed = 1;
            c->tangential = it[i].p->tangential;
            if (it[i].p->within)
                c->certified = 0;
            continue;
        }
        /* Walk backwards from piece i to the chain's start (a node of degree != 2) or around
         * the loop back to i. */
        slong cur = i;
        int rev = 0;
        for (;;) {
            slong nd = it[cur].node[rev ? 1 : 0];
            if (nodes[nd].deg != 2)
                break;
            slong nxt = -1;
            int nrev = 0;
            for (slong j = 0; j < ni && nxt < 0; j++) {
                if (j == cur || it[j].dropped || it[j].p->isolated || it[j].p->closed)
                    continue;
                if (it[j].node[1] == nd) {
                    nxt = j;
                    nrev = 0;
                } else if (it[j].node[0] == nd) {
                    nxt = j;
                    nrev = 1;
                }
            }
            if (nxt < 0 || nxt == i)
                break;
            cur = nxt;
            rev = nrev;
        }
        slong first = cur;
        c->tangential = 1;
        for (;;) {
            it[cur].used = 1;
            c->tangential &= it[cur].p->tangential != 0;
            /* A join resolved within tolerance at either end of the piece. */
            if (nodes[it[cur].node[0]].within || nodes[it[cur].node[1]].within ||
                it[cur].p->within)
                c->certified = 0;
            st = append_piece(c, &alloc, it + cur, rev, nodes, o->swapped);
            if (st != CB_OK)
                break;
            slong nd = it[cur].node[rev ? 0 : 1];
            if (nodes[nd].deg != 2)
                break;
            slong nxt = -1;
            int nrev = 0;
            for (slong j = 0; j < ni && nxt < 0; j++) {
                if (j == cur || it[j].dropped || it[j].p->isolated || it[j].p->closed)
                    continue;
                if (it[j].node[0] == nd) {
                    nxt = j;
                    nrev = 0;
                } else if (it[j].node[1] == nd) {
                    nxt = j;
                    nrev = 1;
                }
            }
            if (nxt < 0)
                break;
            if (nxt == first || it[nxt].used) {
                c->closed = nxt == first;
                break;
            }
            cur = nxt;
            rev = nrev;
        }
    }
    for (slong k = nc0; k < r->n_curves && st == CB_OK; k++)
        drop_folds(r->curve + k, o->tol);
    /* Isolated points not at a node or at an earlier point: closed forms by distance, the
     * patch routes by the joins above. */
    slong p0 = r->n_points;
    for (slong i = 0; i < ni && st == CB_OK; i++) {
        const _cb_ssi_piece *p = it[i].p;
        if (!p->isolated)
            continue;
        int dup = 0, w = 0;
        if (o->closed_form) {
            for (slong q = 0; q < nn && !dup; q++)
                dup = nodes[q].deg > 0 && d3(nodes[q].X, p->xyz) <= jtol;
            for (slong q = p0; q < r->n_points && !dup; q++)
                dup = d3(r->point[q].p.xyz, p->xyz) <= jtol;
        } else {
            slong rt = uf_find(par, 2 * i);
            for (slong e = 0; e < 2 * ni && !dup; e++) {
                if (e == 2 * i || uf_find(par, e) != rt)
                    continue;
                const _cb_ssi_piece *q = it[e / 2].p;
                if (q->closed || (q->isolated && e % 2))
                    continue;
                /* At a node of a kept piece, or at an earlier isolated point. */
                dup = q->isolated ? e < 2 * i : !it[e / 2].dropped;
            }
            w = within[2 * i];
        }
        if (dup)
            continue;
        cb_ssi_isolated *pt = _cb_ssi_add_point(r, o->face_a, o->face_b);
        if (!pt) {
            st = CB_ERR_NOMEM;
            break;
        }
        out_point(&pt->p, p->xyz, p->pt, o->swapped);
        pt->certified = !w;
    }
    free(it);
    free(nodes);
    free(par);
    free(nid);
    free(decided);
    free(within);
    return st;
}
