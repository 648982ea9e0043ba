/* trace.c — tracing the branches of a certified topology graph (paper section 4.4, appendix B).
 *
 * The graph of cb_ctopo_compute cuts the curve into edges that are graphs t = y(s) between
 * consecutive vertices with no critical value strictly between them. There the roots of
 * h(s, .) in [0, 1] are simple and constant in number, so a branch is "the root of rank k"
 * and can be followed by solving h(s, t) = 0 for t at each s: no predictor can jump to a
 * neighbouring branch, which is the failure mode of plain marching near singular points. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "ssi/ssi.h"

/* --------------------------------------------------------------- squarefree part in doubles */

void _cb_ssi_sqf_init(_cb_ssi_sqf *h)
{
    h->ds = h->dt = -1;
    h->hd = NULL;
}

void _cb_ssi_sqf_clear(_cb_ssi_sqf *h)
{
    free(h->hd);
    _cb_ssi_sqf_init(h);
}

cb_status _cb_ssi_sqf_set(_cb_ssi_sqf *h, const cb_bipoly_struct *hp)
{
    _cb_ssi_sqf_clear(h);
    h->ds = FLINT_MAX(cb_bipoly_deg_s(hp), 0);
    h->dt = FLINT_MAX(hp->len - 1, 0);
    slong len = (h->ds + 1) * (h->dt + 1);
    h->hd = calloc((size_t)len, sizeof(double));
    if (!h->hd)
        return CB_ERR_NOMEM;
    slong emax = WORD_MIN;
    for (slong j = 0; j < hp->len; j++)
        for (slong i = 0; i < fmpz_poly_length(hp->c + j); i++)
            if (!fmpz_is_zero(hp->c[j].coeffs + i))
                emax = FLINT_MAX(emax, (slong)fmpz_bits(hp->c[j].coeffs + i));
    for (slong j = 0; j < hp->len; j++)
        for (slong i = 0; i < fmpz_poly_length(hp->c + j); i++) {
            const fmpz *c = hp->c[j].coeffs + i;
            if (fmpz_is_zero(c))
                continue;
            slong ex;
            double m = fmpz_get_d_2exp(&ex, c);
            h->hd[i * (h->dt + 1) + j] = ldexp(m, (int)(ex - emax));
        }
    return CB_OK;
}

/* Coefficients a[j] of h(s, t) in t at a fixed s (Horner in s). */
static void sqf_at_s(double *a, const _cb_ssi_sqf *h, double s)
{
    for (slong j = 0; j <= h->dt; j++) {
        double v = 0;
        for (slong i = h->ds; i >= 0; i--)
            v = v * s + h->hd[i * (h->dt + 1) + j];
        a[j] = v;
    }
}

/* --------------------------------------------------------------- univariate roots ---------- */

static double horner(const double *a, int deg, double t)
{
    double v = 0;
    for (int j = deg; j >= 0; j--)
        v = v * t + a[j];
    return v;
}

int _cb_ssi_roots01(double *roots, const double *a, int deg)
{
    while (deg > 0 && a[deg] == 0)
        deg--;
    if (deg <= 0)
        return 0;
    double d[CB_MAX_DEGREE * 4 + 1], cut[CB_MAX_DEGREE * 4 + 2];
    for (int j = 1; j <= deg; j++)
        d[j - 1] = j * a[j];
    int nc = 0;
    cut[nc++] = 0;
    nc += _cb_ssi_roots01(cut + nc, d, deg - 1);
    cut[nc++] = 1;
    int n = 0;
    for (int k = 0; k + 1 < nc; k++) {
        double lo = cut[k], hi = cut[k + 1];
        double flo = horner(a, deg, lo), fhi = horner(a, deg, hi);
        if (flo == 0) {
            if (n == 0 || roots[n - 1] != lo)
                roots[n++] = lo;
            continue;
        }
        if (fhi == 0) {
            if (k + 2 == nc)
                roots[n++] = hi;
            continue;
        }
        if ((flo < 0) == (fhi < 0))
            continue;
        /* Newton inside the sign-change bracket (between consecutive critical points the
         * polynomial is monotone), bisecting whenever a step would leave it: a handful of
         * evaluations where bisection to the last bit took about 55 (at degree 24 these roots
         * were 80% of a pair's time). */
        double x = 0.5 * (lo + hi);
        for (int it = 0; it < 200; it++) {
            double fx = horner(a, deg, x);
            if (fx == 0) {
                lo = hi = x;
                break;
            }
            if ((fx < 0) == (flo < 0))
                lo = x;
            else
                hi = x;
            double dfx = horner(d, deg - 1, x), xn = x - fx / dfx;
            if (!(xn > lo && xn < hi))
                xn = 0.5 * (lo + hi);
            if (xn <= lo || xn >= hi || xn == x)
                break;
            x = xn;
        }
        roots[n++] = lo == hi ? lo : x;
    }
    return n;
}

/* --------------------------------------------------------------- containers ---------------- */

void _cb_ssi_trace_set_init(_cb_ssi_trace_set *ts)
{
    ts->n = ts->alloc = 0;
    ts->c = NULL;
}

void _cb_ssi_trace_set_clear(_cb_ssi_trace_set *ts)
{
    for (slong i = 0; i < ts->n; i++) {
        free(ts->c[i].st);
        free(ts->c[i].fixed);
    }
    free(ts->c);
    _cb_ssi_trace_set_init(ts);
}

/* A new empty curve; NULL when out of memory (ts is left as it was). */
static _cb_ssi_trace_curve *trace_set_add(_cb_ssi_trace_set *ts)
{
    if (ts->n == ts->alloc) {
        slong alloc = ts->alloc ? 2 * ts->alloc : 8;
        _cb_ssi_trace_curve *q = realloc(ts->c, (size_t)alloc * sizeof(*q));
        if (!q)
            return NULL;
        ts->c = q;
        ts->alloc = alloc;
    }
    _cb_ssi_trace_curve *c = ts->c + ts->n++;
    memset(c, 0, sizeof(*c));
    return c;
}

/* Appends (s, t) unless the curve ends there; CB_ERR_NOMEM leaves c as it was. */
static cb_status curve_push(_cb_ssi_trace_curve *c, double s, double t, unsigned fixed)
{
    if (c->n > 0 && c->st[2 * c->n - 2] == s && c->st[2 * c->n - 1] == t)
        return CB_OK;
    if (c->n == c->alloc) {
        /* alloc grows only once both arrays have: a larger st alone is harmless. */
        slong alloc = c->alloc ? 2 * c->alloc : 32;
        double *st = realloc(c->st, (size_t)alloc * 2 * sizeof(double));
        if (!st)
            return CB_ERR_NOMEM;
        c->st = st;
        unsigned *fixed_q = realloc(c->fixed, (size_t)alloc * sizeof(unsigned));
        if (!fixed_q)
            return CB_ERR_NOMEM;
        c->fixed = fixed_q;
        c->alloc = alloc;
    }
    c->st[2 * c->n] = s;
    c->st[2 * c->n + 1] = t;
    c->fixed[c->n] = fixed;
    c->n++;
    return CB_OK;
}

/* Q-side fixed bits of a vertex on the box sides. */
static unsigned vertex_fixed(const cb_ctopo_vertex_struct *v)
{
    unsigned f = 0;
    if (v->sides & (CB_CTOPO_SIDE_S0 | CB_CTOPO_SIDE_S1))
        f |= 4u;
    if (v->sides & (CB_CTOPO_SIDE_T0 | CB_CTOPO_SIDE_T1))
        f |= 8u;
    return f;
}

/* --------------------------------------------------------------- one edge ------------------ */

typedef struct {
    const _cb_ssi_sqf *h;
    int rank, count;   /* branch = root number rank of count roots */
    int vertical;
    double alpha;      /* s of a vertical edge */
    double *work;      /* dt + 1 coefficients */
    double *roots;
} edge_param;

/* The point of the edge at parameter x (s for a branch, t for a vertical edge); 0 when the
 * root count differs from the certified one (x too close to a critical end for doubles). */
static int edge_point(double st[2], edge_param *E, double x)
{
    if (E->vertical) {
        st[0] = E->alpha;
        st[1] = x;
        return 1;
    }
    sqf_at_s(E->work, E->h, x);
    int n = _cb_ssi_roots01(E->roots, E->work, (int)E->h->dt);
    if (n != E->count)
        return 0;
    st[0] = x;
    st[1] = E->roots[E->rank];
    return 1;
}

static double dist3(const double a[3], const double b[3])
{
    return sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                (a[2] - b[2]) * (a[2] - b[2]));
}

/* Appends the points of edge e from vertex `from` to vertex `to` (end point included, start
 * point assumed present); CB_ERR_NOMEM when out could not grow. */
static cb_status trace_edge(_cb_ssi_trace_curve *out, const cb_ctopo_t T, slong e, int reversed,
                            const _cb_ssi_sqf *h, _cb_ssi_lift_fn lift, const void *lift_ctx,
                            double chord, double max_seg, double *work, double *roots)
{
    const cb_ctopo_edge_struct *E = T->edge + e;
    const cb_ctopo_vertex_struct *va = T->vertex + (reversed ? E->v1 : E->v0);
    const cb_ctopo_vertex_struct *vb = T->vertex + (reversed ? E->v0 : E->v1);
    edge_param P = {h, 0, 0, E->vertical, va->s, work, roots};
    double xa = E->vertical ? va->t : va->s, xb = E->vertical ? vb->t : vb->s;
    double span = xb - xa;
    if (!E->vertical && span != 0) {
        /* Rank at a regular end (a helping point if there is one: its s is not critical, so
         * the count there is the count inside), else just inside the other end. When both
         * ends qualify, the one where the branch's root is best separated from the others
         * (a helping point next to a fold sees both branches of the fold almost equal, and
         * the nearest root there may be the other branch's), among those that see the count
         * of the edge's middle (a root at round-off distance from a side of the box may be
         * lost at one end). */
        const cb_ctopo_vertex_struct *ends[2] = {va, vb};
        sqf_at_s(work, h, 0.5 * (xa + xb));
        int n_mid = _cb_ssi_roots01(roots, work, (int)h->dt);
        int n = -1, best = 0;
        double best_sep = -1;
        for (int pass = 0; pass < 2 && n < 0; pass++)
            for (int k = 0; k < 2; k++) {
                const cb_ctopo_vertex_struct *r = ends[k], *o = ends[1 - k];
                int regular = r->kind < CB_CTOPO_CRITICAL && !r->singular;
                int usable = r->kind == CB_CTOPO_HELPING ||
                             (regular && o->kind != CB_CTOPO_HELPING);
                if (pass == 1)
                    usable = k == ((vb->kind == CB_CTOPO_HELPING && va->kind != CB_CTOPO_HELPING) ||
                                   !(va->kind < CB_CTOPO_CRITICAL && !va->singular));
                if (!usable)
                    continue;
                /* At the end, or just inside it (towards the other end: span has the
                 * direction of travel, so also for an edge walked against s); where the count
                 * there differs from the middle's, further inside: a helping line at round-off distance from a
                 * critical one (a rational critical value) sees there the near-double roots
                 * of another branch's fold as real in doubles. */
                static const double inset[3] = {1e-6, 1e-4, 1e-2};
                int nr = 0;
                for (int q = r->kind == CB_CTOPO_HELPING ? -1 : 0; q < 3; q++) {
                    double x = q < 0 ? r->s : r->s + (k == 0 ? 1 : -1) * inset[q] * span;
                    sqf_at_s(work, h, x);
                    nr = _cb_ssi_roots01(roots, work, (int)h->dt);
                    if (pass == 1 || nr == n_mid)
                        break;
                }
                if (nr == 0 || (pass == 0 && nr != n_mid))
                    continue;
                int b = 0;
                for (int q = 1; q < nr; q++)
                    if (fabs(roots[q] - r->t) < fabs(roots[b] - r->t))
                        b = q;
                double sep = HUGE_VAL;
                for (int q = 0; q < nr; q++)
                    if (q != b)
                        sep = fmin(sep, fabs(roots[q] - roots[b]));
                if (sep > best_sep) {
                    best_sep = sep;
                    best = b;
                    n = nr;
                }
            }
        if (n < 0)
            n = 0;
        /* A helping end whose line holds as many roots as the middle: its exact rank is the
         * branch's (the count is constant between critical lines). Doubles cannot tell the
         * roots apart there when the helping line lies a round-off distance from a rational
         * critical value, next to a fold. */
        const cb_ctopo_vertex_struct *hv = va->kind == CB_CTOPO_HELPING ? va
                                           : vb->kind == CB_CTOPO_HELPING ? vb
                                                                          : NULL;
        if (hv && hv->count == n_mid && n_mid > 0) {
            best = (int)hv->rank;
            n = n_mid;
        } else if (best_sep < 1e-3 && n_mid > 0) {
            /* Both ends ambiguous: at the middle, the root nearest the ends' mean t. */
            sqf_at_s(work, h, 0.5 * (xa + xb));
            n = _cb_ssi_roots01(roots, work, (int)h->dt);
            double target = 0.5 * (va->t + vb->t);
            best = 0;
            for (int q = 1; q < n; q++)
                if (fabs(roots[q] - target) < fabs(roots[best] - target))
                    best = q;
        }
        P.rank = best;
        P.count = n;
        if (n == 0)
            return curve_push(out, vb->s, vb->t, vertex_fixed(vb));
    }
    double cur[2] = {va->s, va->t}, Xc[3];
    lift(Xc, lift_ctx, cur[0], cur[1]);
    double x = xa, step = span / 8;
    const double min_step = 1e-13 * (fabs(span) > 0 ? 1 : 0);
    for (int guard = 0; guard < 100000 && x != xb; guard++) {
        double xn = x + step;
        int last = (span > 0) ? (xn >= xb) : (xn <= xb);
        double nxt[2], mid[2], Xn[3], Xm[3];
        int ok;
        if (last) {
            xn = xb;
            nxt[0] = vb->s;
            nxt[1] = vb->t;
            ok = 1;
        } else {
            ok = edge_point(nxt, &P, xn);
        }
        /* A step below the spacing of doubles at x makes no progress (an edge between a
         * node on a rational critical line and its helping line a round-off distance away:
         * it cycled 100000 times, 80% of the paper's Example 2). */
        if (ok && !last && xn == x)
            ok = 0;
        if (ok)
            ok = edge_point(mid, &P, 0.5 * (x + xn));
        if (ok) {
            lift(Xn, lift_ctx, nxt[0], nxt[1]);
            lift(Xm, lift_ctx, mid[0], mid[1]);
            double sag = sqrt((Xm[0] - 0.5 * (Xc[0] + Xn[0])) * (Xm[0] - 0.5 * (Xc[0] + Xn[0])) +
                              (Xm[1] - 0.5 * (Xc[1] + Xn[1])) * (Xm[1] - 0.5 * (Xc[1] + Xn[1])) +
                              (Xm[2] - 0.5 * (Xc[2] + Xn[2])) * (Xm[2] - 0.5 * (Xc[2] + Xn[2])));
            ok = sag <= chord && dist3(Xc, Xn) <= max_seg;
            if (ok && sag < 0.25 * chord)
                step *= 1.5;
        }
        if (!ok && fabs(step) > min_step * fabs(span) && x + 0.5 * step != x) {
            step *= 0.5;
            continue;
        }
        if (!ok && !last) {
            /* Below the resolution of doubles next to a critical end: the end is the rest. */
            xn = xb;
            nxt[0] = vb->s;
            nxt[1] = vb->t;
            lift(Xn, lift_ctx, nxt[0], nxt[1]);
        }
        x = xn;
        cur[0] = nxt[0];
        cur[1] = nxt[1];
        memcpy(Xc, Xn, sizeof Xc);
        if (curve_push(out, cur[0], cur[1], x == xb ? vertex_fixed(vb) : 0u) != CB_OK)
            return CB_ERR_NOMEM;
        if ((span > 0 && x + step > xb) || (span < 0 && x + step < xb))
            step = xb - x;
    }
    return curve_push(out, vb->s, vb->t, vertex_fixed(vb));
}

/* --------------------------------------------------------------- vertex refinement -------- */

static double sqf_eval(const _cb_ssi_sqf *h, double s, double t)
{
    double acc = 0;
    for (slong i = h->ds; i >= 0; i--) {
        double row = 0;
        for (slong j = h->dt; j >= 0; j--)
            row = row * t + h->hd[i * (h->dt + 1) + j];
        acc = acc * s + row;
    }
    return acc;
}

/* dh/dt at (s, t). */
static double sqf_eval_t(const _cb_ssi_sqf *h, double s, double t)
{
    double acc = 0;
    for (slong i = h->ds; i >= 0; i--) {
        double row = 0;
        for (slong j = h->dt; j >= 1; j--)
            row = row * t + j * h->hd[i * (h->dt + 1) + j];
        acc = acc * s + row;
    }
    return acc;
}

void _cb_ssi_vertex_refine(cb_ctopo_t T, const _cb_ssi_sqf *h)
{
    for (slong v = 0; v < T->n_vertices; v++) {
        cb_ctopo_vertex_struct *V = T->vertex + v;
        if (V->kind == CB_CTOPO_HELPING || fmpq_equal(V->t_lo, V->t_hi))
            continue;
        double a = fmpq_get_d(V->t_lo), b = fmpq_get_d(V->t_hi);
        int simple = V->kind == CB_CTOPO_FIBRE || V->kind == CB_CTOPO_BOUNDARY;
        /* A simple root: h changes sign over the box. A multiple one (fold, cusp, isolated
         * point): h_t does, or else |h| is least at it. A simple root whose h shows one sign
         * at both ends in doubles lies within round-off of an end (the box holds one root and
         * h is monotone in t there): |h| is least at it too. Left at the box's midpoint, such
         * a vertex put a spur half a patch long into the curve (a plane parallel to a torus's
         * axis crossing a rational patch's side a round-off distance from its corner). */
        double (*f)(const _cb_ssi_sqf *, double, double) = simple ? sqf_eval : sqf_eval_t;
        double fa = f(h, V->s, a), fb = f(h, V->s, b);
        if (!(fa * fb < 0)) {
            const double g = 0.6180339887498949;
            double x1 = b - g * (b - a), x2 = a + g * (b - a);
            double f1 = fabs(sqf_eval(h, V->s, x1)), f2 = fabs(sqf_eval(h, V->s, x2));
            for (int it = 0; it < 80; it++) {
                if (f1 < f2) {
                    b = x2;
                    x2 = x1;
                    f2 = f1;
                    x1 = b - g * (b - a);
                    f1 = fabs(sqf_eval(h, V->s, x1));
                } else {
                    a = x1;
                    x1 = x2;
                    f1 = f2;
                    x2 = a + g * (b - a);
                    f2 = fabs(sqf_eval(h, V->s, x2));
                }
            }
            V->t = f1 < f2 ? x1 : x2;
            continue;
        }
        for (int it = 0; it < 80 && b - a > 0; it++) {
            double m = 0.5 * (a + b), fm = f(h, V->s, m);
            if (m <= a || m >= b)
                break;
            if ((fm < 0) == (fa < 0)) {
                a = m;
                fa = fm;
            } else {
                b = m;
            }
        }
        V->t = 0.5 * (a + b);
    }
}

/* --------------------------------------------------------------- chains -------------------- */

cb_status _cb_ssi_trace(_cb_ssi_trace_set *out, const cb_ctopo_t T, const _cb_ssi_sqf *h,
                        _cb_ssi_lift_fn lift, const void *lift_ctx, double chord, double max_seg)
{
    slong nv = T->n_vertices, ne = T->n_edges;
    slong *deg = calloc((size_t)nv + 1, sizeof(slong));
    slong *start = calloc((size_t)nv + 2, sizeof(slong));
    slong *inc = malloc((size_t)(2 * ne + 1) * sizeof(slong));
    char *used = calloc((size_t)ne + 1, 1);
    double *work = malloc((size_t)(h->dt + 2) * sizeof(double));
    double *roots = malloc((size_t)(h->dt + 2) * sizeof(double));
    slong *fill = calloc((size_t)nv + 1, sizeof(slong));
    cb_status st = deg && start && inc && used && work && roots && fill ? CB_OK : CB_ERR_NOMEM;
    for (slong e = 0; e < ne && st == CB_OK; e++) {
        deg[T->edge[e].v0]++;
        deg[T->edge[e].v1]++;
    }
    for (slong v = 0; v < nv && st == CB_OK; v++)
        start[v + 1] = start[v] + deg[v];
    for (slong e = 0; e < ne && st == CB_OK; e++) {
        inc[start[T->edge[e].v0] + fill[T->edge[e].v0]++] = e;
        inc[start[T->edge[e].v1] + fill[T->edge[e].v1]++] = e;
    }
    free(fill);
    /* A chain passes through a vertex of degree 2 inside the box; it stops elsewhere, so that
     * pieces end on patch sides (where stitching joins them) and at nodes. */
#define PASS(v) (deg[v] == 2 && T->vertex[v].sides == 0)
    for (int pass = 0; pass < 2 && st == CB_OK; pass++) {
        /* Pass 0: open chains, started at stopping vertices in index order. Pass 1: the
         * remaining edges are closed loops, started at their lowest edge. */
        for (slong e0 = 0; e0 < ne && st == CB_OK; e0++) {
            if (used[e0])
                continue;
            const cb_ctopo_edge_struct *E0 = T->edge + e0;
            slong v;
            int rev;
            if (pass == 0) {
                if (!PASS(E0->v0)) {
                    v = E0->v0;
                    rev = 0;
                } else if (!PASS(E0->v1)) {
                    v = E0->v1;
                    rev = 1;
                } else {
                    continue;
                }
            } else {
                v = E0->v0;
                rev = 0;
            }
            _cb_ssi_trace_curve *c = trace_set_add(out);
            if (!c) {
                st = CB_ERR_NOMEM;
                break;
            }
            c->tangential = 1;
            c->v[0] = c->v[1] = -1;
            if (pass == 0)
                c->v[0] = v;
            const cb_ctopo_vertex_struct *vs = T->vertex + v;
            st = curve_push(c, vs->s, vs->t, vertex_fixed(vs));
            slong e = e0;
            while (st == CB_OK) {
                used[e] = 1;
                c->tangential &= T->edge[e].tangential != 0;
                st = trace_edge(c, T, e, rev, h, lift, lift_ctx, chord, max_seg, work, roots);
                v = rev ? T->edge[e].v0 : T->edge[e].v1;
                if (!PASS(v)) {
                    if (pass == 0)
                        c->v[1] = v;
                    break;
                }
                slong nxt = -1;
                for (slong k = start[v]; k < start[v + 1]; k++)
                    if (!used[inc[k]])
                        nxt = inc[k];
                if (nxt < 0) {
                    c->closed = pass == 1;
                    if (pass == 0)
                        c->v[1] = v;
                    break;
                }
                e = nxt;
                rev = T->edge[e].v1 == v;
            }
        }
    }
#undef PASS
    for (slong v = 0; v < nv && st == CB_OK; v++) {
        if (deg[v] != 0)
            continue;
        _cb_ssi_trace_curve *c = trace_set_add(out);
        if (!c) {
            st = CB_ERR_NOMEM;
            break;
        }
        c->isolated = 1;
        c->tangential = 1;
        c->v[0] = c->v[1] = v;
        st = curve_push(c, T->vertex[v].s, T->vertex[v].t, vertex_fixed(T->vertex + v));
    }
    free(deg);
    free(start);
    free(inc);
    free(used);
    free(work);
    free(roots);
    return st;
}
