/* ssi_body.c — every face of one body against every face of another (see cb_ssi_bodies). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brep/bbox.h"
#include "brep/parallel.h"
#include "ssi/ssi.h"

/* Samples per edge used to bound an analytic face's parameters. */
#define EDGE_SAMPLES 17

/* The face's surface as an SSI input; an analytic face is bounded by the parameter box of its
 * edges (u unwrapped along each loop; a span of a whole turn or more is the full turn).
 * Returns 0 for surface kinds the driver does not take. */
static int face_surface(cb_ssi_surface *S, const cb_topo_body *b, int face)
{
    const cb_topo_surface *ts = b->surfaces + b->faces[face].surface;
    if (ts->kind == CB_SURFACE_NURBS) {
        cb_ssi_surface_set_nurbs(S, ts->nurbs);
        return 1;
    }
    if (ts->kind != CB_SURFACE_ANALYTIC)
        return 0;
    const cb_analytic_surface *a = &ts->analytic;
    double lo[2] = {HUGE_VAL, HUGE_VAL}, hi[2] = {-HUGE_VAL, -HUGE_VAL}, prev[2] = {0, 0};
    int have = 0;
    const cb_topo_face *f = b->faces + face;
    for (int l = f->first; l < f->first + f->count; l++) {
        const cb_topo_loop *lp = b->loops + l;
        for (int c = lp->first; c < lp->first + lp->count; c++) {
            const cb_topo_edge *e = b->edges + b->coedges[c].edge;
            for (int k = 0; k < EDGE_SAMPLES; k++) {
                double t = e->t0 + (e->t1 - e->t0) * k / (EDGE_SAMPLES - 1), X[3], uv[2];
                cb_topo_curve_eval(X, b->curves + e->curve, t);
                _cb_ssi_analytic_invert(uv, a, X);
                int periodic[2] = {a->kind != CB_ANALYTIC_PLANE, a->kind == CB_ANALYTIC_TORUS};
                for (int d = 0; d < 2; d++) {
                    if (periodic[d] && have)
                        uv[d] += 2 * CB_SSI_PI * nearbyint((prev[d] - uv[d]) / (2 * CB_SSI_PI));
                    lo[d] = fmin(lo[d], uv[d]);
                    hi[d] = fmax(hi[d], uv[d]);
                    prev[d] = uv[d];
                }
                have = 1;
            }
        }
    }
    if (!have)
        return 0;
    double range[4] = {lo[0], hi[0], lo[1], hi[1]};
    int periodic[2] = {a->kind != CB_ANALYTIC_PLANE, a->kind == CB_ANALYTIC_TORUS};
    for (int d = 0; d < 2; d++)
        if (periodic[d] && hi[d] - lo[d] >= 2 * CB_SSI_PI - 1e-6) {
            range[2 * d] = lo[d];
            range[2 * d + 1] = lo[d] + 2 * CB_SSI_PI;
        }
    if (a->kind == CB_ANALYTIC_SPHERE && range[1] - range[0] >= 2 * CB_SSI_PI - 1e-6) {
        /* A sphere face bounded by a seam and the poles: its latitude range is the sphere's. */
        range[2] = fmin(range[2], -CB_SSI_PI / 2);
        range[3] = fmax(range[3], CB_SSI_PI / 2);
    }
    cb_ssi_surface_set_analytic(S, a, range);
    return 1;
}

/* Axis-aligned box of a face's surface: the control net (NURBS, or the analytic surface's
 * exact rational form over its range). */
static int face_box(cb_aabb *box, const cb_ssi_surface *S)
{
    if (S->kind == CB_SSI_NURBS) {
        cb_nurbs_surface_aabb(box, S->nurbs);
        return 1;
    }
    double r[4];
    memcpy(r, S->range, sizeof r);
    if (S->analytic.kind == CB_ANALYTIC_SPHERE) {
        r[2] = fmax(r[2], -CB_SSI_PI / 2);
        r[3] = fmin(r[3], CB_SSI_PI / 2);
    }
    cb_nurbs_surface_t net;
    cb_nurbs_surface_init(net);
    int ok = cb_analytic_to_nurbs(net, &S->analytic, r[0], r[1], r[2], r[3], NULL) == CB_OK;
    if (ok)
        cb_nurbs_surface_aabb(box, net);
    cb_nurbs_surface_clear(net);
    return ok;
}

typedef struct {
    int i, j, run; /* run: intersect the faces; else msg is the failure to record */
    char msg[160];
    cb_ssi_result_t r;
    cb_status st;
    cb_error err;
} fpair;

typedef struct {
    fpair *f;
    const cb_ssi_surface *sa, *sb;
    cb_ssi_opts o;
} fctx;

static void fbody(void *vctx, size_t begin, size_t end)
{
    fctx *c = vctx;
    for (size_t k = begin; k < end; k++) {
        fpair *F = c->f + k;
        if (!F->run)
            continue;
        cb_error_clear(&F->err);
        F->st = cb_ssi_surfaces(F->r, c->sa + F->i, c->sb + F->j, F->i, F->j, &c->o, &F->err);
    }
}

/* Appends the content of s to r (s keeps nothing that r owns). */
static void result_move(cb_ssi_result_t r, cb_ssi_result_t s)
{
    if (s->n_curves) {
        if (r->n_curves + s->n_curves > r->alloc_curves) {
            r->alloc_curves = FLINT_MAX(2 * r->alloc_curves, r->n_curves + s->n_curves);
            r->curve = realloc(r->curve, (size_t)r->alloc_curves * sizeof(*r->curve));
        }
        memcpy(r->curve + r->n_curves, s->curve, (size_t)s->n_curves * sizeof(*s->curve));
        r->n_curves += s->n_curves;
        s->n_curves = 0;
    }
    if (s->n_points) {
        if (r->n_points + s->n_points > r->alloc_points) {
            r->alloc_points = FLINT_MAX(2 * r->alloc_points, r->n_points + s->n_points);
            r->point = realloc(r->point, (size_t)r->alloc_points * sizeof(*r->point));
        }
        memcpy(r->point + r->n_points, s->point, (size_t)s->n_points * sizeof(*s->point));
        r->n_points += s->n_points;
    }
    for (slong k = 0; k < s->n_failed; k++) {
        const cb_ssi_failure *f = s->failed + k;
        _cb_ssi_add_failure(r, f->face_a, f->face_b, f->patch_a, f->patch_b, f->status, f->msg);
        cb_ssi_failure *g = r->failed + r->n_failed - 1;
        g->has_box = f->has_box;
        memcpy(g->box_a, f->box_a, sizeof g->box_a);
        memcpy(g->box_b, f->box_b, sizeof g->box_b);
    }
    r->pairs_total += s->pairs_total;
    r->pairs_culled += s->pairs_culled;
    r->pairs_empty += s->pairs_empty;
    r->pairs_certified += s->pairs_certified;
    r->pairs_subdivided += s->pairs_subdivided;
    r->subpairs += s->subpairs;
    r->max_dist_a = fmax(r->max_dist_a, s->max_dist_a);
    r->max_dist_b = fmax(r->max_dist_b, s->max_dist_b);
    r->time_topo += s->time_topo;
    r->time_trace += s->time_trace;
}

cb_status cb_ssi_bodies(cb_ssi_result_t r, const cb_topo_body *a, const cb_topo_body *b,
                        const cb_ssi_opts *opts, cb_error *err)
{
    cb_ssi_opts o = *opts;
    if (o.tol <= 0 || o.chord <= 0) {
        cb_aabb ba, bb;
        cb_topo_body_edge_box(&ba, a);
        cb_topo_body_edge_box(&bb, b);
        double d2 = 0;
        for (int k = 0; k < 3; k++) {
            double ext = fmax(ba.hi[k], bb.hi[k]) - fmin(ba.lo[k], bb.lo[k]);
            d2 += ext * ext;
        }
        if (o.tol <= 0)
            o.tol = 1e-6 * sqrt(d2);
        if (o.chord <= 0)
            o.chord = 1e-3 * sqrt(d2);
    }
    cb_ssi_surface *sa = malloc((size_t)(a->n_faces + 1) * sizeof(cb_ssi_surface));
    cb_ssi_surface *sb = malloc((size_t)(b->n_faces + 1) * sizeof(cb_ssi_surface));
    cb_aabb *xa = malloc((size_t)(a->n_faces + 1) * sizeof(cb_aabb));
    cb_aabb *xb = malloc((size_t)(b->n_faces + 1) * sizeof(cb_aabb));
    char *oka = calloc((size_t)a->n_faces + 1, 1), *okb = calloc((size_t)b->n_faces + 1, 1);
    for (int i = 0; i < a->n_faces; i++)
        oka[i] = face_surface(sa + i, a, i) && face_box(xa + i, sa + i);
    for (int j = 0; j < b->n_faces; j++)
        okb[j] = face_surface(sb + j, b, j) && face_box(xb + j, sb + j);
    /* Face pairs in order: a failure record, or a pair to intersect. */
    slong nf = 0, af = 64;
    fpair *fp = malloc((size_t)af * sizeof(fpair));
    for (int i = 0; i < a->n_faces; i++)
        for (int j = 0; j < b->n_faces; j++) {
            int bad = !oka[i] || !okb[j];
            if (!bad && !cb_aabb_overlap(xa + i, xb + j, o.tol))
                continue;
            if (nf == af) {
                af *= 2;
                fp = realloc(fp, (size_t)af * sizeof(fpair));
            }
            fpair *F = fp + nf++;
            F->i = i;
            F->j = j;
            F->run = 0;
            F->st = CB_OK;
            cb_ssi_result_init(F->r);
            if (bad) {
                const cb_topo_surface *s = !oka[i] ? a->surfaces + a->faces[i].surface
                                                   : b->surfaces + b->faces[j].surface;
                snprintf(F->msg, sizeof F->msg, "face of a %s surface is not handled",
                         cb_topo_surface_type_name(s));
            } else if (sa[i].kind == CB_SSI_ANALYTIC && sb[j].kind == CB_SSI_ANALYTIC) {
                snprintf(F->msg, sizeof F->msg, "analytic/analytic pair (%s, %s) is not handled",
                         cb_analytic_kind_name(sa[i].analytic.kind),
                         cb_analytic_kind_name(sb[j].analytic.kind));
            } else {
                F->run = 1;
            }
        }
    /* Face pairs run in parallel (each serial inside) and are combined in pair order, so the
     * result does not depend on the number of threads. */
    fctx fc = {fp, sa, sb, o};
    fc.o.threads = 1;
    cb_status st = cb_parallel_for((size_t)nf, 1, o.threads, fbody, &fc);
    if (st != CB_OK)
        cb_error_set(err, st, "ssi: parallel face pairs failed");
    for (slong k = 0; k < nf; k++) {
        fpair *F = fp + k;
        if (st == CB_OK && !F->run)
            _cb_ssi_add_failure(r, F->i, F->j, -1, -1, CB_ERR_UNSUPPORTED, F->msg);
        if (st == CB_OK && F->run && F->st != CB_OK) {
            st = F->st;
            if (err)
                *err = F->err;
            cb_error_prefix(err, "faces %d, %d: ", F->i, F->j);
        }
        if (st == CB_OK && F->run)
            result_move(r, F->r);
        cb_ssi_result_clear(F->r);
    }
    free(fp);
    r->tol = o.tol;
    free(sa);
    free(sb);
    free(xa);
    free(xb);
    free(oka);
    free(okb);
    return st;
}
