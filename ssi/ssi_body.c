/* ssi_body.c — every face of one body against every face of another (see cb_ssi_bodies). */
#include <math.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brep/bbox.h"
#include "brep/geom.h"
#include "brep/parallel.h"
#include "ssi/ssi.h"

/* Samples per edge used to bound an analytic face's parameters. */
#define EDGE_SAMPLES 17

/* An angle difference brought into [-pi, pi]. */
static double turn_diff(double x)
{
    return x - 2 * CB_SSI_PI * nearbyint(x / (2 * CB_SSI_PI));
}

/* For a circle or ellipse edge over [t0, t1] on a plane a: widens lo, hi (the plane's
 * parameters) to the arc's extremes (where the derivative of each parameter vanishes, within
 * the range) and returns 1; 0 for other curves or surfaces. */
static int conic_on_plane(double lo[2], double hi[2], const cb_analytic_surface *a,
                          const cb_topo_curve *c, double t0, double t1)
{
    if (a->kind != CB_ANALYTIC_PLANE ||
        (c->kind != CB_CURVE_CIRCLE && c->kind != CB_CURVE_ELLIPSE) || !(t1 >= t0))
        return 0;
    const double *ax[2] = {a->frame.x, a->frame.y};
    for (int d = 0; d < 2; d++) {
        /* parameter d along the conic: const + A cos t + B sin t */
        double A = c->r1 * cb_vec3_dot(c->frame.x, ax[d]), B = c->r2 * cb_vec3_dot(c->frame.y, ax[d]);
        double ts = atan2(B, A);
        for (int k = -2; k <= 3; k++) {
            double t = ts + k * CB_SSI_PI;
            if (t < t0 || t > t1)
                continue;
            double X[3], uv[2];
            cb_topo_curve_eval(X, c, t);
            _cb_ssi_analytic_invert(uv, a, X);
            lo[d] = fmin(lo[d], uv[d]);
            hi[d] = fmax(hi[d], uv[d]);
        }
    }
    return 1;
}

/* The face's surface as an SSI input; an analytic face is bounded by the parameter box of its
 * edges (an angle by the shortest arc holding its samples; a seam, or a span of a whole turn
 * or more, makes it the full turn).
 * Returns 1; 0 for surface kinds the driver does not take; -1 when out of memory. */
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
    double lo[2] = {HUGE_VAL, HUGE_VAL}, hi[2] = {-HUGE_VAL, -HUGE_VAL}, grow[2] = {0, 0};
    int have = 0, periodic[2] = {a->kind != CB_ANALYTIC_PLANE, a->kind == CB_ANALYTIC_TORUS};
    const cb_topo_face *f = b->faces + face;
    slong ns = 0, nalloc = 0;
    double *ang = NULL; /* angles of the periodic directions, 2 per sample, in [0, 2 pi) */
    for (int l = f->first; l < f->first + f->count; l++) {
        const cb_topo_loop *lp = b->loops + l;
        for (int c = lp->first; c < lp->first + lp->count; c++) {
            const cb_topo_edge *e = b->edges + b->coedges[c].edge;
            /* this edge's extent in the non-periodic directions and its deviation */
            double prev[2] = {0, 0}, elo[2] = {HUGE_VAL, HUGE_VAL}, ehi[2] = {-HUGE_VAL, -HUGE_VAL};
            double edev[2] = {0, 0};
            for (int k = 0; k < EDGE_SAMPLES; k++) {
                double t = e->t0 + (e->t1 - e->t0) * k / (EDGE_SAMPLES - 1), X[3], uv[2];
                cb_topo_curve_eval(X, b->curves + e->curve, t);
                _cb_ssi_analytic_invert(uv, a, X);
                if (k > 0) {
                    /* how far the edge strays from the chord between two samples, at the
                     * middle of the step (an arc by its sagitta) */
                    double tm = t - 0.5 * (e->t1 - e->t0) / (EDGE_SAMPLES - 1), Xm[3], um[2];
                    cb_topo_curve_eval(Xm, b->curves + e->curve, tm);
                    _cb_ssi_analytic_invert(um, a, Xm);
                    for (int d = 0; d < 2; d++) {
                        double dev = periodic[d]
                                         ? turn_diff(um[d] - prev[d] - 0.5 * turn_diff(uv[d] - prev[d]))
                                         : um[d] - 0.5 * (prev[d] + uv[d]);
                        if (isfinite(dev))
                            edev[d] = fmax(edev[d], fabs(dev));
                    }
                }
                memcpy(prev, uv, sizeof prev);
                if (ns == nalloc) {
                    slong na = nalloc ? 2 * nalloc : 64;
                    double *q = realloc(ang, (size_t)(2 * na) * sizeof(double));
                    if (!q) {
                        free(ang);
                        return -1;
                    }
                    ang = q;
                    nalloc = na;
                }
                for (int d = 0; d < 2; d++) {
                    if (periodic[d]) {
                        ang[2 * ns + d] = fmod(fmod(uv[d], 2 * CB_SSI_PI) + 2 * CB_SSI_PI,
                                               2 * CB_SSI_PI);
                    } else {
                        elo[d] = fmin(elo[d], uv[d]);
                        ehi[d] = fmax(ehi[d], uv[d]);
                    }
                }
                ns++;
                have = 1;
            }
            /* The extremes of an arc lie between its samples (a plane face bounded by a
             * circle of radius r reached r (1 - cos(pi / 16)) beyond them). A conic on a
             * plane has them in closed form (the plane's parameters are affine in space);
             * any other edge's samples' extent is grown by twice its deviation from their
             * chords. Curves are clipped to this box and trimmed to the face's loops later
             * (boolean/cut.c), so a box too large costs little. */
            if (conic_on_plane(elo, ehi, a, b->curves + e->curve, e->t0, e->t1))
                edev[0] = edev[1] = 0;
            for (int d = 0; d < 2; d++)
                if (periodic[d]) {
                    grow[d] = fmax(grow[d], edev[d]);
                } else if (elo[d] <= ehi[d]) {
                    lo[d] = fmin(lo[d], elo[d] - 2 * edev[d]);
                    hi[d] = fmax(hi[d], ehi[d] + 2 * edev[d]);
                }
        }
    }
    /* A periodic direction spans the shortest arc holding every sample: the complement of the
     * largest gap between consecutive sorted angles (robust where samples straddle the branch
     * cut at +-pi, which an unwrapping along the loop could resolve the wrong way). */
    for (int d = 0; d < 2 && have; d++) {
        if (!periodic[d])
            continue;
        double *x = malloc((size_t)ns * sizeof(double));
        if (!x) {
            free(ang);
            return -1;
        }
        for (slong k = 0; k < ns; k++)
            x[k] = ang[2 * k + d];
        for (slong i = 1; i < ns; i++) /* insertion sort: a few hundred samples */
            for (slong j = i; j > 0 && x[j - 1] > x[j]; j--) {
                double tmp = x[j];
                x[j] = x[j - 1];
                x[j - 1] = tmp;
            }
        double gap = x[0] + 2 * CB_SSI_PI - x[ns - 1];
        lo[d] = x[0];
        hi[d] = x[ns - 1];
        for (slong k = 0; k + 1 < ns; k++)
            if (x[k + 1] - x[k] > gap) {
                gap = x[k + 1] - x[k];
                lo[d] = x[k + 1];
                hi[d] = x[k] + 2 * CB_SSI_PI;
            }
        free(x);
    }
    free(ang);
    if (!have)
        return 0;
    /* A seam (an edge used twice by the face) runs along a periodic direction's constant
     * parameter: the face goes once around in that direction, whatever its other edges span
     * (a sphere bounded by its seam alone). */
    int around[2] = {0, 0};
    for (int l = f->first; l < f->first + f->count; l++) {
        const cb_topo_loop *lp = b->loops + l;
        for (int c = lp->first; c < lp->first + lp->count; c++) {
            int e = b->coedges[c].edge, uses = 0;
            for (int l2 = f->first; l2 < f->first + f->count; l2++)
                for (int c2 = b->loops[l2].first; c2 < b->loops[l2].first + b->loops[l2].count;
                     c2++)
                    uses += b->coedges[c2].edge == e;
            if (uses < 2)
                continue;
            const cb_topo_edge *ed = b->edges + e;
            double slo[2] = {HUGE_VAL, HUGE_VAL}, shi[2] = {-HUGE_VAL, -HUGE_VAL};
            for (int k = 1; k + 1 < EDGE_SAMPLES; k++) {
                double t = ed->t0 + (ed->t1 - ed->t0) * k / (EDGE_SAMPLES - 1), X[3], uv[2];
                cb_topo_curve_eval(X, b->curves + ed->curve, t);
                _cb_ssi_analytic_invert(uv, a, X);
                for (int d = 0; d < 2; d++) {
                    slo[d] = fmin(slo[d], uv[d]);
                    shi[d] = fmax(shi[d], uv[d]);
                }
            }
            around[shi[0] - slo[0] > shi[1] - slo[1] ? 1 : 0] = 1;
        }
    }
    /* The periodic directions likewise (an arc of an ellipse in angle). */
    for (int d = 0; d < 2; d++)
        if (periodic[d]) {
            lo[d] -= 2 * grow[d];
            hi[d] += 2 * grow[d];
        }
    if (a->kind == CB_ANALYTIC_SPHERE || a->kind == CB_ANALYTIC_ELLIPSOID) {
        lo[1] = fmax(lo[1], -CB_SSI_PI / 2);
        hi[1] = fmin(hi[1], CB_SSI_PI / 2);
    }
    double range[4] = {lo[0], hi[0], lo[1], hi[1]};
    for (int d = 0; d < 2; d++)
        if (periodic[d] && (around[d] || hi[d] - lo[d] >= 2 * CB_SSI_PI - 1e-6)) {
            range[2 * d] = lo[d];
            range[2 * d + 1] = lo[d] + 2 * CB_SSI_PI;
        }
    if (a->kind == CB_ANALYTIC_SPHERE && range[1] - range[0] >= 2 * CB_SSI_PI - 1e-6) {
        /* A sphere face bounded by a seam and the poles: its latitude range is the sphere's. */
        range[2] = fmin(range[2], -CB_SSI_PI / 2);
        range[3] = fmax(range[3], CB_SSI_PI / 2);
    }
    if (a->kind == CB_ANALYTIC_CONE) {
        /* A face with its apex as a vertex reaches the apex; the inversion of samples at the
         * apex rounds to either side of it. The face lies on one nappe: the side of the
         * sample farthest from the apex. The range stops at the apex. */
        double apex = -a->r1 / tan(a->angle);
        if (range[2] < apex && apex < range[3]) {
            if (apex - range[2] > range[3] - apex)
                range[3] = apex;
            else
                range[2] = apex;
        }
    }
    cb_ssi_surface_set_analytic(S, a, range);
    return 1;
}

/* Axis-aligned box of a face's surface: the control net (NURBS, or the analytic surface's
 * exact rational form over its range). Returns 1; 0 when there is no such form; -1 when out of
 * memory. */
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
    cb_status st = cb_analytic_to_nurbs(net, &S->analytic, r[0], r[1], r[2], r[3], NULL);
    if (st == CB_OK)
        cb_nurbs_surface_aabb(box, net);
    cb_nurbs_surface_clear(net);
    return st == CB_OK ? 1 : (st == CB_ERR_NOMEM ? -1 : 0);
}

/* SSI inputs and boxes of b's faces; ok[i] = 0 for a face the driver does not take.
 * CB_ERR_NOMEM. */
static cb_status body_faces(cb_ssi_surface *S, cb_aabb *box, char *ok, const cb_topo_body *b)
{
    for (int i = 0; i < b->n_faces; i++) {
        int k = face_surface(S + i, b, i);
        if (k > 0)
            k = face_box(box + i, S + i);
        if (k < 0)
            return CB_ERR_NOMEM;
        ok[i] = k > 0;
    }
    return CB_OK;
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
    atomic_long done; /* face pairs finished, for progress */
    long total;       /* face pairs to run */
} fctx;

static void fbody(void *vctx, size_t begin, size_t end)
{
    fctx *c = vctx;
    for (size_t k = begin; k < end; k++) {
        fpair *F = c->f + k;
        if (!F->run)
            continue;
        cb_error_clear(&F->err);
        if (c->o.cancel && cb_context_cancelled(c->o.cancel)) {
            F->st = cb_error_set(&F->err, CB_ERR_CANCELLED, "ssi: cancelled");
            continue;
        }
        F->st = cb_ssi_surfaces(F->r, c->sa + F->i, c->sb + F->j, F->i, F->j, &c->o, &F->err);
        if (c->o.progress)
            cb_context_progress(c->o.progress, (double)(atomic_fetch_add(&c->done, 1) + 1),
                                (double)c->total, "ssi");
    }
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
    slong nf = 0, af = 64;
    fpair *fp = malloc((size_t)af * sizeof(fpair));
    cb_status st = sa && sb && xa && xb && oka && okb && fp ? CB_OK : CB_ERR_NOMEM;
    if (st == CB_OK)
        st = body_faces(sa, xa, oka, a);
    if (st == CB_OK)
        st = body_faces(sb, xb, okb, b);
    /* Face pairs in order: a failure record, or a pair to intersect. */
    for (int i = 0; i < a->n_faces && st == CB_OK; i++)
        for (int j = 0; j < b->n_faces; j++) {
            int bad = !oka[i] || !okb[j];
            if (!bad && !cb_aabb_overlap(xa + i, xb + j, o.tol))
                continue;
            if (nf == af) {
                fpair *q = realloc(fp, (size_t)(2 * af) * sizeof(fpair));
                if (!q) {
                    st = CB_ERR_NOMEM;
                    break;
                }
                fp = q;
                af *= 2;
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
            } else {
                F->run = 1;
            }
        }
    /* Face pairs run in parallel (each serial inside) and are combined in pair order, so the
     * result does not depend on the number of threads. */
    if (st != CB_OK) {
        cb_error_set(err, st, "ssi: out of memory preparing %d x %d faces", a->n_faces,
                     b->n_faces);
    } else {
        fctx fc = {fp, sa, sb, o, 0, 0};
        for (slong k = 0; k < nf; k++)
            fc.total += fp[k].run;
        fc.o.threads = 1;
        st = cb_parallel_for((size_t)nf, 1, o.threads, fbody, &fc);
        if (st != CB_OK)
            cb_error_set(err, st, "ssi: parallel face pairs failed: %s", cb_status_name(st));
    }
    for (slong k = 0; k < nf; k++) {
        fpair *F = fp + k;
        if (st == CB_OK && !F->run &&
            _cb_ssi_add_failure(r, F->i, F->j, -1, -1, CB_ERR_UNSUPPORTED, F->msg) != CB_OK)
            st = cb_error_set(err, CB_ERR_NOMEM, "faces %d, %d: ssi: out of memory recording "
                              "that they are not handled", F->i, F->j);
        if (st == CB_OK && F->run && F->st != CB_OK) {
            st = F->st;
            if (err)
                *err = F->err;
            cb_error_prefix(err, "faces %d, %d: ", F->i, F->j);
        }
        if (st == CB_OK && F->run) {
            /* Face normals of coincident faces: the surface normals times same_sense. */
            for (slong c = 0; c < F->r->n_coincident; c++) {
                cb_ssi_coincident *cr = F->r->coincident + c;
                int flip = (a->faces[F->i].same_sense != 0) != (b->faces[F->j].same_sense != 0);
                cr->same_face_normal = flip ? !cr->same_normal : cr->same_normal;
            }
            if (_cb_ssi_result_move(r, F->r) != CB_OK)
                st = cb_error_set(err, CB_ERR_NOMEM,
                                  "faces %d, %d: ssi: out of memory collecting their result",
                                  F->i, F->j);
        }
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
