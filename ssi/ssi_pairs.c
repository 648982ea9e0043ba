/* ssi_pairs.c — the surface/surface driver: Bezier extraction, OBB culling, implicitisation,
 * the per-patch-pair pipeline in parallel, then stitching (see ssi/ssi.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "brep/bbox.h"
#include "brep/parallel.h"
#include "ssi/implicit.h"
#include "ssi/spline.h"
#include "ssi/ssi.h"
#include "ssi/ssi_tol.h"

void cb_ssi_surface_set_analytic(cb_ssi_surface *S, const cb_analytic_surface *a,
                                 const double range[4])
{
    memset(S, 0, sizeof(*S));
    S->kind = CB_SSI_ANALYTIC;
    S->analytic = *a;
    memcpy(S->range, range, 4 * sizeof(double));
}

void cb_ssi_surface_set_nurbs(cb_ssi_surface *S, const cb_nurbs_surface_t s)
{
    memset(S, 0, sizeof(*S));
    S->kind = CB_SSI_NURBS;
    S->nurbs = s;
}

void cb_ssi_opts_default(cb_ssi_opts *o)
{
    o->tol = 0;
    o->chord = 0;
    o->threads = 0;
    o->max_phi_degree = 12;
    cb_ctopo_opts_default(&o->topo);
    o->spline_max_depth = 30;
    o->spline_max_subpairs = 20000;
    o->spline_band_subpairs = 200000;
    o->recognise = 1;
    o->cancel = NULL;
    o->progress = NULL;
    o->keep_marks = 0;
    o->topo_transpose = 1;
}

static double now_s(void)
{
    struct timespec ts;
    timespec_get(&ts, TIME_UTC);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Periods of the analytic parameters: u is angular for all but the plane, v for the torus. */
static void analytic_periods(double per[2], const cb_analytic_surface *a)
{
    per[0] = a->kind == CB_ANALYTIC_PLANE ? 0 : 2 * CB_SSI_PI;
    per[1] = a->kind == CB_ANALYTIC_TORUS ? 2 * CB_SSI_PI : 0;
}

/* Control net of the analytic surface over its range (angular spans capped at one turn), for
 * boxes; 0 when the range is unbounded. */
static int analytic_net(cb_nurbs_surface_t out, const cb_analytic_surface *a, const double r[4])
{
    double per[2], b[4];
    analytic_periods(per, a);
    for (int i = 0; i < 2; i++) {
        b[2 * i] = r[2 * i];
        b[2 * i + 1] = r[2 * i + 1];
        if (!isfinite(b[2 * i]) || !isfinite(b[2 * i + 1]))
            return 0;
        if (per[i] > 0 && b[2 * i + 1] - b[2 * i] > per[i])
            b[2 * i + 1] = b[2 * i] + per[i];
    }
    if (a->kind == CB_ANALYTIC_SPHERE || a->kind == CB_ANALYTIC_ELLIPSOID) {
        b[2] = FLINT_MAX(b[2], -CB_SSI_PI / 2);
        b[3] = FLINT_MIN(b[3], CB_SSI_PI / 2);
    }
    return cb_analytic_to_nurbs(out, a, b[0], b[1], b[2], b[3], NULL) == CB_OK;
}

static void aabb_add_net(cb_aabb *box, const cb_nurbs_surface_struct *s)
{
    cb_aabb b;
    cb_nurbs_surface_aabb(&b, s);
    for (int k = 0; k < 3; k++) {
        box->lo[k] = fmin(box->lo[k], b.lo[k]);
        box->hi[k] = fmax(box->hi[k], b.hi[k]);
    }
}

static void cross3(double c[3], const double a[3], const double b[3])
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

/* 1 when the patch's weights are not all equal. */
static int patch_rational(const cb_nurbs_surface_struct *s)
{
    for (int k = 1; k < s->n_u * s->n_v; k++)
        if (s->cw[4 * k + 3] != s->cw[3])
            return 1;
    return 0;
}

/* ---------------------------------------------------------------- per P patch -------------- */

typedef struct {
    cb_dixon_patch_t dp;
    cb_dixon_pencil_t pencil;
    int has_pencil;
    cb_implicit_t F;
    cb_status st;
    char msg[160];
    int needed;
} p_side;

typedef struct {
    p_side *P;
    cb_nurbs_surface_struct *patches;
} p_ctx;

/* Relative flatness below which a patch counts as planar: its control points within this
 * times the diagonal of their box from the plane through three of its corners (a planar face
 * after a rotation is off by round-off, about 1e-16; its Dixon equation would be a
 * hyperbolic paraboloid of the patch's noise, and the inversion that clips to it
 * ill-conditioned). */
#define NEAR_PLANAR 1e-12

/* The three corners (homogeneous) of a net spanning the largest triangle, when every control
 * point is within NEAR_PLANAR of their plane; 0 otherwise. */
static int near_planar_corners(double h[3][4], const cb_nurbs_surface_struct *patch)
{
    int nu = patch->n_u, nv = patch->n_v, np = nu * nv;
    const int corner[4] = {0, nv - 1, (nu - 1) * nv, np - 1};
    double X[4][3], lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL};
    double hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    for (int k = 0; k < np; k++)
        for (int q = 0; q < 3; q++) {
            double x = patch->cw[4 * k + q] / patch->cw[4 * k + 3];
            lo[q] = fmin(lo[q], x);
            hi[q] = fmax(hi[q], x);
        }
    for (int c = 0; c < 4; c++)
        for (int q = 0; q < 3; q++)
            X[c][q] = patch->cw[4 * corner[c] + q] / patch->cw[4 * corner[c] + 3];
    double best = 0, n[3] = {0, 0, 0};
    int skip = -1;
    for (int s = 0; s < 4; s++) {
        int i[3], m = 0;
        for (int c = 0; c < 4; c++)
            if (c != s)
                i[m++] = c;
        double a[3], b[3], cr[3];
        for (int q = 0; q < 3; q++) {
            a[q] = X[i[1]][q] - X[i[0]][q];
            b[q] = X[i[2]][q] - X[i[0]][q];
        }
        cross3(cr, a, b);
        double l = sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]);
        if (l > best) {
            best = l;
            skip = s;
            for (int q = 0; q < 3; q++)
                n[q] = cr[q] / l;
        }
    }
    double diag = sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                       (hi[2] - lo[2]) * (hi[2] - lo[2]));
    if (skip < 0 || !(best > 0) || !(diag > 0))
        return 0;
    const double *o = X[skip == 0 ? 1 : 0];
    for (int k = 0; k < np; k++) {
        double d = 0;
        for (int q = 0; q < 3; q++)
            d += n[q] * (patch->cw[4 * k + q] / patch->cw[4 * k + 3] - o[q]);
        if (!(fabs(d) <= NEAR_PLANAR * diag))
            return 0;
    }
    int m = 0;
    for (int c = 0; c < 4; c++)
        if (c != skip) {
            memcpy(h[m], patch->cw + 4 * corner[c], 4 * sizeof(double));
            m++;
        }
    return 1;
}

/* The plane of a near planar patch (near_planar_corners); 0 when it is not planar. */
static int near_planar(cb_implicit_t F, const cb_nurbs_surface_struct *patch)
{
    double h[3][4];
    return near_planar_corners(h, patch) &&
           cb_implicit_plane_through(F, (const double(*)[4])h, NULL) == CB_OK;
}

/* Implicit equation of one P patch; a planar patch (no Dixon pencil) gets its exact plane, a
 * patch planar up to round-off the plane through three of its corners. */
static void p_side_run(p_side *ps, const cb_nurbs_surface_struct *patch)
{
    cb_error err;
    cb_error_clear(&err);
    ps->st = cb_dixon_patch_set_bezier(ps->dp, patch, &err);
    if (ps->st == CB_OK && near_planar(ps->F, patch))
        return;
    if (ps->st == CB_OK) {
        ps->st = cb_dixon_pencil_set(ps->pencil, ps->dp, &err);
        if (ps->st == CB_OK) {
            ps->has_pencil = 1;
            ps->st = cb_implicit_from_dixon(ps->F, ps->pencil, ps->dp, &err);
        } else if (ps->st == CB_ERR_UNSUPPORTED) {
            /* A planar patch: its exact plane (rounding it would tilt a curve lying on a side
             * of Q's patch box off that side, and the clipped pieces would fall apart). */
            cb_error_clear(&err);
            ps->st = cb_implicit_from_plane_patch(ps->F, ps->dp, &err);
        }
    }
    if (ps->st != CB_OK)
        snprintf(ps->msg, sizeof ps->msg, "implicitisation: %.120s", err.msg);
}

/* The implicit degree of the first Bezier patch of s, WORD_MAX when it cannot be found. For
 * the rational quadratic patches of the exact conic forms it is the surface's own (base
 * points lower it from the Dixon bound 8): 2 for a sphere or an ellipsoid, 4 for a torus. */
static slong first_patch_implicit_degree(const cb_nurbs_surface_struct *s)
{
    cb_nurbs_surface_struct *pat = NULL;
    int nu, nv;
    cb_error err;
    if (cb_nurbs_surface_extract_bezier(&pat, &nu, &nv, s, &err) != CB_OK)
        return WORD_MAX;
    p_side ps;
    memset(&ps, 0, sizeof ps);
    cb_dixon_patch_init(ps.dp);
    cb_dixon_pencil_init(ps.pencil);
    cb_implicit_init(ps.F);
    p_side_run(&ps, pat);
    slong deg = ps.st == CB_OK ? ps.F->deg : WORD_MAX;
    cb_dixon_patch_clear(ps.dp);
    cb_dixon_pencil_clear(ps.pencil);
    cb_implicit_clear(ps.F);
    cb_nurbs_surface_array_free(pat, nu * nv);
    return deg;
}

static void p_body(void *vctx, size_t begin, size_t end)
{
    p_ctx *c = vctx;
    for (size_t i = begin; i < end; i++)
        if (c->P[i].needed)
            p_side_run(c->P + i, c->patches + i);
}

/* ---------------------------------------------------------------- per patch pair ----------- */

typedef struct {
    int ip, iq;
    cb_status st;
    char msg[200];
    int empty;
    int spline; /* subdivision route; pieces already in the surfaces' domains */
    int fallback; /* the algebraic route failed and the subdivision route was taken */
    int probe;  /* rational P patch over the degree bound: implicitise first, then choose */
    int coincident, same_normal; /* the patches lie on one surface; normals agree at cxyz */
    double cxyz[3], cdist;       /* cdist: distance of cxyz from P's patch */
    int c_exact;                 /* coincident exactly (else within c_width <= tol) */
    double c_width;
    _cb_ssi_spline_stats sst;
    double ubox[8]; /* with sst.uncertified > 0: P's and Q's boxes {u0, u1, v0, v1} (domains)
                       of every sub-pair left uncertified, tangent regions not resolved too */
    _cb_ssi_tiny_set tiny; /* subdivision route: sub-pairs left for _cb_ssi_tiny_resolve */
    int tiny_within;       /* a tangent region resolved within tol touched the pair */
    int within;            /* counted in pairs_within_tolerance (else certified) */
    _cb_ssi_piece_set pieces;
    slong n_marks;
    cb_ssi_mark *marks; /* opts.keep_marks: the graph's vertices; faces and side set later */
    double t_topo, t_trace;
} pair_job;

typedef struct {
    pair_job *job;
    p_side *P;            /* spline P, per patch */
    const cb_implicit_struct *F_an; /* analytic P */
    const cb_ssi_surface *Ps;
    cb_dixon_patch_struct *Q;
    const cb_nurbs_surface_struct *ppat, *qpat; /* Bezier patches (ppat NULL: analytic P) */
    const cb_ssi_opts *opts;
    double tol, chord, max_seg, size;
} pair_ctx;

/* ---------------------------------------------------------------- coincident patches ------ */

/* First-order distance |F(X)| / |grad F(X)| of X from the surface F = 0 (0 where F vanishes,
 * infinite where only the gradient does). */
static double implicit_dist(const cb_implicit_struct *F, const double X[3])
{
    cb_poly3_struct p = {(int)F->deg, F->cd};
    double g[3], f = cb_poly3_eval_grad(g, &p, X);
    if (f == 0)
        return 0;
    double gn = sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
    return gn > 0 ? fabs(f) / gn : HUGE_VAL;
}

/* Point k of the 5 x 5 grid of a Bezier patch's domain, the centre first. */
static void grid_param(double uv[2], const cb_nurbs_surface_struct *pat, int k)
{
    double d[4];
    cb_nurbs_surface_domain(pat, d);
    int g = (k + 12) % 25;
    uv[0] = d[0] + (d[1] - d[0]) * (g / 5) / 4.0;
    uv[1] = d[2] + (d[3] - d[2]) * (g % 5) / 4.0;
}

double _cb_ssi_nurbs_project(double uv[2], const cb_nurbs_surface_struct *pat, const double X[3],
                             int warm)
{
    double d[4], P[3], best = HUGE_VAL;
    cb_nurbs_surface_domain(pat, d);
    if (!warm)
        for (int i = 0; i <= 8; i++)
            for (int j = 0; j <= 8; j++) {
                double u = d[0] + (d[1] - d[0]) * i / 8.0, v = d[2] + (d[3] - d[2]) * j / 8.0;
                cb_nurbs_surface_eval(P, pat, u, v);
                double e = (P[0] - X[0]) * (P[0] - X[0]) + (P[1] - X[1]) * (P[1] - X[1]) +
                           (P[2] - X[2]) * (P[2] - X[2]);
                if (e < best) {
                    best = e;
                    uv[0] = u;
                    uv[1] = v;
                }
            }
    double D[6][3];
    cb_nurbs_surface_eval_derivs(D, pat, uv[0], uv[1]);
    best = (D[0][0] - X[0]) * (D[0][0] - X[0]) + (D[0][1] - X[1]) * (D[0][1] - X[1]) +
           (D[0][2] - X[2]) * (D[0][2] - X[2]);
    for (int it = 0; it < 30 && best > 0; it++) {
        double a = 0, b = 0, c = 0, ru = 0, rv = 0;
        for (int k = 0; k < 3; k++) {
            double r = X[k] - D[0][k];
            a += D[1][k] * D[1][k];
            b += D[1][k] * D[2][k];
            c += D[2][k] * D[2][k];
            ru += D[1][k] * r;
            rv += D[2][k] * r;
        }
        double det = a * c - b * b;
        if (!(fabs(det) > 0) || !isfinite(det))
            break;
        double nu = fmin(d[1], fmax(d[0], uv[0] + (c * ru - b * rv) / det));
        double nv = fmin(d[3], fmax(d[2], uv[1] + (a * rv - b * ru) / det));
        double E[6][3];
        cb_nurbs_surface_eval_derivs(E, pat, nu, nv);
        double e = (E[0][0] - X[0]) * (E[0][0] - X[0]) + (E[0][1] - X[1]) * (E[0][1] - X[1]) +
                   (E[0][2] - X[2]) * (E[0][2] - X[2]);
        if (!(e < best))
            break;
        best = e;
        uv[0] = nu;
        uv[1] = nv;
        memcpy(D, E, sizeof D);
    }
    return sqrt(best);
}

/* Pre-filter of the algebraic route's coincidence proof (never decides): every point of a
 * CB_SSI_COINCIDENT_GRID square grid of Q within CB_SSI_COINCIDENT_FILTER tol of F = 0 (first
 * order). The centre is tried first, so a pair that is not coincident costs one point. */
static int job_near_coincident(const pair_ctx *c, const pair_job *J, const cb_implicit_struct *F)
{
    const cb_nurbs_surface_struct *q = c->qpat + J->iq;
    double d[4];
    cb_nurbs_surface_domain(q, d);
    const int n = CB_SSI_COINCIDENT_GRID, n2 = n * n;
    for (int k = 0; k < n2; k++) {
        int g = (k + n2 / 2) % n2;
        double X[3];
        cb_nurbs_surface_eval(X, q, d[0] + (d[1] - d[0]) * (g / n) / (n - 1),
                              d[2] + (d[3] - d[2]) * (g % n) / (n - 1));
        if (!(implicit_dist(F, X) <= CB_SSI_COINCIDENT_FILTER * c->tol))
            return 0;
    }
    return 1;
}

/* Orientation of a coincident pair: the normals S_u x S_v of Q and of P at the point of Q's
 * 5 x 5 grid nearest P's patch (a point of both patches when they overlap; analytic P: its own
 * parameters there; spline P: the nearest point of its patch). J->cdist: that distance. */
static void job_orientation(pair_job *J, const pair_ctx *c)
{
    const cb_nurbs_surface_struct *q = c->qpat + J->iq;
    double best = HUGE_VAL, pbest[2] = {0, 0}, qbest[2] = {0, 0}, pv[2] = {0, 0};
    for (int k = 0; k < 25 && best > 0; k++) {
        double uv[2], X[3], Y[3], dist;
        grid_param(uv, q, k);
        cb_nurbs_surface_eval(X, q, uv[0], uv[1]);
        if (c->ppat) {
            dist = _cb_ssi_nurbs_project(pv, c->ppat + J->ip, X, 0);
        } else {
            _cb_ssi_analytic_invert(pv, &c->Ps->analytic, X);
            cb_analytic_eval(Y, &c->Ps->analytic, pv[0], pv[1]);
            dist = sqrt((X[0] - Y[0]) * (X[0] - Y[0]) + (X[1] - Y[1]) * (X[1] - Y[1]) +
                        (X[2] - Y[2]) * (X[2] - Y[2]));
        }
        if (dist < best) {
            best = dist;
            memcpy(pbest, pv, sizeof pbest);
            memcpy(qbest, uv, sizeof qbest);
        }
    }
    double D[6][3], nq[3], np[3];
    cb_nurbs_surface_eval_derivs(D, q, qbest[0], qbest[1]);
    cross3(nq, D[1], D[2]);
    memcpy(J->cxyz, D[0], sizeof J->cxyz);
    if (c->ppat)
        cb_nurbs_surface_eval_derivs(D, c->ppat + J->ip, pbest[0], pbest[1]);
    else
        cb_analytic_eval_derivs(D, &c->Ps->analytic, pbest[0], pbest[1]);
    cross3(np, D[1], D[2]);
    J->same_normal = np[0] * nq[0] + np[1] * nq[1] + np[2] * nq[2] > 0;
    J->cdist = best;
}

/* J's Bezier patches P and Q run again with so: the new pieces, regions and figures are kept
 * when they leave nothing uncertified, otherwise the previous ones stand (their refusal with
 * them); either way both runs' sub-pairs count as examined. */
static void spline_rerun(pair_job *J, const pair_ctx *c, const _cb_ssi_bez *P,
                         const _cb_ssi_bez *Q, const _cb_ssi_spline_opts *so)
{
    _cb_ssi_piece_set prev = J->pieces;
    _cb_ssi_tiny_set prev_tiny = J->tiny;
    _cb_ssi_spline_stats prev_st = J->sst;
    _cb_ssi_piece_set_init(&J->pieces);
    _cb_ssi_tiny_set_init(&J->tiny);
    _cb_ssi_spline_pair(&J->pieces, &J->sst, P, Q, so, &J->tiny, (int)(J - c->job));
    long both = prev_st.subpairs + J->sst.subpairs;
    if (J->sst.uncertified > 0 && !J->sst.nomem) {
        _cb_ssi_piece_set_clear(&J->pieces);
        _cb_ssi_tiny_set_clear(&J->tiny);
        J->pieces = prev;
        J->tiny = prev_tiny;
        J->sst = prev_st;
    } else {
        _cb_ssi_piece_set_clear(&prev);
        _cb_ssi_tiny_set_clear(&prev_tiny);
    }
    J->sst.subpairs = both;
}

/* The subdivision route for one patch pair (ssi/spline.h), after the coincidence test. */
static void spline_run(pair_job *J, const pair_ctx *c)
{
    double t0 = now_s();
    cb_error err;
    cb_error_clear(&err);
    _cb_ssi_bez P, Q;
    J->st = _cb_ssi_bez_set(&P, c->ppat + J->ip, &err);
    if (J->st == CB_OK) {
        J->st = _cb_ssi_bez_set(&Q, c->qpat + J->iq, &err);
        if (J->st != CB_OK)
            _cb_ssi_bez_clear(&P);
    }
    if (J->st != CB_OK) {
        snprintf(J->msg, sizeof J->msg, "%.190s", err.msg);
        return;
    }
    int proved = 0;
    double width = 0;
    if (_cb_ssi_coincide_filter_bez(&P, &Q, c->tol))
        proved = _cb_ssi_coincide_reparam(&width, c->ppat + J->ip, c->qpat + J->iq, &P, &Q,
                                          c->tol);
    if (proved) {
        J->coincident = 1;
        J->c_exact = proved == 1;
        J->c_width = width;
        job_orientation(J, c);
        J->t_topo = now_s() - t0;
        _cb_ssi_bez_clear(&P);
        _cb_ssi_bez_clear(&Q);
        return;
    }
    _cb_ssi_spline_opts so = {c->opts->spline_max_depth, c->opts->spline_max_subpairs, c->tol,
                              c->chord, c->max_seg, 0, 0};
    _cb_ssi_spline_pair(&J->pieces, &J->sst, &P, &Q, &so, &J->tiny, (int)(J - c->job));
    const _cb_ssi_spline_stats *s = &J->sst;
    /* The budget ran out: again, with the band budget and sub-pairs proved within tol of each
     * other left whole at any size, so that a contact band along a tangential curve (millions
     * of sub-pairs of STOP_TOL tol) is covered by few; its cluster is then traced
     * (_cb_ssi_tiny_resolve). Not the first choice: near nodes and crossings at small angles
     * are resolved more finely by the first pass. */
    if (!s->nomem && c->opts->spline_band_subpairs > 0 &&
        s->uncertified - s->no_direction - s->ambiguous_roots - s->many_branches -
                s->march_failed > 0) {
        /* Kept only when it leaves nothing uncertified: otherwise the first run's finer
         * pieces and regions stand (its refusal with them). */
        so.band = 1;
        so.max_subpairs = so.max_edge_boxes = c->opts->spline_band_subpairs;
        spline_rerun(J, c, &P, &Q, &so);
    }
    if (s->nomem) {
        J->st = CB_ERR_NOMEM;
        snprintf(J->msg, sizeof J->msg, "subdivision: out of memory after %ld sub-patch pairs",
                 s->subpairs);
    } else if (s->uncertified > 0) {
        J->st = s->march_failed ? CB_ERR_NUMERIC : CB_ERR_UNSUPPORTED;
        snprintf(J->msg, sizeof J->msg,
                 "subdivision: %ld of %ld sub-patch pairs not certified (no direction %d, "
                 "ambiguous boundary roots %d, several branches %d, marching failed %d, "
                 "over budget %ld)",
                 s->uncertified, s->subpairs, s->no_direction, s->ambiguous_roots,
                 s->many_branches, s->march_failed,
                 s->uncertified - s->no_direction - s->ambiguous_roots - s->many_branches -
                     s->march_failed);
    }
    J->empty = s->branches == 0 && s->uncertified == 0;
    J->t_topo = now_s() - t0;
    _cb_ssi_bez_clear(&P);
    _cb_ssi_bez_clear(&Q);
}

/* The vertices of T (coordinates refined) as marks in Q's surface parameters; swap: T's s is
 * Q's second parameter (the transposed topology). */
static cb_status job_marks(pair_job *J, const cb_ctopo_t T, const _cb_ssi_pair_geom *g,
                           int patch, int swap)
{
    if (T->n_vertices == 0)
        return CB_OK;
    J->marks = malloc((size_t)T->n_vertices * sizeof(cb_ssi_mark));
    if (!J->marks)
        return CB_ERR_NOMEM;
    J->n_marks = T->n_vertices;
    for (slong k = 0; k < T->n_vertices; k++) {
        const cb_ctopo_vertex_struct *v = T->vertex + k;
        cb_ssi_mark *m = J->marks + k;
        double a = swap ? v->t : v->s, b = swap ? v->s : v->t;
        memset(m, 0, sizeof *m);
        m->patch = patch;
        m->kind = v->kind;
        m->singular = v->singular;
        m->tangential = v->tangential;
        cb_dixon_patch_to_domain(m->uv, m->uv + 1, g->q, a, b);
        _cb_ssi_lift(m->xyz, g, a, b);
    }
    return CB_OK;
}

/* ---------------------------------------------------------------- topology and tracing ----- */

/* The lift for a topology computed on phi with its variables swapped. */
static void swapped_lift(double X[3], const void *geom, double sigma, double tau)
{
    _cb_ssi_lift(X, geom, tau, sigma);
}

/* phi(t, s): the variables swapped. */
static void transpose(fmpz_mpoly_t out, const fmpz_mpoly_t p, const fmpz_mpoly_ctx_t ctx)
{
    fmpz_t co;
    fmpz_init(co);
    fmpz_mpoly_zero(out, ctx);
    for (slong k = 0; k < fmpz_mpoly_length(p, ctx); k++) {
        ulong e[2], f[2];
        fmpz_mpoly_get_term_exp_ui(e, p, k, ctx);
        fmpz_mpoly_get_term_coeff_fmpz(co, p, k, ctx);
        f[0] = e[1];
        f[1] = e[0];
        fmpz_mpoly_set_coeff_fmpz_ui(out, co, f, ctx);
    }
    fmpz_clear(co);
}

/* Topology, tracing and clipping of phi = 0 (mp) in Q's patch box [0, 1]^2, pieces (and marks)
 * into J; swap: mp is phi with its variables swapped, so the sweep runs along Q's second
 * parameter. Errors: those of cb_ctopo_compute (err set, "topology: ..."), CB_ERR_NOMEM. */
static cb_status topo_trace(pair_job *J, const pair_ctx *c, const _cb_ssi_pair_geom *g,
                            const fmpz_mpoly_t mp, const fmpz_mpoly_ctx_t ctx, int swap,
                            cb_error *err)
{
    double ta = now_s();
    fmpq_t zero, one;
    fmpq_init(zero);
    fmpq_init(one);
    fmpq_one(one);
    cb_ctopo_t T;
    cb_ctopo_init(T);
    cb_status st = cb_ctopo_compute(T, mp, ctx, zero, one, zero, one, &c->opts->topo, err);
    double tb = now_s();
    J->t_topo += tb - ta;
    if (st != CB_OK) {
        if (st != CB_ERR_NOMEM)
            cb_error_prefix(err, "topology: ");
    } else {
        _cb_ssi_sqf h;
        _cb_ssi_sqf_init(&h);
        _cb_ssi_trace_set ts;
        _cb_ssi_trace_set_init(&ts);
        st = _cb_ssi_sqf_set(&h, T->h);
        if (st == CB_OK) {
            _cb_ssi_vertex_refine(T, &h);
            if (c->opts->keep_marks)
                st = job_marks(J, T, g, J->iq, swap);
        }
        if (st == CB_OK)
            st = _cb_ssi_trace(&ts, T, &h, swap ? swapped_lift : _cb_ssi_lift, g, g->chord,
                               g->max_seg);
        for (slong k = 0; swap && k < ts.n && st == CB_OK; k++) {
            _cb_ssi_trace_curve *tc = ts.c + k;
            for (slong i = 0; i < tc->n; i++) {
                double a = tc->st[2 * i];
                unsigned f = tc->fixed[i];
                tc->st[2 * i] = tc->st[2 * i + 1];
                tc->st[2 * i + 1] = a;
                tc->fixed[i] = (f & ~12u) | ((f & 4u) << 1) | ((f & 8u) >> 1);
            }
        }
        slong first = J->pieces.n;
        if (st == CB_OK)
            st = _cb_ssi_clip(&J->pieces, &ts, g);
        if (st == CB_OK)
            st = _cb_ssi_ends_from_graph(&J->pieces, first, T, mp, ctx, swap);
        if (st != CB_OK)
            cb_error_set(err, st, "tracing: out of memory");
        _cb_ssi_trace_set_clear(&ts);
        _cb_ssi_sqf_clear(&h);
        J->t_trace += now_s() - tb;
    }
    cb_ctopo_clear(T);
    fmpq_clear(zero);
    fmpq_clear(one);
    return st;
}

static void pair_run(pair_job *J, const pair_ctx *c)
{
    double t0 = now_s();
    cb_error err;
    cb_error_clear(&err);
    const cb_implicit_struct *F = c->F_an;
    _cb_ssi_pair_geom g;
    memset(&g, 0, sizeof g);
    if (!F) {
        const p_side *ps = c->P + J->ip;
        if (ps->st != CB_OK) {
            J->st = ps->st;
            snprintf(J->msg, sizeof J->msg, "%s", ps->msg);
            return;
        }
        F = ps->F;
        g.p = ps->dp;
        g.p_pencil = ps->has_pencil ? ps->pencil : NULL;
        g.p_polynomial = !patch_rational(c->ppat + J->ip);
        cb_nurbs_surface_aabb(&g.p_net, c->ppat + J->ip);
    } else {
        g.p_analytic = 1;
        g.an = c->Ps->analytic;
        memcpy(g.an_range, c->Ps->range, sizeof g.an_range);
        analytic_periods(g.an_period, &g.an);
    }
    g.q = c->Q + J->iq;
    g.tol = c->tol;
    g.chord = c->chord;
    g.max_seg = c->max_seg;
    g.size = c->size;

    cb_phi_t phi;
    cb_phi_init(phi);
    J->st = cb_phi_compute(phi, F, g.q, &err);
    if (J->st != CB_OK) {
        snprintf(J->msg, sizeof J->msg, "phi: %.150s", err.msg);
        cb_phi_clear(phi);
        return;
    }
    /* The true bidegree: the formal one, N times Q's, can be above it (the paper's Example 2:
     * (27, 24) of (27, 27)). */
    slong ts = 0, tt = 0;
    for (slong i = 0; i <= phi->ds; i++)
        for (slong j = 0; j <= phi->dt; j++)
            if (!fmpz_is_zero(phi->c + i * (phi->dt + 1) + j)) {
                ts = FLINT_MAX(ts, i);
                tt = FLINT_MAX(tt, j);
            }
    if (ts > c->opts->max_phi_degree || tt > c->opts->max_phi_degree) {
        J->st = CB_ERR_UNSUPPORTED;
        snprintf(J->msg, sizeof J->msg,
                 "phi of bidegree (%ld, %ld) is above the topology stage's limit %ld",
                 (long)ts, (long)tt, (long)c->opts->max_phi_degree);
        cb_phi_clear(phi);
        return;
    }
    slong len = (phi->ds + 1) * (phi->dt + 1), npos = 0, nneg = 0, nz = 0;
    for (slong k = 0; k < len; k++) {
        npos += phi->bern[k] > 0;
        nneg += phi->bern[k] < 0;
        nz += !fmpz_is_zero(phi->c + k);
    }
    double width = 0;
    if (nz == 0 || (job_near_coincident(c, J, F) &&
                    _cb_ssi_coincide_implicit(&width, F, phi, g.q, c->qpat + J->iq, c->tol))) {
        /* Q lies on P's surface: exactly (phi = 0), or proved within tol (rounded input,
         * where phi may even be of one sign). */
        J->coincident = 1;
        J->c_exact = nz == 0;
        J->c_width = width;
        job_orientation(J, c);
        cb_phi_clear(phi);
        J->t_topo = now_s() - t0;
        return;
    }
    if (npos == len || nneg == len) {
        /* Bernstein coefficients (faithfully rounded) of one strict sign: phi has no zero. */
        J->empty = 1;
        cb_phi_clear(phi);
        J->t_topo = now_s() - t0;
        return;
    }
    fmpz_mpoly_ctx_t ctx;
    fmpz_mpoly_ctx_init(ctx, 2, ORD_LEX);
    fmpz_mpoly_t mp;
    fmpz_mpoly_init(mp, ctx);
    for (slong i = 0; i <= phi->ds; i++)
        for (slong j = 0; j <= phi->dt; j++) {
            const fmpz *co = phi->c + i * (phi->dt + 1) + j;
            if (fmpz_is_zero(co))
                continue;
            ulong e[2] = {(ulong)i, (ulong)j};
            fmpz_mpoly_set_coeff_fmpz_ui(mp, co, e, ctx);
        }
    cb_phi_clear(phi);
    J->t_topo = now_s() - t0;
    J->st = topo_trace(J, c, &g, mp, ctx, 0, &err);
    if (J->st == CB_ERR_UNSUPPORTED && c->opts->topo_transpose) {
        /* Refused as not in generic position (several multiple roots over one irrational
         * critical value): a mirror-symmetric design puts two folds on one line of one
         * parameter, rarely on one line of the other. The first refusal is the message. */
        cb_error e2;
        cb_error_clear(&e2);
        fmpz_mpoly_t tp;
        fmpz_mpoly_init(tp, ctx);
        transpose(tp, mp, ctx);
        cb_status s2 = topo_trace(J, c, &g, tp, ctx, 1, &e2);
        fmpz_mpoly_clear(tp, ctx);
        if (s2 == CB_OK || s2 == CB_ERR_NOMEM) {
            J->st = s2;
            err = e2;
        }
    }
    if (J->st != CB_OK) {
        /* The pair says why and outputs nothing rather than part of its curves. */
        _cb_ssi_piece_set_clear(&J->pieces);
        _cb_ssi_piece_set_init(&J->pieces);
        snprintf(J->msg, sizeof J->msg, "%.190s", err.msg);
    }
    fmpz_mpoly_clear(mp, ctx);
    fmpz_mpoly_ctx_clear(ctx);
}

static void pair_body(void *vctx, size_t begin, size_t end)
{
    pair_ctx *c = vctx;
    for (size_t k = begin; k < end; k++) {
        pair_job *J = c->job + k;
        if (J->spline) {
            spline_run(J, c);
        } else if (J->st == CB_OK) {
            pair_run(J, c);
            /* Two B-spline patches whose curve topology could not be certified (a critical
             * fibre not in generic position, or one that will not separate): the subdivision
             * route proves its own answer or says why not. */
            if (J->st != CB_OK && J->st != CB_ERR_NOMEM && c->ppat) {
                char first[sizeof J->msg];
                snprintf(first, sizeof first, "%s", J->msg);
                _cb_ssi_piece_set_clear(&J->pieces);
                _cb_ssi_piece_set_init(&J->pieces);
                J->st = CB_OK;
                J->empty = J->coincident = 0;
                J->spline = J->fallback = 1;
                spline_run(J, c);
                if (J->st != CB_OK) {
                    char second[sizeof J->msg];
                    snprintf(second, sizeof second, "%s", J->msg);
                    snprintf(J->msg, sizeof J->msg, "%.95s; then %.95s", first, second);
                }
            }
        }
    }
}

/* x in a patch's local [lo, hi] = [0, 1] mapped to the domain [d0, d1]: 0 and 1 exactly to
 * the ends, so that the shared sides of neighbouring patches compare equal; dn < 0 rounds
 * down, > 0 up (enclosures), 0 nearest. */
static double local_to_dom(double x, double d0, double d1, int dn)
{
    if (x == 0)
        return d0;
    if (x == 1)
        return d1;
    if (!isfinite(x))
        return x;
    double y = d0 + x * (d1 - d0);
    double e = (fabs(y) + fabs(d0) + fabs(d1 - d0)) * 0x1p-51;
    return dn < 0 ? y - e : (dn > 0 ? y + e : y);
}

/* Pieces from local patch parameters to the surfaces' domains (analytic angles into
 * [lo, lo + period)), their ends' lines with them (the exact roots stay local, with the
 * patch's range saying which local coordinates they are). */
static void to_domains(_cb_ssi_piece_set *ps, const cb_dixon_patch_struct *Pp,
                       const cb_ssi_surface *Ps, const cb_dixon_patch_struct *Qp)
{
    double per[2] = {0, 0};
    if (!Pp)
        analytic_periods(per, &Ps->analytic);
    for (slong k = 0; k < ps->n; k++)
        for (int e = 0; e < 2; e++)
            for (int l = 0; l < ps->p[k].end[e].nl; l++) {
                _cb_ssi_end_line *ln = ps->p[k].end[e].ln + l;
                const cb_dixon_patch_struct *D = ln->sigma ? Qp : Pp;
                if (!D) {
                    ln->range[0] = ln->range[1] = NAN;
                    continue;
                }
                const double *d = D->domain;
                int fr = 1 - ln->dir;
                ln->c = local_to_dom(ln->c, d[2 * ln->dir], d[2 * ln->dir + 1], 0);
                ln->lo = local_to_dom(ln->lo, d[2 * fr], d[2 * fr + 1], -1);
                ln->hi = local_to_dom(ln->hi, d[2 * fr], d[2 * fr + 1], 1);
                ln->range[0] = d[2 * fr];
                ln->range[1] = d[2 * fr + 1];
            }
    for (slong k = 0; k < ps->n; k++)
        for (slong i = 0; i < ps->p[k].n; i++) {
            _cb_ssi_pq *q = ps->p[k].pt + i;
            for (int d = 0; d < 2; d++)
                q->st[d] = local_to_dom(q->st[d], Qp->domain[2 * d], Qp->domain[2 * d + 1], 0);
            if (Pp) {
                for (int d = 0; d < 2; d++)
                    q->uv[d] =
                        local_to_dom(q->uv[d], Pp->domain[2 * d], Pp->domain[2 * d + 1], 0);
            } else {
                for (int d = 0; d < 2; d++) {
                    double lo = Ps->range[2 * d];
                    if (per[d] > 0 && isfinite(lo))
                        q->uv[d] = lo + fmod(fmod(q->uv[d] - lo, per[d]) + per[d], per[d]);
                }
            }
        }
}

/* A box in a Bezier patch's local [0,1]^2 mapped to the patch's domain. */
static void box_to_domain(double out[4], const double loc[4], const cb_nurbs_surface_struct *pat)
{
    double d[4];
    cb_nurbs_surface_domain(pat, d);
    for (int k = 0; k < 4; k++)
        out[k] = d[k & 2] + loc[k] * (d[(k & 2) + 1] - d[k & 2]);
}

/* The region of a patch pair coincident within tolerance: both patches' parameter boxes (an
 * analytic P's range), Q's control box, the proved width. CB_ERR_NOMEM. */
static cb_status coincidence_region(cb_ssi_result_t r, const pair_job *J, int fa, int fb, int pa,
                                    int pb, int swapped, const cb_nurbs_surface_struct *ppat,
                                    const cb_ssi_surface *Ps,
                                    const cb_nurbs_surface_struct *qpat)
{
    cb_ssi_region *g = _cb_ssi_add_region(r, CB_SSI_REGION_COINCIDENCE, fa, fb, pa, pb,
                                          J->c_width);
    if (!g)
        return CB_ERR_NOMEM;
    double bp[4], bq[4];
    if (ppat)
        cb_nurbs_surface_domain(ppat + J->ip, bp);
    else
        memcpy(bp, Ps->range, sizeof bp);
    cb_nurbs_surface_domain(qpat + J->iq, bq);
    memcpy(swapped ? g->box_b : g->box_a, bp, sizeof bp);
    memcpy(swapped ? g->box_a : g->box_b, bq, sizeof bq);
    cb_aabb b;
    cb_nurbs_surface_aabb(&b, qpat + J->iq);
    memcpy(g->lo, b.lo, sizeof g->lo);
    memcpy(g->hi, b.hi, sizeof g->hi);
    return CB_OK;
}

/* The per-patch boxes of cb_ssi_surfaces, used only while the patch pairs are chosen. */
static void free_boxes(cb_obb *qobb, cb_obb *pobb, cb_aabb *qbox, cb_aabb *pbox, char *qhave,
                       char *phave)
{
    free(qobb);
    free(pobb);
    free(qbox);
    free(pbox);
    free(qhave);
    free(phave);
}

cb_status cb_ssi_surfaces(cb_ssi_result_t r, const cb_ssi_surface *A, const cb_ssi_surface *B,
                          int face_a, int face_b, const cb_ssi_opts *opts, cb_error *err)
{
    if (A->kind == CB_SSI_ANALYTIC && B->kind == CB_SSI_ANALYTIC)
        return _cb_ssi_analytic_pair(r, A, B, face_a, face_b, opts, err);
    if (opts->recognise) {
        /* Fast path: B-spline planes and cylinders written as their exact rational forms
         * (ssi_recog.c) take the analytic closed forms, which decide tangency and nodes within
         * tol where the rounded conic weights leave the B-spline route undecided. */
        int done = 0;
        cb_status st0 = _cb_ssi_recognised_pair(r, A, B, face_a, face_b, opts, &done, err);
        if (st0 != CB_OK || done)
            return st0;
    }
    /* P is implicitised: the analytic side, or the spline of lower patch bidegree; between
     * rational patches of degree <= 2 (exact conic forms), the one of lower implicit degree,
     * which gives phi the lower degree and its fibres in the other's parameters (an ellipsoid
     * against a torus: degree 4, the torus' fibres, as the analytic route has it; the other
     * way round phi has degree 8 and fibres through several critical points it refuses). */
    int swapped;
    if (A->kind == CB_SSI_ANALYTIC)
        swapped = 0;
    else if (B->kind == CB_SSI_ANALYTIC)
        swapped = 1;
    else {
        double h[3][4];
        int da = A->nurbs->deg_u * A->nurbs->deg_v, db = B->nurbs->deg_u * B->nurbs->deg_v;
        int pa = near_planar_corners(h, A->nurbs), pb = near_planar_corners(h, B->nurbs);
        swapped = db < da;
        if (da == db && da <= 4 && patch_rational(A->nurbs) && patch_rational(B->nurbs))
            swapped = first_patch_implicit_degree(B->nurbs) <
                      first_patch_implicit_degree(A->nurbs);
        /* A planar B-spline (CAD systems write planes so) is P: its implicit equation is its
         * plane, phi has the other patch's degree, and the algebraic route decides the
         * tangencies (a fillet running into the plane) that subdivision cannot. */
        if (pa != pb)
            swapped = pb;
    }
    const cb_ssi_surface *Ps = swapped ? B : A, *Qs = swapped ? A : B;
    int fa = face_a, fb = face_b;
    if (Ps->kind == CB_SSI_ANALYTIC) {
        /* phi of degree N (m_Q, n_Q) with N the implicit degree, the same bound on every
         * patch of Q: above the limit the subdivision route takes the pair, which needs both
         * sides as patches. */
        slong N = _cb_ssi_implicit_degree(&Ps->analytic);
        if (N * FLINT_MAX(Qs->nurbs->deg_u, Qs->nurbs->deg_v) > opts->max_phi_degree)
            return _cb_ssi_analytic_as_nurbs(r, A, B, face_a, face_b, opts, err);
    }

    cb_status st;
    cb_nurbs_surface_struct *qpat = NULL, *ppat = NULL;
    int nqu, nqv, npu = 1, npv = 1;
    st = cb_nurbs_surface_extract_bezier(&qpat, &nqu, &nqv, Qs->nurbs, err);
    if (st != CB_OK)
        return st;
    if (Ps->kind == CB_SSI_NURBS) {
        st = cb_nurbs_surface_extract_bezier(&ppat, &npu, &npv, Ps->nurbs, err);
        if (st != CB_OK) {
            cb_nurbs_surface_array_free(qpat, nqu * nqv);
            return st;
        }
    }
    int nq = nqu * nqv, np = npu * npv;

    /* Boxes and the model size. */
    cb_aabb box = {{HUGE_VAL, HUGE_VAL, HUGE_VAL}, {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL}};
    /* Oriented boxes are made only for patches whose axis-aligned box meets one of the other
     * side (their fit dominates the cost of a face pair that is mostly culled). */
    cb_obb *qobb = malloc((size_t)nq * sizeof(cb_obb));
    cb_obb *pobb = malloc((size_t)np * sizeof(cb_obb));
    cb_aabb *qbox = malloc((size_t)nq * sizeof(cb_aabb));
    cb_aabb *pbox = malloc((size_t)np * sizeof(cb_aabb));
    char *qhave = calloc((size_t)nq, 1), *phave = calloc((size_t)np, 1);
    pair_job *job = calloc((size_t)np * nq + 1, sizeof(pair_job));
    if (!qobb || !pobb || !qbox || !pbox || !qhave || !phave || !job) {
        free_boxes(qobb, pobb, qbox, pbox, qhave, phave);
        free(job);
        cb_nurbs_surface_array_free(qpat, nq);
        if (ppat)
            cb_nurbs_surface_array_free(ppat, np);
        return cb_error_set(err, CB_ERR_NOMEM, "ssi: out of memory for %d x %d patch pairs",
                            np, nq);
    }
    int p_bounded = 1;
    for (int j = 0; j < nq; j++) {
        cb_nurbs_surface_aabb(qbox + j, qpat + j);
        aabb_add_net(&box, qpat + j);
    }
    if (ppat) {
        for (int i = 0; i < np; i++) {
            cb_nurbs_surface_aabb(pbox + i, ppat + i);
            aabb_add_net(&box, ppat + i);
        }
    } else {
        cb_nurbs_surface_t net;
        cb_nurbs_surface_init(net);
        p_bounded = analytic_net(net, &Ps->analytic, Ps->range);
        if (p_bounded) {
            cb_nurbs_surface_obb(pobb, net);
            cb_nurbs_surface_aabb(pbox, net);
            phave[0] = 1;
            aabb_add_net(&box, net);
        }
        cb_nurbs_surface_clear(net);
    }
    double size = sqrt((box.hi[0] - box.lo[0]) * (box.hi[0] - box.lo[0]) +
                       (box.hi[1] - box.lo[1]) * (box.hi[1] - box.lo[1]) +
                       (box.hi[2] - box.lo[2]) * (box.hi[2] - box.lo[2]));
    double tol = opts->tol > 0 ? opts->tol : 1e-6 * size;
    double chord = opts->chord > 0 ? opts->chord : 1e-3 * size;
    /* Longest chord of a traced polyline (the subdivision route's marching, contact bands). */
    double max_seg = 0.05 * size;
    r->tol = tol;

    /* Patch pairs surviving the OBB test (section 4.1). */
    slong nj = 0;
    for (int i = 0; i < np; i++)
        for (int j = 0; j < nq; j++) {
            r->pairs_total++;
            if (p_bounded && !cb_aabb_overlap(pbox + i, qbox + j, tol)) {
                r->pairs_culled++;
                continue;
            }
            if (p_bounded && !phave[i]) {
                cb_nurbs_surface_obb(pobb + i, ppat + i);
                phave[i] = 1;
            }
            if (p_bounded && !qhave[j]) {
                cb_nurbs_surface_obb(qobb + j, qpat + j);
                qhave[j] = 1;
            }
            if (p_bounded && cb_obb_separated(pobb + i, qobb + j, tol)) {
                r->pairs_culled++;
                continue;
            }
            job[nj].ip = i;
            job[nj].iq = j;
            /* Degree of phi before any algebra: N (m_Q, n_Q), N <= 2 m_P n_P for a patch
             * (the Dixon rank), the true degree for an analytic surface. */
            slong N = ppat ? 2 * ppat[i].deg_u * ppat[i].deg_v
                           : _cb_ssi_implicit_degree(&Ps->analytic);
            slong dq = FLINT_MAX(qpat[j].deg_u, qpat[j].deg_v);
            double h[3][4];
            int planar = ppat && near_planar_corners(h, ppat + i);
            if (planar)
                N = 1; /* p_side_run gives the patch its plane */
            int rational = !planar && ppat && patch_rational(ppat + i);
            if ((rational && ppat[i].deg_u * ppat[i].deg_v <= 4) ||
                (!planar && ppat && N * dq > opts->max_phi_degree &&
                 N <= opts->max_phi_degree)) {
                /* A rational P patch of degree <= 2, or a patch whose phi could exceed the
                 * limit while its Dixon bound 2 m n does not (the limit raised for it, as for
                 * the paper's Example 2): implicitise, then choose. Base points lower the
                 * implicit degree below 2 m n: exact conic weights, as Colibri's models write
                 * them, give 2 for a cylinder or sphere piece; the bicubic P of the paper's
                 * Example 1 gives 9, and phi (27, 24) against its Q. */
                job[nj].probe = 1;
            } else if (rational) {
                job[nj].spline = 1;
                r->pairs_subdivided++;
            } else if (N * dq > opts->max_phi_degree) {
                /* Only patch pairs get here (an analytic P of such a degree was converted
                 * above). */
                job[nj].spline = 1;
                r->pairs_subdivided++;
            }
            _cb_ssi_piece_set_init(&job[nj].pieces);
            _cb_ssi_tiny_set_init(&job[nj].tiny);
            nj++;
        }
    free_boxes(qobb, pobb, qbox, pbox, qhave, phave);

    cb_implicit_t F_an;
    cb_implicit_init(F_an);
    cb_dixon_patch_struct *Q = calloc((size_t)nq, sizeof(cb_dixon_patch_struct));
    p_side *P = ppat ? calloc((size_t)np, sizeof(p_side)) : NULL;
    if (!Q || (ppat && !P))
        st = cb_error_set(err, CB_ERR_NOMEM, "ssi: out of memory for %d x %d patches", np, nq);
    for (int j = 0; j < nq && Q; j++)
        cb_dixon_patch_init(Q + j);
    for (int i = 0; i < np && P; i++) {
        cb_dixon_patch_init(P[i].dp);
        cb_dixon_pencil_init(P[i].pencil);
        cb_implicit_init(P[i].F);
    }
    for (int j = 0; j < nq && st == CB_OK; j++)
        st = cb_dixon_patch_set_bezier(Q + j, qpat + j, err);
    if (st == CB_OK && ppat) {
        for (slong k = 0; k < nj; k++)
            if (job[k].st == CB_OK && !job[k].spline)
                P[job[k].ip].needed = 1;
        p_ctx pc = {P, ppat};
        st = cb_parallel_for((size_t)np, 1, opts->threads, p_body, &pc);
        if (st != CB_OK)
            cb_error_set(err, st, "ssi: parallel implicitisation failed: %s", cb_status_name(st));
        /* Probed pairs: the algebraic route when the true implicit degree allows it. */
        for (slong k = 0; k < nj; k++) {
            pair_job *J = job + k;
            if (!J->probe)
                continue;
            /* The algebraic route when the implicit degree dropped below the Dixon rank
             * bound 2 m n (base points); otherwise (weights rounded, as sqrt(2)/2 is: no base
             * points, degree 2 m n, huge coefficients) the subdivision route. pair_run checks
             * phi's true bidegree against the limit (F's degree times Q's only bounds it)
             * and falls back to subdivision above it. */
            slong bound = 2 * ppat[J->ip].deg_u * ppat[J->ip].deg_v;
            if (P[J->ip].st != CB_OK || P[J->ip].F->deg >= bound) {
                J->spline = 1;
                r->pairs_subdivided++;
            }
        }
    } else if (st == CB_OK) {
        st = cb_implicit_from_analytic(F_an, &Ps->analytic, err);
    }
    if (st == CB_OK) {
        pair_ctx pc = {job, P, ppat ? NULL : F_an, Ps, Q, ppat, qpat, opts, tol, chord,
                       max_seg, size};
        st = cb_parallel_for((size_t)nj, 1, opts->threads, pair_body, &pc);
        if (st != CB_OK)
            cb_error_set(err, st, "ssi: parallel patch pairs failed: %s", cb_status_name(st));
    }
    if (st == CB_OK) {
        _cb_ssi_stitch_set *sets = malloc((size_t)(nj + 1) * sizeof(_cb_ssi_stitch_set));
        _cb_ssi_piece_set *psets = malloc((size_t)(nj + 1) * sizeof(_cb_ssi_piece_set));
        _cb_ssi_tiny_set *tiny = malloc((size_t)(nj + 1) * sizeof(_cb_ssi_tiny_set));
        char *bad = calloc((size_t)nj + 1, 1);
        long *unres = calloc((size_t)nj + 1, sizeof(long));
        double *bad_box = malloc((size_t)(8 * (nj + 1)) * sizeof(double));
        if (!sets || !psets || !tiny || !bad || !unres || !bad_box)
            st = cb_error_set(err, CB_ERR_NOMEM, "ssi: out of memory for the curves of %ld "
                              "patch pairs", (long)nj);
        /* Tangent regions the subdivision route left at its floor, resolved over all patch
         * pairs of the two surfaces at once (a region met by several pairs becomes one point),
         * on the pieces in the surfaces' domains. */
        for (slong k = 0; k < nj && st == CB_OK; k++) {
            pair_job *J = job + k;
            if (!J->spline && J->st == CB_OK)
                to_domains(&J->pieces, P ? P[J->ip].dp : NULL, Ps, Q + J->iq);
            psets[k] = J->pieces;
            tiny[k] = J->tiny;
        }
        long regions = 0, nodes = 0;
        double wt_width = 0;
        _cb_ssi_tiny_region *treg = NULL;
        slong ntreg = 0;
        char *twithin = calloc((size_t)nj + 1, 1);
        if (st == CB_OK && !twithin)
            st = cb_error_set(err, CB_ERR_NOMEM, "ssi: out of memory resolving tangent regions");
        if (st == CB_OK &&
            _cb_ssi_tiny_resolve(psets, nj, tiny, bad, unres, bad_box, tol, &regions, &nodes,
                                 &wt_width, &treg, &ntreg, twithin, Ps, Qs, chord, max_seg) < 0)
            st = cb_error_set(err, CB_ERR_NOMEM, "ssi: out of memory resolving tangent regions");
        /* Each resolved region listed: a near node (at most tol across), or a contact band
         * (up to WT_MAX_TOL tol, every member proved within tol of the other surface). */
        for (slong g = 0; g < ntreg && st == CB_OK; g++) {
            const _cb_ssi_tiny_region *tr = treg + g;
            const pair_job *J = job + tr->job;
            int pa = ppat ? J->ip : -1, pb = J->iq;
            cb_ssi_region *rg = _cb_ssi_add_region(
                r, tr->width <= tol ? CB_SSI_REGION_NEAR_NODE : CB_SSI_REGION_CONTACT_BAND, fa,
                fb, swapped ? pb : pa, swapped ? pa : pb, tr->width);
            if (!rg) {
                st = cb_error_set(err, CB_ERR_NOMEM, "ssi: out of memory recording a tangent "
                                  "region");
                break;
            }
            memcpy(rg->lo, tr->lo, sizeof rg->lo);
            memcpy(rg->hi, tr->hi, sizeof rg->hi);
            double *bp = swapped ? rg->box_b : rg->box_a, *bq = swapped ? rg->box_a : rg->box_b;
            for (int d = 0; d < 2; d++) {
                bp[2 * d] = bp[2 * d + 1] = tr->uv[d];
                bq[2 * d] = bq[2 * d + 1] = tr->st[d];
            }
        }
        for (slong k = 0; k < nj && twithin; k++)
            job[k].tiny_within = twithin[k];
        /* Each pair with curves along sides lying on each other, listed (its outcome within
         * tolerance below). */
        for (slong k = 0; k < nj && st == CB_OK; k++) {
            const pair_job *J = job + k;
            if (!J->spline || J->st != CB_OK || J->sst.side_subpairs == 0)
                continue;
            int pa = ppat ? J->ip : -1, pb = J->iq;
            cb_ssi_region *rg = _cb_ssi_add_region(r, CB_SSI_REGION_SIDE, fa, fb,
                                                   swapped ? pb : pa, swapped ? pa : pb,
                                                   J->sst.side_width);
            if (!rg) {
                st = cb_error_set(err, CB_ERR_NOMEM, "ssi: out of memory recording a side");
                break;
            }
            memcpy(rg->lo, J->sst.side_lo, sizeof rg->lo);
            memcpy(rg->hi, J->sst.side_hi, sizeof rg->hi);
            box_to_domain(swapped ? rg->box_b : rg->box_a, J->sst.side_box_p, ppat + J->ip);
            box_to_domain(swapped ? rg->box_a : rg->box_b, J->sst.side_box_q, qpat + J->iq);
        }
        free(treg);
        free(twithin);
        for (slong k = 0; k < nj && st == CB_OK; k++) {
            pair_job *J = job + k;
            J->pieces = psets[k];
            /* The pair's uncertified region: its sub-pairs left so, and the clusters not
             * resolved. */
            double *ub = J->ubox;
            if (J->spline && J->sst.uncertified > 0) {
                box_to_domain(ub, J->sst.box_p, ppat + J->ip);
                box_to_domain(ub + 4, J->sst.box_q, qpat + J->iq);
                for (int q = 0; q < 8 && bad[k]; q++) {
                    double b = bad_box[8 * k + q];
                    ub[q] = q % 2 ? fmax(ub[q], b) : fmin(ub[q], b);
                }
            } else if (bad[k]) {
                memcpy(ub, bad_box + 8 * k, sizeof J->ubox);
            }
            if (!bad[k])
                continue;
            /* A region larger than the tolerance: the pair is not certified. */
            if (J->st == CB_OK) {
                J->st = CB_ERR_UNSUPPORTED;
                snprintf(J->msg, sizeof J->msg,
                         "subdivision: %ld sub-patch pairs in a tangent region that is neither "
                         "within tol nor proved within tol of the other surface (%ld examined)",
                         unres[k], J->sst.subpairs);
            }
            J->sst.uncertified += unres[k];
        }
        free(psets);
        r->regions_within_tol += regions;
        r->nodes_within_tol += nodes;
        r->width_within_tol = fmax(r->width_within_tol, wt_width);
        free(tiny);
        free(bad);
        free(unres);
        free(bad_box);
        slong n_coinc = 0, first_coinc = -1;
        int c_exact = 1;
        double c_width = 0;
        for (slong k = 0; k < nj && st == CB_OK; k++) {
            pair_job *J = job + k;
            r->time_topo += J->t_topo;
            r->time_trace += J->t_trace;
            r->subpairs += J->sst.subpairs;
            int pa = ppat ? J->ip : -1, pb = J->iq;
            if (swapped) {
                int t = pa;
                pa = pb;
                pb = t;
            }
            if (J->st == CB_OK && J->coincident) {
                r->pairs_coincident++;
                n_coinc++;
                /* The pair whose comparison point lies on both patches (or nearest). */
                if (first_coinc < 0 || J->cdist < job[first_coinc].cdist)
                    first_coinc = k;
                if (J->c_exact) {
                    r->pairs_certified++;
                } else {
                    r->pairs_within_tolerance++;
                    c_exact = 0;
                    c_width = fmax(c_width, J->c_width);
                    if (coincidence_region(r, J, fa, fb, pa, pb, swapped, ppat, Ps, qpat) !=
                        CB_OK) {
                        st = cb_error_set(err, CB_ERR_NOMEM, "ssi: out of memory recording a "
                                          "coincidence within tolerance");
                        break;
                    }
                }
            } else if (J->st != CB_OK) {
                if (_cb_ssi_add_failure(r, fa, fb, pa, pb, J->st, J->msg) != CB_OK) {
                    st = cb_error_set(err, CB_ERR_NOMEM, "ssi: out of memory recording an "
                                      "uncertified patch pair (%s)", cb_status_name(J->st));
                    break;
                }
                if (J->spline && J->sst.uncertified > 0) {
                    cb_ssi_failure *f = r->failed + r->n_failed - 1;
                    f->has_box = 1;
                    memcpy(swapped ? f->box_b : f->box_a, J->ubox, 4 * sizeof(double));
                    memcpy(swapped ? f->box_a : f->box_b, J->ubox + 4, 4 * sizeof(double));
                }
            } else if (J->tiny_within || (J->spline && J->sst.side_subpairs > 0)) {
                r->pairs_within_tolerance++;
                J->within = 1;
            } else {
                r->pairs_certified++;
                r->pairs_empty += J->empty;
            }
            r->pairs_subdivided += J->fallback;
            _cb_ssi_stitch_set *S = sets + k;
            S->ps = &J->pieces;
            S->patch_a = pa;
            S->patch_b = pb;
            S->outcome = CB_SSI_CERTIFIED;
            for (int q = 0; q < 4; q++)
                S->pdom[q] = NAN;
            if (ppat)
                cb_nurbs_surface_domain(ppat + J->ip, S->pdom);
            cb_nurbs_surface_domain(qpat + J->iq, S->qdom);
            if (J->st == CB_OK && !J->spline && J->n_marks > 0) {
                for (slong i = 0; i < J->n_marks; i++) {
                    J->marks[i].face_a = fa;
                    J->marks[i].face_b = fb;
                    J->marks[i].q_side = !swapped;
                }
                if (_cb_ssi_add_marks(r, J->marks, J->n_marks) != CB_OK) {
                    st = cb_error_set(err, CB_ERR_NOMEM, "ssi: out of memory recording the "
                                      "topology marks");
                    break;
                }
            }
        }
        if (st == CB_OK && n_coinc > 0) {
            const pair_job *J = job + first_coinc;
            int pa = ppat ? J->ip : -1, pb = J->iq;
            cb_ssi_coincident *cr =
                _cb_ssi_add_coincident(r, fa, fb, swapped ? pb : pa, swapped ? pa : pb,
                                       J->same_normal, J->cxyz, c_exact, c_width);
            if (cr) {
                cr->patch_pairs = n_coinc;
                cr->whole = n_coinc == nj;
            } else {
                st = cb_error_set(err, CB_ERR_NOMEM,
                                  "ssi: out of memory recording coincident surfaces");
            }
        }
        slong c0 = r->n_curves, q0 = r->n_points;
        _cb_ssi_stitch_opts so = {swapped, fa, fb, tol, chord, 0, {{{0}}}};
        for (int sg = 0; sg < 2; sg++) {
            const cb_ssi_surface *S = sg ? Qs : Ps;
            if (S->kind == CB_SSI_NURBS)
                _cb_ssi_seams(so.seam[sg], S->nurbs);
            else
                for (int d = 0; d < 2; d++)
                    so.seam[sg][d][0] = so.seam[sg][d][1] = NAN;
        }
        if (st == CB_OK && _cb_ssi_stitch(r, sets, nj, &so))
            st = cb_error_set(err, CB_ERR_NOMEM, "ssi: out of memory joining curves");
        /* Pairs whose curves' ends were joined within tolerance, or whose joins were refused
         * (a failure record of its own says so), are certified no longer. */
        for (slong k = 0; k < nj && st == CB_OK; k++)
            if (sets[k].outcome != CB_SSI_CERTIFIED && job[k].st == CB_OK &&
                !job[k].coincident && !job[k].within) {
                r->pairs_certified--;
                if (sets[k].outcome == CB_SSI_WITHIN_TOL)
                    r->pairs_within_tolerance++;
            }
        free(sets);
        if (st == CB_OK && _cb_ssi_result_densify(r, c0, A, B, chord, tol))
            st = cb_error_set(err, CB_ERR_NOMEM, "ssi: out of memory refining curves");
        for (slong c = c0; c < r->n_curves; c++)
            for (slong i = 0; i < r->curve[c].n; i++)
                _cb_ssi_result_measure(r, A, B, r->curve[c].pt + i);
        for (slong q = q0; q < r->n_points; q++)
            _cb_ssi_result_measure(r, A, B, &r->point[q].p);
    }
    for (slong k = 0; k < nj; k++) {
        _cb_ssi_piece_set_clear(&job[k].pieces);
        _cb_ssi_tiny_set_clear(&job[k].tiny);
        free(job[k].marks);
    }
    free(job);
    if (P) {
        for (int i = 0; i < np; i++) {
            cb_dixon_patch_clear(P[i].dp);
            cb_dixon_pencil_clear(P[i].pencil);
            cb_implicit_clear(P[i].F);
        }
        free(P);
    }
    for (int j = 0; j < nq && Q; j++)
        cb_dixon_patch_clear(Q + j);
    free(Q);
    cb_implicit_clear(F_an);
    cb_nurbs_surface_array_free(qpat, nq);
    if (ppat)
        cb_nurbs_surface_array_free(ppat, np);
    return st;
}
