/* imprint.c — the boundaries of coincident faces drawn onto each other (_cb_cuts_imprint): where
 * two faces lie on one surface, their intersection curves say nothing of where the overlap
 * ends, so each face is split along the other's edges, which then bound the pieces that lie on
 * the other solid. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "boolean/cut_internal.h"

/* Sampling of an edge: a piece of curve is halved while its chord strays from the curve's
 * midpoint by more than this many tolerances (the arrangement merges polylines within
 * CB_BOOL_SNAP tolerances of each other), at most to depth MAX_DEPTH below START pieces. */
#define SAGITTA_TOLS 1.0
enum { START = 16, MAX_DEPTH = 12 };

typedef struct {
    int n, cap;
    double *t;
} tlist;

static int tpush(tlist *l, double t)
{
    if (l->n == l->cap) {
        int cap = l->cap ? 2 * l->cap : 64;
        double *q = realloc(l->t, (size_t)cap * sizeof *q);
        if (!q)
            return -1;
        l->t = q;
        l->cap = cap;
    }
    l->t[l->n++] = t;
    return 0;
}

/* Parameters of curve c over [a, b] (a excluded, b included) fine enough for the sagitta. */
static int sample(tlist *l, const cb_topo_curve *c, double a, double b, double sag, int depth)
{
    double pa[3], pb[3], pm[3];
    cb_topo_curve_eval(pa, c, a);
    cb_topo_curve_eval(pb, c, b);
    cb_topo_curve_eval(pm, c, 0.5 * (a + b));
    double d2 = 0;
    for (int k = 0; k < 3; k++) {
        double m = 0.5 * (pa[k] + pb[k]) - pm[k];
        d2 += m * m;
    }
    if (depth < MAX_DEPTH && d2 > sag * sag)
        return sample(l, c, a, 0.5 * (a + b), sag, depth + 1) ||
               sample(l, c, 0.5 * (a + b), b, sag, depth + 1);
    return tpush(l, b);
}

typedef struct {
    const cut_ctx *cx;
    const cb_topo_curve *c;
    int own; /* the side whose edge this is */
    double tol;
} edge_ctx;

/* The point of the edge at t with its parameters on both faces (guess: a neighbour's, or
 * NULL), and whether it lies on the other face: on its surface within 10 tolerances and not
 * outside its loops. */
static int edge_point(cut_pt *p, const edge_ctx *e, double t, const cut_pt *guess)
{
    cb_topo_curve_eval(p->xyz, e->c, t);
    int inside = 1;
    for (int s = 0; s < 2; s++) {
        const cb_face *f = e->cx->f[s];
        double d = cb_topo_inverter_invert(p->uv[s], &f->inv, p->xyz, guess ? guess->uv[s] : NULL);
        if (s != e->own)
            inside = d <= 10 * e->tol &&
                     cb_face_classify_uv(f, p->uv[s][0], p->uv[s][1], 1e-3 * e->tol) != CB_FACE_OUT;
    }
    return inside;
}

/* Where the edge passes from inside the other face (at ta) to outside (at tb), or back: the
 * last inside point, by bisection on the edge's parameter to a thousandth of the tolerance. */
static void boundary_point(cut_pt *out, const edge_ctx *e, double ta, double tb,
                           const cut_pt *guess)
{
    cut_pt m;
    for (int it = 0; it < 100; it++) {
        double pa[3], pb[3];
        cb_topo_curve_eval(pa, e->c, ta);
        cb_topo_curve_eval(pb, e->c, tb);
        double d2 = 0;
        for (int k = 0; k < 3; k++)
            d2 += (pa[k] - pb[k]) * (pa[k] - pb[k]);
        if (d2 <= 1e-6 * e->tol * e->tol)
            break;
        double tm = 0.5 * (ta + tb);
        if (edge_point(&m, e, tm, guess))
            ta = tm;
        else
            tb = tm;
    }
    edge_point(out, e, ta, guess);
}

/* Edge `edge` of the face on side `own` of cx, drawn on the other face where it lies inside
 * it, appended to out. */
static cb_status imprint_edge(cb_bool_cuts *out, const cut_ctx *cx, int own, int edge,
                              const cb_ssi_curve *pair, double tol, cb_error *err)
{
    const cb_topo_body *b = cx->f[own]->b;
    const cb_topo_edge *E = b->edges + edge;
    edge_ctx e = {cx, b->curves + E->curve, own, tol};
    tlist ts = {0, 0, NULL};
    cb_status st = CB_OK;
    if (tpush(&ts, E->t0))
        st = cb_error_set(err, CB_ERR_NOMEM, "imprint: out of memory");
    for (int k = 0; k < START && !st; k++)
        if (sample(&ts, e.c, E->t0 + (E->t1 - E->t0) * k / START,
                   k + 1 == START ? E->t1 : E->t0 + (E->t1 - E->t0) * (k + 1) / START,
                   SAGITTA_TOLS * tol, 0))
            st = cb_error_set(err, CB_ERR_NOMEM, "imprint: out of memory");
    cut_run run = {0, 0, NULL};
    int closed_edge = E->v[0] == E->v[1];
    int all_in = 1, prev_in = 0;
    cut_pt prev, p;
    for (int i = 0; i < ts.n && !st; i++) {
        int in = edge_point(&p, &e, ts.t[i], i ? &prev : NULL);
        all_in &= in;
        if (in && i > 0 && !prev_in) {
            cut_pt x;
            boundary_point(&x, &e, ts.t[i], ts.t[i - 1], &p);
            if (_cb_cut_run_push(&run, &x))
                st = cb_error_set(err, CB_ERR_NOMEM, "imprint: out of memory");
        }
        if (in && !st && _cb_cut_run_push(&run, &p))
            st = cb_error_set(err, CB_ERR_NOMEM, "imprint: out of memory");
        if (!in && prev_in && !st) {
            cut_pt x;
            boundary_point(&x, &e, ts.t[i - 1], ts.t[i], &prev);
            if (_cb_cut_run_push(&run, &x))
                st = cb_error_set(err, CB_ERR_NOMEM, "imprint: out of memory");
            else if (run.n >= 2)
                st = _cb_cut_split_emit(out, &run, 0, cx, pair, -1, err);
            run.n = 0;
        }
        prev_in = in;
        prev = p;
    }
    if (!st && run.n >= 2)
        st = _cb_cut_split_emit(out, &run, closed_edge && all_in, cx, pair, -1, err);
    free(run.p);
    free(ts.t);
    return st;
}

cb_status _cb_cuts_imprint(cb_bool_cuts *out, const cb_ssi_result_struct *r,
                           const cb_bool_solid *A, const cb_bool_solid *B, double tol,
                           cb_error *err)
{
    cb_status st = CB_OK;
    for (slong k = 0; k < r->n_coincident && !st; k++) {
        const cb_ssi_coincident *c = r->coincident + k;
        if (!c->whole)
            return cb_error_set(err, CB_ERR_UNSUPPORTED,
                                "imprint: A face %d and B face %d lie on one surface only in "
                                "part (some patch pairs coincide, others cross)",
                                c->face_a, c->face_b);
        cut_ctx cx;
        _cb_cut_ctx_init(&cx, cb_bool_solid_face(A, c->face_a), cb_bool_solid_face(B, c->face_b),
                         tol);
        cb_ssi_curve pair = {0, NULL, 0, 1, c->face_a, c->face_b, 1};
        for (int own = 0; own < 2 && !st; own++) {
            const cb_face *F = cx.f[own];
            for (int j = 0; j < F->n_edges && !st; j++)
                if (F->edges[j].boundary)
                    st = imprint_edge(out, &cx, own, F->edges[j].edge, &pair, tol, err);
        }
    }
    return st;
}
