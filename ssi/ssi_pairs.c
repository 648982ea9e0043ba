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
    o->spline_max_depth = 20;
    o->spline_max_subpairs = 20000;
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

/* Implicit equation of one P patch; a planar patch (no Dixon pencil) gets its plane. */
static void p_side_run(p_side *ps, const cb_nurbs_surface_struct *patch)
{
    cb_error err;
    cb_error_clear(&err);
    ps->st = cb_dixon_patch_set_bezier(ps->dp, patch, &err);
    if (ps->st == CB_OK) {
        ps->st = cb_dixon_pencil_set(ps->pencil, ps->dp, &err);
        if (ps->st == CB_OK) {
            ps->has_pencil = 1;
            ps->st = cb_implicit_from_dixon(ps->F, ps->pencil, ps->dp, &err);
        } else if (ps->st == CB_ERR_UNSUPPORTED) {
            int m = patch->deg_u, n = patch->deg_v;
            double c[4][3];
            const int idx[4][2] = {{0, 0}, {m, 0}, {0, n}, {m, n}};
            for (int k = 0; k < 4; k++) {
                const double *w = cb_nurbs_surface_cw(patch, idx[k][0], idx[k][1]);
                for (int q = 0; q < 3; q++)
                    c[k][q] = w[q] / w[3];
            }
            double d1[3], d2[3], nrm[3], o[3];
            for (int q = 0; q < 3; q++) {
                d1[q] = c[3][q] - c[0][q];
                d2[q] = c[2][q] - c[1][q];
                o[q] = 0.25 * (c[0][q] + c[1][q] + c[2][q] + c[3][q]);
            }
            nrm[0] = d1[1] * d2[2] - d1[2] * d2[1];
            nrm[1] = d1[2] * d2[0] - d1[0] * d2[2];
            nrm[2] = d1[0] * d2[1] - d1[1] * d2[0];
            cb_frame f;
            cb_analytic_surface pl;
            cb_error_clear(&err);
            ps->st = cb_frame_make(&f, o, nrm, NULL, &err);
            if (ps->st == CB_OK)
                ps->st = cb_analytic_plane(&pl, &f, &err);
            if (ps->st == CB_OK)
                ps->st = cb_implicit_from_analytic(ps->F, &pl, &err);
        }
    }
    if (ps->st != CB_OK)
        snprintf(ps->msg, sizeof ps->msg, "implicitisation: %.120s", err.msg);
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
    _cb_ssi_spline_stats sst;
    _cb_ssi_piece_set pieces;
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
    double tol, chord, max_seg;
} pair_ctx;

/* The subdivision route for one polynomial patch pair (ssi/spline.h). */
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
    _cb_ssi_spline_opts so = {c->opts->spline_max_depth, c->opts->spline_max_subpairs, c->tol,
                              c->chord, c->max_seg};
    _cb_ssi_spline_pair(&J->pieces, &J->sst, &P, &Q, &so);
    const _cb_ssi_spline_stats *s = &J->sst;
    if (s->uncertified > 0) {
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

    cb_phi_t phi;
    cb_phi_init(phi);
    J->st = cb_phi_compute(phi, F, g.q, &err);
    if (J->st != CB_OK) {
        snprintf(J->msg, sizeof J->msg, "phi: %.150s", err.msg);
        cb_phi_clear(phi);
        return;
    }
    if (phi->ds > c->opts->max_phi_degree || phi->dt > c->opts->max_phi_degree) {
        J->st = CB_ERR_UNSUPPORTED;
        snprintf(J->msg, sizeof J->msg,
                 "phi of bidegree (%ld, %ld) is above the topology stage's limit %ld",
                 (long)phi->ds, (long)phi->dt, (long)c->opts->max_phi_degree);
        cb_phi_clear(phi);
        return;
    }
    slong len = (phi->ds + 1) * (phi->dt + 1), npos = 0, nneg = 0, nz = 0;
    for (slong k = 0; k < len; k++) {
        npos += phi->bern[k] > 0;
        nneg += phi->bern[k] < 0;
        nz += !fmpz_is_zero(phi->c + k);
    }
    if (nz == 0) {
        J->st = CB_ERR_UNSUPPORTED;
        snprintf(J->msg, sizeof J->msg, "the patches lie on one surface (phi = 0)");
        cb_phi_clear(phi);
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
    fmpq_t zero, one;
    fmpq_init(zero);
    fmpq_init(one);
    fmpq_one(one);
    cb_ctopo_t T;
    cb_ctopo_init(T);
    J->st = cb_ctopo_compute(T, mp, ctx, zero, one, zero, one, &c->opts->topo, &err);
    double t1 = now_s();
    J->t_topo = t1 - t0;
    if (J->st != CB_OK) {
        snprintf(J->msg, sizeof J->msg, "topology: %.150s", err.msg);
    } else {
        _cb_ssi_sqf h;
        _cb_ssi_sqf_init(&h);
        _cb_ssi_sqf_set(&h, mp, ctx);
        _cb_ssi_trace_set ts;
        _cb_ssi_trace_set_init(&ts);
        _cb_ssi_trace(&ts, T, &h, _cb_ssi_lift, &g, g.chord, g.max_seg);
        _cb_ssi_clip(&J->pieces, &ts, &g);
        _cb_ssi_trace_set_clear(&ts);
        _cb_ssi_sqf_clear(&h);
        J->t_trace = now_s() - t1;
    }
    cb_ctopo_clear(T);
    fmpq_clear(zero);
    fmpq_clear(one);
    fmpz_mpoly_clear(mp, ctx);
    fmpz_mpoly_ctx_clear(ctx);
}

static void pair_body(void *vctx, size_t begin, size_t end)
{
    pair_ctx *c = vctx;
    for (size_t k = begin; k < end; k++)
        if (c->job[k].spline)
            spline_run(c->job + k, c);
        else if (c->job[k].st == CB_OK)
            pair_run(c->job + k, c);
}

/* Pieces from local patch parameters to the surfaces' domains (analytic angles into
 * [lo, lo + period)). */
static void to_domains(_cb_ssi_piece_set *ps, const cb_dixon_patch_struct *Pp,
                       const cb_ssi_surface *Ps, const cb_dixon_patch_struct *Qp)
{
    double per[2] = {0, 0};
    if (!Pp)
        analytic_periods(per, &Ps->analytic);
    for (slong k = 0; k < ps->n; k++)
        for (slong i = 0; i < ps->p[k].n; i++) {
            _cb_ssi_pq *q = ps->p[k].pt + i;
            double a, b;
            cb_dixon_patch_to_domain(&a, &b, Qp, q->st[0], q->st[1]);
            q->st[0] = a;
            q->st[1] = b;
            if (Pp) {
                cb_dixon_patch_to_domain(&a, &b, Pp, q->uv[0], q->uv[1]);
                q->uv[0] = a;
                q->uv[1] = b;
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

void _cb_ssi_add_failure(cb_ssi_result_t r, int fa, int fb, int pa, int pb, cb_status st,
                        const char *msg)
{
    if (r->n_failed == r->alloc_failed) {
        r->alloc_failed = r->alloc_failed ? 2 * r->alloc_failed : 8;
        r->failed = realloc(r->failed, (size_t)r->alloc_failed * sizeof(*r->failed));
    }
    cb_ssi_failure *f = r->failed + r->n_failed++;
    f->face_a = fa;
    f->face_b = fb;
    f->patch_a = pa;
    f->patch_b = pb;
    f->status = st;
    snprintf(f->msg, sizeof f->msg, "%s", msg);
    f->has_box = 0;
    memset(f->box_a, 0, sizeof f->box_a);
    memset(f->box_b, 0, sizeof f->box_b);
    if (r->status == CB_OK)
        r->status = st;
}

static double surface_dist(const cb_ssi_surface *S, const double uv[2], const double X[3])
{
    double p[3];
    if (S->kind == CB_SSI_ANALYTIC)
        cb_analytic_eval(p, &S->analytic, uv[0], uv[1]);
    else
        cb_nurbs_surface_eval(p, S->nurbs, uv[0], uv[1]);
    return sqrt((p[0] - X[0]) * (p[0] - X[0]) + (p[1] - X[1]) * (p[1] - X[1]) +
                (p[2] - X[2]) * (p[2] - X[2]));
}

/* Distances of an output point to both surfaces at its own parameters: an upper bound on its
 * distance to each surface, recorded in r. */
static void measure(cb_ssi_result_t r, const cb_ssi_surface *A, const cb_ssi_surface *B,
                    const cb_ssi_point *p)
{
    r->max_dist_a = fmax(r->max_dist_a, surface_dist(A, p->uv_a, p->xyz));
    r->max_dist_b = fmax(r->max_dist_b, surface_dist(B, p->uv_b, p->xyz));
}

cb_status cb_ssi_surfaces(cb_ssi_result_t r, const cb_ssi_surface *A, const cb_ssi_surface *B,
                          int face_a, int face_b, const cb_ssi_opts *opts, cb_error *err)
{
    if (A->kind == CB_SSI_ANALYTIC && B->kind == CB_SSI_ANALYTIC)
        return cb_error_set(err, CB_ERR_UNSUPPORTED,
                            "ssi: two analytic surfaces (%s, %s) are not handled",
                            cb_analytic_kind_name(A->analytic.kind),
                            cb_analytic_kind_name(B->analytic.kind));
    /* P is implicitised: the analytic side, or the spline of lower patch bidegree. */
    int swapped;
    if (A->kind == CB_SSI_ANALYTIC)
        swapped = 0;
    else if (B->kind == CB_SSI_ANALYTIC)
        swapped = 1;
    else
        swapped = B->nurbs->deg_u * B->nurbs->deg_v < A->nurbs->deg_u * A->nurbs->deg_v;
    const cb_ssi_surface *Ps = swapped ? B : A, *Qs = swapped ? A : B;
    int fa = face_a, fb = face_b;

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
    r->tol = tol;

    /* Patch pairs surviving the OBB test (section 4.1). */
    pair_job *job = calloc((size_t)np * nq + 1, sizeof(pair_job));
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
                           : (Ps->analytic.kind == CB_ANALYTIC_PLANE
                                  ? 1
                                  : (Ps->analytic.kind == CB_ANALYTIC_TORUS ? 4 : 2));
            slong dq = FLINT_MAX(qpat[j].deg_u, qpat[j].deg_v);
            if (N * dq > opts->max_phi_degree && ppat) {
                job[nj].spline = 1;
                r->pairs_subdivided++;
            } else if (N * dq > opts->max_phi_degree) {
                job[nj].st = CB_ERR_UNSUPPORTED;
                snprintf(job[nj].msg, sizeof job[nj].msg,
                         "phi would have degree up to %ld, above the topology stage's limit %ld",
                         (long)(N * dq), (long)opts->max_phi_degree);
            }
            _cb_ssi_piece_set_init(&job[nj].pieces);
            nj++;
        }
    free(qobb);
    free(pobb);
    free(qbox);
    free(pbox);
    free(qhave);
    free(phave);

    p_side *P = NULL;
    cb_implicit_t F_an;
    cb_implicit_init(F_an);
    cb_dixon_patch_struct *Q = calloc((size_t)nq, sizeof(cb_dixon_patch_struct));
    for (int j = 0; j < nq; j++)
        cb_dixon_patch_init(Q + j);
    for (int j = 0; j < nq && st == CB_OK; j++)
        st = cb_dixon_patch_set_bezier(Q + j, qpat + j, err);
    if (st == CB_OK && ppat) {
        P = calloc((size_t)np, sizeof(p_side));
        for (int i = 0; i < np; i++) {
            cb_dixon_patch_init(P[i].dp);
            cb_dixon_pencil_init(P[i].pencil);
            cb_implicit_init(P[i].F);
        }
        for (slong k = 0; k < nj; k++)
            if (job[k].st == CB_OK && !job[k].spline)
                P[job[k].ip].needed = 1;
        p_ctx pc = {P, ppat};
        st = cb_parallel_for((size_t)np, 1, opts->threads, p_body, &pc);
        if (st != CB_OK)
            cb_error_set(err, st, "ssi: parallel implicitisation failed");
    } else if (st == CB_OK) {
        st = cb_implicit_from_analytic(F_an, &Ps->analytic, err);
    }
    if (st == CB_OK) {
        pair_ctx pc = {job, P, ppat ? NULL : F_an, Ps, Q, ppat, qpat, opts, tol, chord,
                       0.05 * size};
        st = cb_parallel_for((size_t)nj, 1, opts->threads, pair_body, &pc);
        if (st != CB_OK)
            cb_error_set(err, st, "ssi: parallel patch pairs failed");
    }
    if (st == CB_OK) {
        _cb_ssi_piece_set *sets = malloc((size_t)(nj + 1) * sizeof(_cb_ssi_piece_set));
        for (slong k = 0; k < nj; k++) {
            pair_job *J = job + k;
            r->time_topo += J->t_topo;
            r->time_trace += J->t_trace;
            r->subpairs += J->sst.subpairs;
            if (J->st != CB_OK) {
                int pa = ppat ? J->ip : -1, pb = J->iq;
                if (swapped) {
                    int t = pa;
                    pa = pb;
                    pb = t;
                }
                _cb_ssi_add_failure(r, fa, fb, pa, pb, J->st, J->msg);
                if (J->spline && J->sst.uncertified > 0) {
                    cb_ssi_failure *f = r->failed + r->n_failed - 1;
                    double bp[4], bq[4];
                    box_to_domain(bp, J->sst.box_p, ppat + J->ip);
                    box_to_domain(bq, J->sst.box_q, qpat + J->iq);
                    f->has_box = 1;
                    memcpy(swapped ? f->box_b : f->box_a, bp, sizeof bp);
                    memcpy(swapped ? f->box_a : f->box_b, bq, sizeof bq);
                }
            } else {
                r->pairs_certified++;
                r->pairs_empty += J->empty;
            }
            if (!J->spline)
                to_domains(&J->pieces, P ? P[J->ip].dp : NULL, Ps, Q + J->iq);
            sets[k] = J->pieces;
        }
        slong c0 = r->n_curves, q0 = r->n_points;
        /* Pieces of the subdivision route meet at boundary roots solved from the same
         * equations (they agree to round-off), so they are joined at tol: 10 tol, needed for
         * the algebraic route's refined ends, would swallow a piece shorter than that at a
         * patch side and leave the curve ending up to 10 tol short of the face boundary. */
        int all_spline = 1;
        for (slong k = 0; k < nj; k++)
            all_spline &= job[k].spline;
        _cb_ssi_stitch(r, sets, nj, swapped, fa, fb, (all_spline ? 1 : 10) * tol, chord);
        free(sets);
        for (slong c = c0; c < r->n_curves; c++)
            for (slong i = 0; i < r->curve[c].n; i++)
                measure(r, A, B, r->curve[c].pt + i);
        for (slong q = q0; q < r->n_points; q++)
            measure(r, A, B, &r->point[q].p);
    }
    for (slong k = 0; k < nj; k++)
        _cb_ssi_piece_set_clear(&job[k].pieces);
    free(job);
    if (P) {
        for (int i = 0; i < np; i++) {
            cb_dixon_patch_clear(P[i].dp);
            cb_dixon_pencil_clear(P[i].pencil);
            cb_implicit_clear(P[i].F);
        }
        free(P);
    }
    for (int j = 0; j < nq; j++)
        cb_dixon_patch_clear(Q + j);
    free(Q);
    cb_implicit_clear(F_an);
    cb_nurbs_surface_array_free(qpat, nq);
    if (ppat)
        cb_nurbs_surface_array_free(ppat, np);
    return st;
}
