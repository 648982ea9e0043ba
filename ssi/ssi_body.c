/* ssi_body.c — every face of one body against every face of another (see cb_ssi_bodies). */
#include <math.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brep/bbox.h"
#include "brep/face.h"
#include "brep/geom.h"
#include "brep/parallel.h"
#include "ssi/ssi.h"

/* Samples per edge used to bound an analytic face's parameters. */
#define EDGE_SAMPLES 17

/* Arcs of converted faces (revolutions, extrusions of conics) with weights cos(pi / 4)
 * rounded, the symmetric form CAD systems write, not the exact quarter-turn form
 * (cb_topo_surface_to_nurbs): the torus of revolution cut through its seam plane gave 34
 * pieces, each stretch along the seam traced from both of its B-spline sides, with the exact
 * form (end rows 16 times apart), 4 curves with this one (end rows bitwise equal). */
#define REVOLVE_EXACT 0

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
        double A = c->r1 * cb_vec3_dot(c->frame.x, ax[d]);
        double B = c->r2 * cb_vec3_dot(c->frame.y, ax[d]);
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

/* A face whose surface the driver converted to a rational B-spline for the SSI, or whose
 * B-spline surface it restricted to the part its loops reach. */
typedef struct {
    int on;                   /* 1: converted; net and range are set */
    const cb_topo_surface *s; /* the face's surface */
    double range[4];          /* its parameter box that net covers */
    cb_nurbs_surface_t net;   /* cb_topo_surface_to_nurbs(s, range), or the restriction */
    int sub;                  /* 1: net is s's B-spline over part of its domain (same
                                 parameters); patch (i, j) of net, of which there are
                                 sub_npv along v, lies in patch (i + off[0], j + off[1]) of
                                 s's, of which there are npv along v */
    int off[2], npv, sub_npv;
    int has_tight;  /* tight is set: the box of s over its loops' (u, v) box */
    cb_aabb tight;
} face_conv;

/* How a face's edge points get its surface's parameters while bounding the face: the
 * coedges' pcurves (the face's own parameters, where a point of a surface covered twice, as a
 * circle through the axis revolved covers a sphere, has two), or the 3D points inverted: closed
 * form for an analytic surface, the topology inverter (global search) for a revolution or
 * extrusion. periodic[d]: direction d is an angle (period 2 pi). */
typedef struct {
    const cb_analytic_surface *a;
    const cb_topo_inverter *inv;
    int periodic[2];
    int pole_dir; /* a direction whose angle is undefined where the surface collapses (the
                     angle of a revolution on its axis), or -1 */
    double *prange; /* NULL, or per coedge of the body the pcurve parameters at its ends
                       (cb_topo_coedge_pcurve_range): sample the pcurves */
} face_inv;

/* (u, v) of X; an angle left undefined by the geometry (a point on a revolution's axis) is NaN,
 * so that it does not widen the face's angular range. */
static void face_invert(double uv[2], const face_inv *fi, const double X[3])
{
    if (fi->a) {
        _cb_ssi_analytic_invert(uv, fi->a, X);
        return;
    }
    cb_topo_inverter_invert(uv, fi->inv, X, NULL);
    if (fi->pole_dir >= 0 && (cb_topo_inverter_collapsed(fi->inv, uv[0], uv[1]) &
                              (1 << fi->pole_dir)))
        uv[fi->pole_dir] = NAN;
}

/* (u, v) of coedge c's sample k of EDGE_SAMPLES along its edge (mid: half a step before it). */
static void coedge_uv(double uv[2], const face_inv *fi, const cb_topo_body *b, int c, int k,
                      int mid)
{
    if (fi->prange) {
        const double *s = fi->prange + 2 * c;
        double t = s[0] + (s[1] - s[0]) * k / (EDGE_SAMPLES - 1), p[3];
        if (mid)
            t -= 0.5 * (s[1] - s[0]) / (EDGE_SAMPLES - 1);
        cb_topo_pcurve_eval(p, b->pcurves + b->coedges[c].pcurve, t);
        uv[0] = p[0];
        uv[1] = p[1];
        return;
    }
    const cb_topo_edge *e = b->edges + b->coedges[c].edge;
    double t = e->t0 + (e->t1 - e->t0) * k / (EDGE_SAMPLES - 1), X[3];
    if (mid)
        t -= 0.5 * (e->t1 - e->t0) / (EDGE_SAMPLES - 1);
    cb_topo_curve_eval(X, b->curves + e->curve, t);
    face_invert(uv, fi, X);
}

/* The parameter box of a face's edges on its surface, range = {u0, u1, v0, v1}: an angle by
 * the shortest arc holding its samples (a seam, or a span of a whole turn or more, makes it
 * the full turn [lo, lo + 2 pi]), the other directions by the samples' extent; both grown by
 * the edges' deviation from their sample chords. Returns 1; 0 when the face has no edge
 * samples; -1 when out of memory. */
static int face_range(double range[4], const face_inv *fi, const cb_topo_body *b, int face)
{
    double lo[2] = {HUGE_VAL, HUGE_VAL}, hi[2] = {-HUGE_VAL, -HUGE_VAL}, grow[2] = {0, 0};
    const int *periodic = fi->periodic;
    int have = 0;
    const cb_topo_face *f = b->faces + face;
    slong ns = 0, nalloc = 0;
    double *ang = NULL; /* angles of the periodic directions, 2 per sample, in [0, 2 pi) */
    double ref[2] = {NAN, NAN}; /* the first defined angle of each periodic direction */
    for (int l = f->first; l < f->first + f->count; l++) {
        const cb_topo_loop *lp = b->loops + l;
        for (int c = lp->first; c < lp->first + lp->count; c++) {
            /* this edge's extent in the non-periodic directions and its deviation */
            double prev[2] = {0, 0}, elo[2] = {HUGE_VAL, HUGE_VAL}, ehi[2] = {-HUGE_VAL, -HUGE_VAL};
            double edev[2] = {0, 0};
            for (int k = 0; k < EDGE_SAMPLES; k++) {
                double uv[2];
                coedge_uv(uv, fi, b, c, k, 0);
                if (k > 0) {
                    /* how far the edge strays from the chord between two samples, at the
                     * middle of the step (an arc by its sagitta) */
                    double um[2];
                    coedge_uv(um, fi, b, c, k, 1);
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
                    if (periodic[d] && isnan(ref[d]))
                        ref[d] = uv[d];
                    if (periodic[d]) {
                        ang[2 * ns + d] = fmod(fmod(uv[d], 2 * CB_SSI_PI) + 2 * CB_SSI_PI,
                                               2 * CB_SSI_PI);
                    } else if (isfinite(uv[d])) {
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
            const cb_topo_edge *ed = b->edges + b->coedges[c].edge;
            if (fi->a && conic_on_plane(elo, ehi, fi->a, b->curves + ed->curve, ed->t0, ed->t1))
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
     * cut at +-pi, which an unwrapping along the loop could resolve the wrong way). Undefined
     * angles (NaN: points on an axis) are left out. */
    for (int d = 0; d < 2 && have; d++) {
        if (!periodic[d])
            continue;
        double *x = malloc((size_t)ns * sizeof(double));
        if (!x) {
            free(ang);
            return -1;
        }
        slong nx = 0;
        for (slong k = 0; k < ns; k++)
            if (isfinite(ang[2 * k + d]))
                x[nx++] = ang[2 * k + d];
        for (slong i = 1; i < nx; i++) /* insertion sort: a few hundred samples */
            for (slong j = i; j > 0 && x[j - 1] > x[j]; j--) {
                double tmp = x[j];
                x[j] = x[j - 1];
                x[j - 1] = tmp;
            }
        if (nx == 0) { /* every sample on the axis: nothing bounds the angle */
            lo[d] = 0;
            hi[d] = 2 * CB_SSI_PI;
            free(x);
            continue;
        }
        double gap = x[0] + 2 * CB_SSI_PI - x[nx - 1];
        lo[d] = x[0];
        hi[d] = x[nx - 1];
        for (slong k = 0; k + 1 < nx; k++)
            if (x[k + 1] - x[k] > gap) {
                gap = x[k + 1] - x[k];
                lo[d] = x[k + 1];
                hi[d] = x[k] + 2 * CB_SSI_PI;
            }
        free(x);
        if (fi->prange) {
            /* Pcurves place the face in a lift of their own: the arc is moved by whole turns
             * to hold the first sample as the pcurve gives it (the reparameterised points then
             * lie in the face's lift). */
            double turns = floor((ref[d] - lo[d]) / (2 * CB_SSI_PI));
            lo[d] += 2 * CB_SSI_PI * turns;
            hi[d] += 2 * CB_SSI_PI * turns;
        }
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
            /* the seam's extent in each direction; for a converted face an angle measured
             * from the first defined sample, as the inverter gives a seam at angle 0 as 0 or
             * as 2 pi - eps (analytic faces: the closed-form angles in (-pi, pi] as they are,
             * which would see a seam at angle pi as a whole turn) */
            double slo[2] = {HUGE_VAL, HUGE_VAL}, shi[2] = {-HUGE_VAL, -HUGE_VAL};
            double first[2] = {NAN, NAN};
            for (int k = 1; k + 1 < EDGE_SAMPLES; k++) {
                double uv[2];
                coedge_uv(uv, fi, b, c, k, 0);
                for (int d = 0; d < 2; d++)
                    if (isfinite(uv[d])) {
                        if (periodic[d] && !fi->a) {
                            if (isnan(first[d]))
                                first[d] = uv[d];
                            uv[d] = turn_diff(uv[d] - first[d]);
                        }
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
    range[0] = lo[0];
    range[1] = hi[0];
    range[2] = lo[1];
    range[3] = hi[1];
    for (int d = 0; d < 2; d++)
        if (periodic[d] && (around[d] || hi[d] - lo[d] >= 2 * CB_SSI_PI - 1e-6)) {
            range[2 * d] = lo[d];
            range[2 * d + 1] = lo[d] + 2 * CB_SSI_PI;
        }
    return 1;
}

/* restrict_nurbs: the box of a B-spline face's loops in (u, v), grown by RESTRICT_MARGIN of
 * the domain's width, bounds the face for the face pairs' overlap test; the part of its
 * surface the SSI takes reaches beyond that box by RESTRICT_GROW of the box's width (at least
 * the margin), so that curves leaving the face end well beyond its boundary, not within the
 * Boolean's snapping distances of it, but not past the knot lines around the grown box (where
 * the knot spans are fine, more of them would only add patch pairs); a cut within
 * RESTRICT_SNAP of a knot span's width from a knot moves out to the knot (restrict_end). */
#define RESTRICT_MARGIN 1e-3
#define RESTRICT_GROW 0.25
#define RESTRICT_SNAP 1e-3

/* Distinct knot values of the domain [U[p], U[n]] (n control points) below x: the Bezier
 * patches before x along that direction, and the one holding x when x is not a knot. */
static int spans_below(const double *U, int n, int p, double x)
{
    int k = 0;
    for (int i = p; i <= n; i++)
        k += U[i] < x && (i == p || U[i] != U[i - 1]);
    return k;
}

/* Where a restriction of the domain [U[p], U[n + 1]] ends (side -1: its low end, +1: its high
 * end) when it should reach x: x itself; the end of x's knot span on that side when x lies
 * within RESTRICT_SNAP of the span's width from either of its knots (no sliver patch, no knot
 * inserted next to another); the domain's end when x lies beyond it. */
static double restrict_end(const double *U, int n, int p, double x, int side)
{
    if (x <= U[p])
        return U[p];
    if (x >= U[n + 1])
        return U[n + 1];
    int i = cb_bspline_find_span(n + 1, p, U, x);
    double a = U[i], b = U[i + 1], snap = RESTRICT_SNAP * (b - a);
    if (x - a <= snap || b - x <= snap)
        return side < 0 ? a : (x == a ? a : b);
    return x;
}

/* out = s over the parameter box {u0, u1, v0, v1} inside its domain, by knot insertion
 * (cb_nurbs_surface_split, in place): the same surface and parameters. */
static cb_status sub_net(cb_nurbs_surface_t out, const cb_nurbs_surface_struct *s,
                         const double box[4])
{
    double dom[4];
    cb_nurbs_surface_domain(s, dom);
    cb_nurbs_surface_t rest;
    cb_nurbs_surface_init(rest);
    cb_status st = cb_nurbs_surface_set(out, s, NULL);
    for (int d = 0; d < 2 && st == CB_OK; d++) {
        if (box[2 * d] > dom[2 * d])
            st = cb_nurbs_surface_split(rest, out, out, (cb_dir)d, box[2 * d], NULL);
        if (st == CB_OK && box[2 * d + 1] < dom[2 * d + 1])
            st = cb_nurbs_surface_split(out, rest, out, (cb_dir)d, box[2 * d + 1], NULL);
    }
    cb_nurbs_surface_clear(rest);
    return st;
}

/* A B-spline face as the part of its surface that its loops reach: the box of its coedges'
 * pcurves in (u, v) (a B-spline pcurve by its control points, which hold the whole curve; a line by
 * its ends; a conic by its centre and radius), grown by RESTRICT_GROW of its width (at least
 * RESTRICT_MARGIN of the domain; out to a knot line when one is that close: restrict_end) but not
 * past the knot lines around it grown by the margin, cut out of the surface exactly (knot
 * insertion; the parameters stay the surface's). Every point of the face lies inside the loops and
 * so inside that box; an intersection curve running out of it ends on the cut, outside the face,
 * where the Boolean's trim (boolean/cut.c) would have cut it anyway. CAD systems trim B-spline
 * faces out of larger surfaces: two copies of a 39-face part had 232 curves of which 20 reached
 * inside both faces; and a band of a cone written as one span of a B-spline reaching the apex,
 * against a turned copy, met it at the apex (a point both surfaces pass through, which subdivision
 * cannot separate) though the band stays far from it. Also sets conv->tight, the box of the surface
 * over the pcurves' box itself (grown by the margin), which bounds the face for the face pairs'
 * overlap test; the 3D edges are checked to lie in it. Returns 1 (conv->net, sub and off set); 0 to
 * use the whole surface (the box reaches its ends: tight may still be set; or a coedge has no
 * pcurve reaching its edge's ends, a loop does not close in (u, v), or an edge leaves that box:
 * tight unset); -1 when out of memory. */
static int restrict_nurbs(face_conv *conv, const cb_topo_surface *ts, const cb_topo_body *b,
                          int face)
{
    const cb_nurbs_surface_struct *s = ts->nurbs;
    cb_topo_inverter inv;
    double tol = b->tol > 0 ? b->tol : 1e-7;
    if (cb_topo_inverter_init(&inv, ts, tol, NULL) != CB_OK)
        return -1;
    double lo[2] = {HUGE_VAL, HUGE_VAL}, hi[2] = {-HUGE_VAL, -HUGE_VAL}, dom[4];
    cb_nurbs_surface_domain(s, dom);
    const cb_topo_face *f = b->faces + face;
    int ok = 1;
    for (int l = f->first; ok && l < f->first + f->count; l++) {
        double first[3] = {0, 0, 0}, prev[3] = {0, 0, 0};
        for (int c = b->loops[l].first; ok && c < b->loops[l].first + b->loops[l].count; c++) {
            const cb_topo_coedge *ce = b->coedges + c;
            double etol = fmax(tol, b->edges[ce->edge].tol), s0, s1;
            ok = ce->pcurve >= 0 && cb_topo_coedge_pcurve_range(&s0, &s1, b, c, &inv, etol) <= etol;
            if (!ok)
                break;
            const cb_topo_curve *pc = b->pcurves + ce->pcurve;
            double pt[3][3], e0[3];
            int np = 0;
            /* The loops must close in (u, v): one that jumps by a period of a closed surface
             * winds round it, and the face reaches beyond its box (a cap round a pole). */
            cb_topo_pcurve_eval(e0, pc, s0);
            if (c == b->loops[l].first)
                memcpy(first, e0, sizeof first);
            else
                ok = fabs(e0[0] - prev[0]) <= 0.25 * (dom[1] - dom[0]) &&
                     fabs(e0[1] - prev[1]) <= 0.25 * (dom[3] - dom[2]);
            cb_topo_pcurve_eval(prev, pc, s1);
            if (c + 1 == b->loops[l].first + b->loops[l].count)
                ok &= fabs(first[0] - prev[0]) <= 0.25 * (dom[1] - dom[0]) &&
                      fabs(first[1] - prev[1]) <= 0.25 * (dom[3] - dom[2]);
            if (pc->kind == CB_CURVE_NURBS) {
                const cb_nurbs_curve_struct *n = pc->nurbs;
                for (int i = 0; i < n->n; i++) {
                    const double *w = n->cw + 4 * i;
                    double uv[2] = {w[0] / w[3], w[1] / w[3]};
                    for (int d = 0; d < 2; d++) {
                        lo[d] = fmin(lo[d], uv[d]);
                        hi[d] = fmax(hi[d], uv[d]);
                    }
                    ok &= w[3] > 0;
                }
            } else if (pc->kind == CB_CURVE_LINE) {
                cb_topo_pcurve_eval(pt[np++], pc, s0);
                cb_topo_pcurve_eval(pt[np++], pc, s1);
            } else {
                double r = fmax(pc->r1, pc->r2);
                for (int d = 0; d < 2; d++) {
                    lo[d] = fmin(lo[d], pc->frame.o[d] - r);
                    hi[d] = fmax(hi[d], pc->frame.o[d] + r);
                }
            }
            for (int k = 0; k < np; k++)
                for (int d = 0; d < 2; d++) {
                    lo[d] = fmin(lo[d], pt[k][d]);
                    hi[d] = fmax(hi[d], pt[k][d]);
                }
        }
    }
    cb_topo_inverter_clear(&inv);
    double cut[4], tight[4];
    int whole = 1;
    for (int d = 0; ok && d < 2; d++) {
        const double *U = d ? s->knots_v : s->knots_u;
        int n = (d ? s->n_v : s->n_u) - 1, p = d ? s->deg_v : s->deg_u;
        double m = RESTRICT_MARGIN * (dom[2 * d + 1] - dom[2 * d]);
        double a = lo[d] - m, z = hi[d] + m;
        ok = isfinite(a) && isfinite(z);
        tight[2 * d] = fmax(dom[2 * d], a);
        tight[2 * d + 1] = fmin(dom[2 * d + 1], z);
        if (ok) {
            /* the knot lines around the box grown by the margin bound the cut */
            double g = fmax(m, RESTRICT_GROW * (hi[d] - lo[d])), kl = dom[2 * d],
                   kh = dom[2 * d + 1];
            for (int i = p; i <= n + 1; i++)
                if (U[i] <= a)
                    kl = U[i];
            for (int i = n + 1; i >= p; i--)
                if (U[i] >= z)
                    kh = U[i];
            cut[2 * d] = fmax(kl, restrict_end(U, n, p, lo[d] - g, -1));
            cut[2 * d + 1] = fmin(kh, restrict_end(U, n, p, hi[d] + g, 1));
        }
        whole &= cut[2 * d] == dom[2 * d] && cut[2 * d + 1] == dom[2 * d + 1];
        ok &= cut[2 * d] < cut[2 * d + 1];
    }
    if (!ok)
        return 0;
    /* The box of the surface over the loops' own (u, v) box (cb_face_surface_box: the
     * sub-patch's control points), for the face pairs' culling: a face trimmed out of one
     * span (a single Bezier patch) is not restricted, but its box is still that of its part. */
    if (tight[0] < tight[1] && tight[2] < tight[3]) {
        cb_status bs = cb_face_surface_box(&conv->tight, ts, tight, NULL);
        if (bs == CB_ERR_NOMEM)
            return -1;
        conv->has_tight = bs == CB_OK;
    }
    /* The pcurves agree with their edges at the ends (cb_topo_coedge_pcurve_range); their
     * middles are checked here: every edge sample must lie in that box (within the edge's
     * tolerance), or the face is taken whole. */
    for (int l = f->first; conv->has_tight && l < f->first + f->count; l++)
        for (int c = b->loops[l].first; c < b->loops[l].first + b->loops[l].count; c++) {
            const cb_topo_edge *e = b->edges + b->coedges[c].edge;
            double slack = fmax(tol, e->tol);
            for (int k = 0; k < EDGE_SAMPLES; k++) {
                double X[3];
                cb_topo_curve_eval(X, b->curves + e->curve,
                                   e->t0 + (e->t1 - e->t0) * k / (EDGE_SAMPLES - 1));
                for (int q = 0; q < 3; q++)
                    if (!(X[q] >= conv->tight.lo[q] - slack && X[q] <= conv->tight.hi[q] + slack))
                        conv->has_tight = 0;
            }
        }
    if (!conv->has_tight)
        return 0;
    if (whole)
        return 0;
    cb_status st = sub_net(conv->net, s, cut);
    if (st != CB_OK)
        return st == CB_ERR_NOMEM ? -1 : 0;
    conv->sub = 1;
    for (int d = 0; d < 2; d++) {
        const double *U = d ? s->knots_v : s->knots_u;
        int n = d ? s->n_v : s->n_u, p = d ? s->deg_v : s->deg_u;
        /* a cut inside a span: that span is the net's first */
        conv->off[d] = spans_below(U, n, p, cut[2 * d]) -
                       (U[cb_bspline_find_span(n, p, U, cut[2 * d])] < cut[2 * d]);
    }
    conv->npv = spans_below(s->knots_v, s->n_v, s->deg_v, dom[3]);
    conv->sub_npv = spans_below(s->knots_v, s->n_v, s->deg_v, cut[3]) - conv->off[1];
    return 1;
}

/* The face's surface as an SSI input. A NURBS face is its surface; an analytic face is
 * bounded by the parameter box of its edges (face_range). A face of a revolution or extrusion
 * becomes the exact rational B-spline of its surface over that box (cb_topo_surface_to_nurbs,
 * held in conv->net; the box from the face's pcurves where it has them: a circle through the
 * axis revolved covers a sphere twice, and an inversion may pick either sheet): a B-spline
 * profile over its whole domain, a full turn as [0, 2 pi] (the profile's own position, where
 * files put a revolved face's seam), other angles and lines over the box; conv->range keeps
 * the box for mapping the SSI's parameters back (reparam).
 * Returns 1; 0 for surface kinds the driver does not take or faces it cannot bound; -1 when
 * out of memory. */
static int face_surface(cb_ssi_surface *S, face_conv *conv, const cb_topo_body *b, int face)
{
    const cb_topo_surface *ts = b->surfaces + b->faces[face].surface;
    conv->s = ts;
    conv->on = 0;
    conv->sub = conv->has_tight = 0;
    if (ts->kind == CB_SURFACE_NURBS) {
        int k = restrict_nurbs(conv, ts, b, face);
        if (k < 0)
            return -1;
        cb_ssi_surface_set_nurbs(S, k ? conv->net : ts->nurbs);
        return 1;
    }
    if (ts->kind == CB_SURFACE_REVOLUTION || ts->kind == CB_SURFACE_EXTRUSION) {
        int rev = ts->kind == CB_SURFACE_REVOLUTION, pd = rev ? 1 : 0; /* profile direction */
        cb_curve_kind pk = ts->profile.kind;
        int conic = pk == CB_CURVE_CIRCLE || pk == CB_CURVE_ELLIPSE;
        cb_topo_inverter inv;
        double tol = b->tol > 0 ? b->tol : 1e-7;
        if (cb_topo_inverter_init(&inv, ts, tol, NULL) != CB_OK)
            return -1; /* the inverter's only error is running out of memory */
        face_inv fi = {NULL, &inv, {rev || (pd == 0 && conic), pd == 1 && conic}, rev ? 0 : -1,
                       NULL};
        /* The face's own parameters from its pcurves where every coedge has one reaching its
         * edge's ends (within the edge's tolerance); else the edges' points inverted. */
        const cb_topo_face *f = b->faces + face;
        double *pr = malloc((size_t)(b->n_coedges + 1) * 2 * sizeof(double));
        int use = pr != NULL;
        for (int l = f->first; use && l < f->first + f->count; l++)
            for (int c = b->loops[l].first; use && c < b->loops[l].first + b->loops[l].count;
                 c++) {
                const cb_topo_edge *e = b->edges + b->coedges[c].edge;
                double etol = fmax(tol, e->tol);
                use = b->coedges[c].pcurve >= 0 &&
                      cb_topo_coedge_pcurve_range(pr + 2 * c, pr + 2 * c + 1, b, c, &inv, etol) <=
                          etol;
            }
        fi.prange = use ? pr : NULL;
        double range[4];
        int k = face_range(range, &fi, b, face);
        free(pr);
        cb_topo_inverter_clear(&inv);
        if (k <= 0)
            return k;
        for (int d = 0; d < 2; d++)
            if (fi.periodic[d] && range[2 * d + 1] - range[2 * d] >= 2 * CB_SSI_PI - 1e-9) {
                range[2 * d] = 0;
                range[2 * d + 1] = 2 * CB_SSI_PI;
            }
        if (pk == CB_CURVE_NURBS)
            cb_nurbs_curve_domain(ts->profile.nurbs, range + 2 * pd, range + 2 * pd + 1);
        memcpy(conv->range, range, sizeof range);
        cb_status st = cb_topo_surface_to_nurbs(conv->net, ts, range, REVOLVE_EXACT, NULL);
        if (st != CB_OK)
            return st == CB_ERR_NOMEM ? -1 : 0;
        conv->on = 1;
        cb_ssi_surface_set_nurbs(S, conv->net);
        return 1;
    }
    if (ts->kind != CB_SURFACE_ANALYTIC)
        return 0;
    const cb_analytic_surface *a = &ts->analytic;
    face_inv fi = {a, NULL, {a->kind != CB_ANALYTIC_PLANE, a->kind == CB_ANALYTIC_TORUS}, -1,
                   NULL};
    double range[4];
    int k = face_range(range, &fi, b, face);
    if (k <= 0)
        return k;
    if (a->kind == CB_ANALYTIC_SPHERE || a->kind == CB_ANALYTIC_ELLIPSOID) {
        range[2] = fmax(range[2], -CB_SSI_PI / 2);
        range[3] = fmin(range[3], CB_SSI_PI / 2);
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

/* uv of conv->net mapped to the face's own surface parameters. */
static void map_uv(double uv[2], const face_conv *conv)
{
    double st[2] = {uv[0], uv[1]};
    cb_topo_surface_nurbs_param(uv, conv->s, conv->range, REVOLVE_EXACT, st);
}

/* A parameter box {u0, u1, v0, v1} mapped by its corners (the map increases per direction). */
static void map_box(double box[4], const face_conv *conv)
{
    double lo[2] = {box[0], box[2]}, hi[2] = {box[1], box[3]};
    map_uv(lo, conv);
    map_uv(hi, conv);
    box[0] = lo[0];
    box[1] = hi[0];
    box[2] = lo[1];
    box[3] = hi[1];
}

/* The SSI's parameters on a converted face (conv->net) mapped to the face's own
 * (cb_topo_surface_nurbs_param: per direction a strictly increasing closed form, so curves
 * keep their topology and point order), in every record of side `side` (0: A) of r: curve and
 * isolated points, marks, the parameter boxes of regions and failures (their corners: the map
 * is increasing in each direction). Patch indices of that side become -1: they number the
 * converted net's Bezier patches, not anything of the face. */
static void reparam(cb_ssi_result_t r, int side, const face_conv *conv)
{
    for (slong c = 0; c < r->n_curves; c++)
        for (slong i = 0; i < r->curve[c].n; i++)
            map_uv(side ? r->curve[c].pt[i].uv_b : r->curve[c].pt[i].uv_a, conv);
    for (slong k = 0; k < r->n_points; k++)
        map_uv(side ? r->point[k].p.uv_b : r->point[k].p.uv_a, conv);
    for (slong k = 0; k < r->n_marks; k++)
        if (r->mark[k].q_side == side) {
            map_uv(r->mark[k].uv, conv);
            r->mark[k].patch = -1;
        }
    for (slong k = 0; k < r->n_regions; k++) {
        cb_ssi_region *g = r->region + k;
        map_box(side ? g->box_b : g->box_a, conv);
        *(side ? &g->patch_b : &g->patch_a) = -1;
    }
    for (slong k = 0; k < r->n_failed; k++) {
        cb_ssi_failure *f = r->failed + k;
        if (f->has_box)
            map_box(side ? f->box_b : f->box_a, conv);
        *(side ? &f->patch_b : &f->patch_a) = -1;
    }
    for (slong k = 0; k < r->n_coincident; k++)
        *(side ? &r->coincident[k].patch_b : &r->coincident[k].patch_a) = -1;
}

/* Patch p of a restricted face's net (conv->sub) as the index of the patch of its whole
 * surface holding it (cb_nurbs_surface_extract_bezier's order, u outer); -1 stays -1. */
static int whole_patch(int p, const face_conv *conv)
{
    int nv = conv->sub_npv;
    return p < 0 ? p : (p / nv + conv->off[0]) * conv->npv + p % nv + conv->off[1];
}

/* The patch indices of side `side` (0: A) of r made those of the face's whole surface. */
static void renumber(cb_ssi_result_t r, int side, const face_conv *conv)
{
    for (slong k = 0; k < r->n_marks; k++)
        if (r->mark[k].q_side == side)
            r->mark[k].patch = whole_patch(r->mark[k].patch, conv);
    for (slong k = 0; k < r->n_regions; k++) {
        int *p = side ? &r->region[k].patch_b : &r->region[k].patch_a;
        *p = whole_patch(*p, conv);
    }
    for (slong k = 0; k < r->n_failed; k++) {
        int *p = side ? &r->failed[k].patch_b : &r->failed[k].patch_a;
        *p = whole_patch(*p, conv);
    }
    for (slong k = 0; k < r->n_coincident; k++) {
        int *p = side ? &r->coincident[k].patch_b : &r->coincident[k].patch_a;
        *p = whole_patch(*p, conv);
    }
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

/* SSI inputs, conversions and boxes of b's faces; ok[i] = 0 for a face the driver does not
 * take. CB_ERR_NOMEM. */
static cb_status body_faces(cb_ssi_surface *S, face_conv *conv, cb_aabb *box, char *ok,
                            const cb_topo_body *b)
{
    for (int i = 0; i < b->n_faces; i++) {
        int k = face_surface(S + i, conv + i, b, i);
        if (k > 0)
            k = face_box(box + i, S + i);
        if (k > 0 && conv[i].has_tight)
            box[i] = conv[i].tight;
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

/* 1 when the parameter box (of face f's surface, finite) lies outside the trimmed face, away
 * from its boundary: its centre classifies OUT; no loop segment meets the box grown by the
 * segment's deviation bound (every lift of the box by a period counted), so the whole box is on
 * the centre's side of the loops; and no sample of a boundary edge (each curve point within gap
 * of one) meets the surface's box over it (cb_face_surface_box, into x) grown by tol plus the
 * edge's tolerance, its pcurve's offset and gap, so no point of it is ON either. Boxes grown
 * per axis hold the balls of those radii: each test only refuses more. */
static int box_outside_face(cb_aabb *x, const cb_face *f, const double box[4], double tol)
{
    for (int k = 0; k < 2; k++) {
        double per = f->inv.period[k];
        if (!(box[2 * k] <= box[2 * k + 1]) || !isfinite(box[2 * k] + box[2 * k + 1]) ||
            (per > 0 && !(box[2 * k + 1] - box[2 * k] < per)))
            return 0;
    }
    if (cb_face_classify_uv(f, 0.5 * (box[0] + box[1]), 0.5 * (box[2] + box[3]), tol) !=
        CB_FACE_OUT)
        return 0;
    int ku = f->inv.period[0] > 0 ? 2 : 0, kv = f->inv.period[1] > 0 ? 2 : 0;
    for (int i = -ku; i <= ku; i++)
        for (int j = -kv; j <= kv; j++) {
            double su = i * f->inv.period[0], sv = j * f->inv.period[1];
            const double lo[3] = {box[0] + su, box[2] + sv, 0};
            const double hi[3] = {box[1] + su, box[3] + sv, 0};
            for (int g = 0; g < f->n_segs; g++) {
                const cb_face_seg *sg = f->segs + g;
                const double p[3] = {sg->p[0], sg->p[1], 0}, q[3] = {sg->q[0], sg->q[1], 0};
                if (!(sg->dev >= 0) || cb_seg3_meets_box(p, q, lo, hi, sg->dev))
                    return 0;
            }
        }
    cb_error e;
    const cb_topo_body *b = f->b;
    if (cb_face_surface_box(x, b->surfaces + b->faces[f->face].surface, box, &e) != CB_OK)
        return 0;
    for (int g = 0; g < f->n_edges; g++) {
        const cb_face_edge *ed = f->edges + g;
        if (!ed->boundary)
            continue;
        double margin = tol + ed->off + b->edges[ed->edge].tol + ed->gap;
        if (!cb_aabb_overlap(x, &ed->box, margin))
            continue;
        for (int k = 0; k <= ed->n; k++)
            if (cb_seg3_meets_box(ed->samples[k], ed->samples[k], x->lo, x->hi, margin))
                return 0;
    }
    return 1;
}

/* Refusals of face pair (i, j) of bodies a and b whose uncertified region (its parameter boxes)
 * lies outside face i's or face j's trimmed domain (box_outside_face): no curve of the two faces
 * lies in it, and everything else of the pair is certified or within tolerance. Each leaves
 * r->failed for a region record (CB_SSI_REGION_OUTSIDE_FACE, the side's 3D box) and is counted
 * in r->pairs_outside_face; r->status is that of the first refusal left. CB_ERR_NOMEM. */
static cb_status drop_outside(cb_ssi_result_t r, const cb_topo_body *a, const cb_topo_body *b,
                              int i, int j, double tol)
{
    cb_face fc[2];
    int have[2] = {0, 0}; /* 0 not prepared yet, 1 prepared, -1 could not be */
    const cb_topo_body *body[2] = {a, b};
    const int face[2] = {i, j};
    cb_status st = CB_OK;
    slong kept = 0;
    for (slong k = 0; k < r->n_failed; k++) {
        cb_ssi_failure f = r->failed[k];
        int out = 0;
        cb_aabb x;
        for (int s = 0; s < 2 && f.has_box && !out && st == CB_OK; s++) {
            if (have[s] == 0) {
                cb_error e;
                double ft = body[s]->tol > 0 ? body[s]->tol : tol;
                cb_status fs = cb_face_init(fc + s, body[s], face[s], ft, &e);
                have[s] = fs == CB_OK ? 1 : -1;
                if (fs == CB_ERR_NOMEM)
                    st = CB_ERR_NOMEM;
            }
            out = have[s] > 0 && box_outside_face(&x, fc + s, s ? f.box_b : f.box_a, tol);
        }
        if (!out) {
            r->failed[kept++] = f;
            continue;
        }
        cb_ssi_region *g = _cb_ssi_add_region(r, CB_SSI_REGION_OUTSIDE_FACE, f.face_a, f.face_b,
                                              f.patch_a, f.patch_b, 0);
        if (!g) {
            st = CB_ERR_NOMEM;
            r->failed[kept++] = f;
            continue;
        }
        memcpy(g->box_a, f.box_a, sizeof g->box_a);
        memcpy(g->box_b, f.box_b, sizeof g->box_b);
        memcpy(g->lo, x.lo, sizeof g->lo);
        memcpy(g->hi, x.hi, sizeof g->hi);
        r->pairs_outside_face++;
    }
    r->n_failed = kept;
    if (r->status != CB_ERR_NOMEM)
        r->status = kept > 0 ? r->failed[0].status : CB_OK;
    for (int s = 0; s < 2; s++)
        if (have[s] > 0)
            cb_face_clear(fc + s);
    return st;
}

typedef struct {
    fpair *f;
    const cb_topo_body *a, *b;
    const cb_ssi_surface *sa, *sb;
    const face_conv *ca, *cb; /* conversions of a's and b's faces */
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
        if (F->st == CB_OK && c->ca[F->i].on)
            reparam(F->r, 0, c->ca + F->i);
        if (F->st == CB_OK && c->cb[F->j].on)
            reparam(F->r, 1, c->cb + F->j);
        if (F->st == CB_OK && c->ca[F->i].sub)
            renumber(F->r, 0, c->ca + F->i);
        if (F->st == CB_OK && c->cb[F->j].sub)
            renumber(F->r, 1, c->cb + F->j);
        if (F->st == CB_OK && F->r->n_failed > 0 &&
            drop_outside(F->r, c->a, c->b, F->i, F->j, c->o.tol) != CB_OK)
            F->st = cb_error_set(&F->err, CB_ERR_NOMEM, "ssi: out of memory checking refused "
                                 "regions against the trimmed faces");
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
    face_conv *ca = calloc((size_t)a->n_faces + 1, sizeof(face_conv));
    face_conv *cb = calloc((size_t)b->n_faces + 1, sizeof(face_conv));
    for (int i = 0; ca && i < a->n_faces; i++)
        cb_nurbs_surface_init(ca[i].net);
    for (int j = 0; cb && j < b->n_faces; j++)
        cb_nurbs_surface_init(cb[j].net);
    slong nf = 0, af = 64;
    fpair *fp = malloc((size_t)af * sizeof(fpair));
    cb_status st = sa && sb && xa && xb && oka && okb && ca && cb && fp ? CB_OK : CB_ERR_NOMEM;
    if (st == CB_OK)
        st = body_faces(sa, ca, xa, oka, a);
    if (st == CB_OK)
        st = body_faces(sb, cb, xb, okb, b);
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
        fctx fc = {fp, a, b, sa, sb, ca, cb, o, 0, 0};
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
    for (int i = 0; ca && i < a->n_faces; i++)
        cb_nurbs_surface_clear(ca[i].net);
    for (int j = 0; cb && j < b->n_faces; j++)
        cb_nurbs_surface_clear(cb[j].net);
    free(ca);
    free(cb);
    return st;
}
