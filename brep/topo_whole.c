/* Faces that cover their whole closed surface, and faces whose loops wind round a period of
 * their surface without a seam (bands, caps round a pole): the seams and poles that bound
 * them (see cb_topo_close_faces in topo.h). */
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "brep/topo.h"

/* Samples along a boundary line or a seam when testing it. */
enum { N_TEST = 17 };

/* The point of the surface at parameter w along direction `along` (0: u) with the other
 * parameter fixed at x. */
static void eval_line(double p[3], const cb_topo_inverter *inv, int along, double w, double x)
{
    if (along == 0)
        cb_topo_inverter_eval(p, inv, w, x);
    else
        cb_topo_inverter_eval(p, inv, x, w);
}

/* Whether the line of the surface with parameter 1 - along fixed at x collapses to a point
 * (a pole, an apex): its samples over the domain in direction `along` lie within tol of its
 * first. */
static int collapses(const cb_topo_inverter *inv, int along, double x, double tol)
{
    double lo = inv->box[2 * along], hi = inv->box[2 * along + 1], p0[3], p[3];
    if (!isfinite(lo) || !isfinite(hi) || !isfinite(x))
        return 0;
    eval_line(p0, inv, along, lo, x);
    for (int k = 1; k < N_TEST; k++) {
        eval_line(p, inv, along, lo + (hi - lo) * k / (N_TEST - 1), x);
        if (cb_vec3_dist(p, p0) > tol)
            return 0;
    }
    return 1;
}

/* c = the conic o + r1 cos t x + r2 sin t y (a circle when r1 = r2), x and y orthonormal. */
static cb_status conic(cb_topo_curve *c, const double o[3], const double x[3], const double y[3],
                       double r1, double r2, cb_error *err)
{
    double z[3];
    cb_vec3_cross(z, x, y);
    c->kind = r1 == r2 ? CB_CURVE_CIRCLE : CB_CURVE_ELLIPSE;
    c->r1 = r1;
    c->r2 = r2;
    return cb_frame_make(&c->frame, o, z, x, err);
}

/* The line of surface s running in direction `along` (0: u) with the other parameter fixed at
 * x, as an exact curve c parameterised by the surface parameter it runs along (so the curve
 * point at t is S(t, x) or S(x, t)): lines of the analytic surfaces at any x (rulings of
 * cylinders and cones, meridians of spheres, ellipsoids and tori, parallels of tori), a
 * revolution's parallels at any v and its profile (the line at u = 0), an extrusion's rulings
 * at any u, a B-spline's lines at
 * the start of its domain (x = box[2 (1 - along)]: its boundary row of control points; an
 * interior one would need knot insertion). Returns CB_ERR_UNSUPPORTED for a surface kind,
 * direction or x without such a curve here. */
static cb_status iso_curve(cb_topo_curve *c, const cb_topo_inverter *inv, int along, double x,
                           cb_error *err)
{
    const cb_topo_surface *s = inv->s;
    if (s->kind == CB_SURFACE_ANALYTIC) {
        const cb_analytic_surface *a = &s->analytic;
        const cb_frame *f = &a->frame;
        /* d: the direction of angle x in the frame's x'y' plane */
        double o[3], d[3];
        for (int i = 0; i < 3; i++)
            d[i] = cos(x) * f->x[i] + sin(x) * f->y[i];
        if ((a->kind == CB_ANALYTIC_SPHERE || a->kind == CB_ANALYTIC_ELLIPSOID) && along == 1) {
            /* The meridian at u = x: cos v m + sin v r3 z' with m = (r1 cos x, r2 sin x, 0). */
            int sphere = a->kind == CB_ANALYTIC_SPHERE;
            double r2 = sphere ? a->r1 : a->r2, r3 = sphere ? a->r1 : a->r3, m[3];
            for (int i = 0; i < 3; i++)
                m[i] = a->r1 * cos(x) * f->x[i] + r2 * sin(x) * f->y[i];
            double r = cb_vec3_normalize(m);
            return conic(c, f->o, m, f->z, r, r3, err);
        }
        if (a->kind == CB_ANALYTIC_TORUS && along == 1) {
            /* The meridian at u = x: the circle of radius r about R d in the plane of d, z'. */
            for (int i = 0; i < 3; i++)
                o[i] = f->o[i] + a->r1 * d[i];
            return conic(c, o, d, f->z, a->r2, a->r2, err);
        }
        if (a->kind == CB_ANALYTIC_TORUS && along == 0) {
            /* The parallel at v = x: radius R + r cos x at height r sin x. */
            double r = a->r1 + a->r2 * cos(x);
            for (int i = 0; i < 3; i++)
                o[i] = f->o[i] + a->r2 * sin(x) * f->z[i];
            return conic(c, o, f->x, f->y, r, r, err);
        }
        if ((a->kind == CB_ANALYTIC_CYLINDER || a->kind == CB_ANALYTIC_CONE) && along == 1) {
            /* The ruling at u = x: r d + v (tan(a) d + z'), a line whose speed is the length
             * of that direction (1 for the cylinder). */
            double slope = a->kind == CB_ANALYTIC_CONE ? tan(a->angle) : 0, dir[3];
            for (int i = 0; i < 3; i++) {
                o[i] = f->o[i] + a->r1 * d[i];
                dir[i] = slope * d[i] + f->z[i];
            }
            c->kind = CB_CURVE_LINE;
            c->r1 = cb_vec3_norm(dir);
            return cb_frame_make(&c->frame, o, dir, NULL, err);
        }
    } else if (s->kind == CB_SURFACE_NURBS && x == inv->box[2 * (1 - along)]) {
        /* The first row (along v) or column (along u) of control points: exact, as the knots
         * are clamped. */
        const cb_nurbs_surface_struct *n = s->nurbs;
        int deg = along ? n->deg_v : n->deg_u, cnt = along ? n->n_v : n->n_u;
        cb_status st = cb_nurbs_curve_alloc(c->nurbs, deg, cnt, err);
        if (st)
            return st;
        memcpy(c->nurbs->knots, along ? n->knots_v : n->knots_u,
               (size_t)(cnt + deg + 1) * sizeof(double));
        for (int k = 0; k < cnt; k++)
            memcpy(c->nurbs->cw + 4 * k, cb_nurbs_surface_cw(n, along ? 0 : k, along ? k : 0),
                   4 * sizeof(double));
        c->kind = CB_CURVE_NURBS;
        return CB_OK;
    } else if (s->kind == CB_SURFACE_REVOLUTION) {
        if (along == 1 && x == inv->box[0]) {
            /* The profile itself is the line at u = 0. */
            *c = s->profile;
            cb_nurbs_curve_init(c->nurbs);
            if (s->profile.kind == CB_CURVE_NURBS)
                return cb_nurbs_curve_set(c->nurbs, s->profile.nurbs, err);
            return CB_OK;
        }
        if (along == 1)
            return cb_error_set(err, CB_ERR_UNSUPPORTED, "no v line of a revolution at %g", x);
        /* The parallel through the profile's point at v = x: turned about the axis. */
        double p[3], foot[3], xd[3], y[3];
        cb_topo_curve_eval(p, &s->profile, x);
        const double *z = s->frame.z;
        double along_axis = 0;
        for (int i = 0; i < 3; i++)
            along_axis += (p[i] - s->frame.o[i]) * z[i];
        for (int i = 0; i < 3; i++) {
            foot[i] = s->frame.o[i] + along_axis * z[i];
            xd[i] = p[i] - foot[i];
        }
        double r = cb_vec3_normalize(xd);
        if (!(r > 0))
            return cb_error_set(err, CB_ERR_UNSUPPORTED, "the profile meets the axis there");
        cb_vec3_cross(y, z, xd);
        return conic(c, foot, xd, y, r, r, err);
    } else if (s->kind == CB_SURFACE_EXTRUSION && along == 1) {
        /* The ruling at u = x: profile(x) + v dir, a line of speed |dir|. */
        double o[3];
        cb_topo_curve_eval(o, &s->profile, x);
        c->kind = CB_CURVE_LINE;
        c->r1 = cb_vec3_norm(s->dir);
        return cb_frame_make(&c->frame, o, s->dir, NULL, err);
    }
    return cb_error_set(err, CB_ERR_UNSUPPORTED, "no %s line of a %s surface at %g",
                        along ? "v" : "u", cb_topo_surface_type_name(s), x);
}

/* Appends the iso_curve in direction `along` at x, checked to lie on the surface within tol
 * over the range t (t[0] < t[1], finite). Returns its index or -1 (err set). */
static int seam_curve(cb_topo_body *b, const cb_topo_inverter *inv, int along, double x,
                      const double t[2], double tol, cb_error *err)
{
    int ci = cb_topo_body_add_curve(b);
    if (ci < 0) {
        cb_error_set(err, CB_ERR_NOMEM, "out of memory");
        return -1;
    }
    if (iso_curve(&b->curves[ci], inv, along, x, err))
        return -1;
    double worst = 0;
    for (int k = 0; k < N_TEST; k++) {
        double w = t[0] + (t[1] - t[0]) * k / (N_TEST - 1), p[3], q[3];
        cb_topo_curve_eval(p, &b->curves[ci], w);
        eval_line(q, inv, along, w, x);
        worst = fmax(worst, cb_vec3_dist(p, q));
    }
    if (!(worst <= tol)) {
        cb_error_set(err, CB_ERR_NUMERIC, "its seam lies %g off the surface", worst);
        return -1;
    }
    return ci;
}

/* The edge on curve ci (seam_curve, range t) from vertex v0 to v1: edge e rewritten, or a new
 * one when e < 0. Returns its index or -1 (err set). */
static int seam_edge(cb_topo_body *b, int ci, const double t[2], int v0, int v1, int e,
                     double tol, cb_error *err)
{
    if (e >= 0) {
        tol = fmax(tol, b->edges[e].tol);
    } else if ((e = cb_topo_body_add_edge(b)) < 0) {
        cb_error_set(err, CB_ERR_NOMEM, "out of memory");
        return -1;
    }
    b->edges[e] = (cb_topo_edge){ci, t[0], t[1], 1, {v0, v1}, tol};
    return e;
}

/* Vertex k moved to S(u, v), or a new one there when k < 0. */
static int vertex_at(cb_topo_body *b, const cb_topo_inverter *inv, double u, double v, int k,
                     cb_error *err)
{
    if (k < 0)
        k = cb_topo_body_add_vertex(b);
    if (k < 0)
        cb_error_set(err, CB_ERR_NOMEM, "out of memory");
    else
        cb_topo_inverter_eval(b->vertices[k].p, inv, u, v);
    return k;
}

/* Appends the pcurve of a seam coedge: the line of the (u, v) plane running along direction
 * `along` (0: u) with the other parameter at x, parameterised by the parameter it runs along
 * (as its edge, iso_curve). Returns its index or -1. */
static int seam_pcurve(cb_topo_body *b, int along, double x, cb_error *err)
{
    int k = cb_topo_body_add_pcurve(b);
    if (k < 0) {
        cb_error_set(err, CB_ERR_NOMEM, "out of memory");
        return -1;
    }
    cb_topo_curve *c = &b->pcurves[k];
    double o[3] = {0, 0, 0}, dir[3] = {0, 0, 0};
    o[1 - along] = x;
    dir[along] = 1;
    c->kind = CB_CURVE_LINE;
    c->r1 = 1;
    return cb_frame_make(&c->frame, o, dir, NULL, err) ? -1 : k;
}

/* Whether face f is bounded by two seams alone, each used twice by its one loop and by nothing
 * else, through one vertex used by nothing else (a torus written as one face, as Open
 * CASCADE writes it). Then edge[0], edge[1] and *vertex are those seams and their vertex. */
static int seam_torus(const cb_topo_body *b, int f, int edge[2], int *vertex)
{
    const cb_topo_face *fa = &b->faces[f];
    if (fa->count != 1 || b->loops[fa->first].count != 4)
        return 0;
    const cb_topo_coedge *c = &b->coedges[b->loops[fa->first].first];
    edge[0] = c[0].edge;
    edge[1] = c[1].edge;
    if (c[2].edge != edge[0] || c[3].edge != edge[1] || edge[0] == edge[1] ||
        c[0].sense == c[2].sense || c[1].sense == c[3].sense)
        return 0;
    *vertex = b->edges[edge[0]].v[0];
    for (int k = 0; k < 2; k++)
        if (b->edges[edge[k]].v[0] != *vertex || b->edges[edge[k]].v[1] != *vertex)
            return 0;
    int uses = 0;
    for (int k = 0; k < b->n_coedges; k++)
        uses += b->coedges[k].edge == edge[0] || b->coedges[k].edge == edge[1];
    for (int e = 0; e < b->n_edges && uses == 4; e++)
        if (e != edge[0] && e != edge[1] &&
            (b->edges[e].v[0] == *vertex || b->edges[e].v[1] == *vertex))
            uses = 0;
    return uses == 4;
}

/* Gives face f the seams and poles of its surface's domain: f has no loop, or (torus) is
 * bounded by the seams seam_torus finds, whose entities are then rewritten in place. Returns 1
 * when it did, 0 when the surface does not close that way (the face is left as it is), -1 on
 * error. */
static int close_face(cb_topo_body *b, int f, double tol, cb_error *err)
{
    int old_edge[2] = {-1, -1}, old_vertex = -1, old_loop = -1;
    if (b->faces[f].count) {
        if (!seam_torus(b, f, old_edge, &old_vertex))
            return 0;
        old_loop = b->faces[f].first;
    }
    cb_topo_inverter inv;
    if (cb_topo_inverter_init(&inv, &b->surfaces[b->faces[f].surface], tol, err))
        return -1;
    const double *box = inv.box;
    /* per coedge: edge, sense, the direction its edge runs along, the other parameter */
    int es[4][3], n = 0, done = 0;
    double at[4];
    if (inv.period[0] > 0 && inv.period[1] > 0) {
        /* A torus: the lines at u0 and v0 through one vertex; the loop runs round the domain
         * counter-clockwise in (u, v) (bottom, right, top, left) when the face's normal is the
         * surface's, clockwise otherwise. */
        /* The curves first: a face rewritten in place changes only once both are found. */
        const double tu[2] = {box[0], box[1]}, tv[2] = {box[2], box[3]};
        int cu = seam_curve(b, &inv, 0, box[2], tu, tol, err); /* along u, at v0 */
        int cv = cu < 0 ? -1 : seam_curve(b, &inv, 1, box[0], tv, tol, err); /* along v, at u0 */
        int v = cv < 0 ? -1 : vertex_at(b, &inv, box[0], box[2], old_vertex, err);
        int su = v < 0 ? -1 : seam_edge(b, cu, tu, v, v, old_edge[0], tol, err);
        int sv = su < 0 ? -1 : seam_edge(b, cv, tv, v, v, old_edge[1], tol, err);
        if (sv < 0)
            goto fail;
        double u0 = box[0], u1 = u0 + inv.period[0], v0 = box[2], v1 = v0 + inv.period[1];
        if (b->faces[f].same_sense) {
            /* bottom, right, top, left */
            const int l[4][3] = {{su, 1, 0}, {sv, 1, 1}, {su, 0, 0}, {sv, 0, 1}};
            const double x[4] = {v0, u1, v1, u0};
            memcpy(es, l, sizeof l);
            memcpy(at, x, sizeof x);
        } else {
            /* left, top, right, bottom */
            const int l[4][3] = {{sv, 1, 1}, {su, 1, 0}, {sv, 0, 1}, {su, 0, 0}};
            const double x[4] = {u0, v1, u1, v0};
            memcpy(es, l, sizeof l);
            memcpy(at, x, sizeof x);
        }
        n = 4;
    } else {
        /* A sphere: closed in one direction, its two ends in the other collapsed to poles; the
         * seam runs from pole to pole along the other direction. */
        int closed = inv.period[0] > 0 ? 0 : inv.period[1] > 0 ? 1 : -1, along = 1 - closed;
        if (closed < 0 || old_loop >= 0 || !collapses(&inv, closed, box[2 * along], tol) ||
            !collapses(&inv, closed, box[2 * along + 1], tol)) {
            cb_topo_inverter_clear(&inv);
            return 0;
        }
        double uv0[2], uv1[2];
        uv0[closed] = uv1[closed] = box[2 * closed];
        uv0[along] = box[2 * along];
        uv1[along] = box[2 * along + 1];
        const double t[2] = {box[2 * along], box[2 * along + 1]};
        int ci = seam_curve(b, &inv, along, box[2 * closed], t, tol, err);
        int p0 = ci < 0 ? -1 : vertex_at(b, &inv, uv0[0], uv0[1], -1, err);
        int p1 = p0 < 0 ? -1 : vertex_at(b, &inv, uv1[0], uv1[1], -1, err);
        int e = p1 < 0 ? -1 : seam_edge(b, ci, t, p0, p1, -1, tol, err);
        if (e < 0)
            goto fail;
        /* The face lies left of the coedge running along the seam in (u, v) when its normal
         * is the surface's: that coedge at the far copy of the seam when the closed direction
         * is u, at the near one when it is v. */
        double near = box[2 * closed], far = near + inv.period[closed];
        int up_far = (closed == 0) == (b->faces[f].same_sense != 0);
        const int l[2][3] = {{e, 1, along}, {e, 0, along}};
        memcpy(es, l, sizeof l);
        at[0] = up_far ? far : near;
        at[1] = up_far ? near : far;
        n = 2;
    }
    int li = old_loop >= 0 ? old_loop : cb_topo_body_add_loop(b);
    if (li < 0) {
        cb_error_set(err, CB_ERR_NOMEM, "out of memory");
        goto fail;
    }
    int first = old_loop >= 0 ? b->loops[li].first : b->n_coedges;
    b->loops[li] = (cb_topo_loop){first, n, 1, f};
    for (int k = 0; k < n; k++) {
        int c = old_loop >= 0 ? first + k : cb_topo_body_add_coedge(b);
        if (c < 0) {
            cb_error_set(err, CB_ERR_NOMEM, "out of memory");
            goto fail;
        }
        int pc = seam_pcurve(b, es[k][2], at[k], err);
        if (pc < 0)
            goto fail;
        b->coedges[c] = (cb_topo_coedge){es[k][0], es[k][1], pc, li};
    }
    b->faces[f].first = li;
    b->faces[f].count = 1;
    done = 1;
fail:
    cb_topo_inverter_clear(&inv);
    return done ? 1 : -1;
}

/* ---------------------------------------------------------------- bands -------------------- */

/* Steps per edge when following a loop on its surface: a full circle edge then turns by 22.5
 * degrees a step, far below the half period at which the lift of a step becomes ambiguous. */
enum { N_WALK = 16 };

/* The point at fraction s of coedge c in its traversal order; returns its curve parameter. */
static double coedge_point(double p[3], const cb_topo_body *b, int c, double s)
{
    const cb_topo_edge *ed = &b->edges[b->coedges[c].edge];
    int forward = (b->coedges[c].sense != 0) == (ed->same_sense != 0);
    double t = forward ? ed->t0 + (ed->t1 - ed->t0) * s : ed->t1 - (ed->t1 - ed->t0) * s;
    cb_topo_curve_eval(p, &b->curves[ed->curve], t);
    return t;
}

/* Loop l followed on the surface in N_WALK steps per coedge, each point inverted next to the
 * previous one, so the (u, v) run on continuously across the periods: uv[2 k] is the start of
 * the loop's coedge k, uv[2 count] the loop's end (its start lifted by the periods it winds
 * round). Returns 0 when a step jumps by more than a quarter period: the loop runs through a
 * pole or an apex (where the periodic parameter turns at once: a half cone bounded by two
 * rulings), and its winding is not told by the walk. */
static int follow_loop(double *uv, const cb_topo_body *b, int l, const cb_topo_inverter *inv)
{
    const cb_topo_loop *lp = &b->loops[l];
    double p[3], q[2];
    coedge_point(p, b, lp->first, 0);
    cb_topo_inverter_invert(q, inv, p, NULL);
    uv[0] = q[0];
    uv[1] = q[1];
    for (int k = 0; k < lp->count; k++) {
        for (int s = 1; s <= N_WALK; s++) {
            double g[2] = {q[0], q[1]};
            coedge_point(p, b, lp->first + k, (double)s / N_WALK);
            cb_topo_inverter_invert(q, inv, p, g);
            for (int i = 0; i < 2; i++)
                if (inv->period[i] > 0 && fabs(q[i] - g[i]) > 0.25 * inv->period[i])
                    return 0;
        }
        uv[2 * k + 2] = q[0];
        uv[2 * k + 3] = q[1];
    }
    return 1;
}

/* The vertex coedge c starts at. */
static int start_vertex(const cb_topo_body *b, int c)
{
    const cb_topo_coedge *ce = &b->coedges[c];
    return b->edges[ce->edge].v[ce->sense ? 0 : 1];
}

/* Rewrites the coedges in loop order from one list per loop: loop l gets the coedges
 * list[start[l] .. start[l + 1]) (their loop field set here). A loop whose list is empty is
 * removed: the loops after it move down one place and the faces' ranges follow (a face's loops
 * stay contiguous). Coedges in no loop are dropped; nothing else refers to coedge indices. */
static cb_status relay(cb_topo_body *b, const cb_topo_coedge *list, const int *start,
                       cb_error *err)
{
    int total = start[b->n_loops];
    while (b->n_coedges < total)
        if (cb_topo_body_add_coedge(b) < 0)
            return cb_error_set(err, CB_ERR_NOMEM, "out of memory");
    int *to = malloc((size_t)(b->n_loops + 1) * sizeof *to), n = 0;
    if (!to)
        return cb_error_set(err, CB_ERR_NOMEM, "out of memory");
    for (int l = 0; l < b->n_loops; l++) {
        to[l] = start[l + 1] > start[l] ? n : -1;
        if (to[l] < 0)
            continue;
        cb_topo_loop lp = b->loops[l];
        lp.first = start[l];
        lp.count = start[l + 1] - start[l];
        for (int k = lp.first; k < lp.first + lp.count; k++) {
            b->coedges[k] = list[k];
            b->coedges[k].loop = n;
        }
        b->loops[n++] = lp;
    }
    for (int f = 0; f < b->n_faces; f++) {
        cb_topo_face *fa = &b->faces[f];
        int first = -1, count = 0;
        for (int l = fa->first; l < fa->first + fa->count; l++)
            if (to[l] >= 0) {
                first = first < 0 ? to[l] : first;
                count++;
            }
        fa->first = first < 0 ? 0 : first;
        fa->count = count;
    }
    free(to);
    b->n_coedges = total;
    b->n_loops = n;
    return CB_OK;
}

/* Splits edge e at curve parameter t (strictly inside its range) at a new vertex there: e keeps
 * the part [t0, t], a new edge takes [t, t1], and every coedge of e, in whatever face, becomes
 * the two coedges of the parts in its order, without a pcurve (they are computed later; the
 * part of a pcurve a half uses is found anew anyway). Returns the new vertex or -1 (err set). */
static int split_edge(cb_topo_body *b, int e, double t, cb_error *err)
{
    int v = cb_topo_body_add_vertex(b), e2 = v < 0 ? -1 : cb_topo_body_add_edge(b);
    if (e2 < 0) {
        cb_error_set(err, CB_ERR_NOMEM, "out of memory");
        return -1;
    }
    cb_topo_edge *lo = &b->edges[e], *hi = &b->edges[e2];
    cb_topo_curve_eval(b->vertices[v].p, &b->curves[lo->curve], t);
    *hi = *lo;
    lo->t1 = t;
    hi->t0 = t;
    /* Along the edge (v[0] to v[1]) the part [t0, t] comes first when the curve runs that
     * way. */
    int first = lo->same_sense ? e : e2, second = lo->same_sense ? e2 : e;
    b->edges[first].v[1] = v;
    b->edges[second].v[0] = v;
    int uses = 0;
    for (int c = 0; c < b->n_coedges; c++)
        uses += b->coedges[c].edge == e;
    int *start = malloc((size_t)(b->n_loops + 1) * sizeof *start);
    cb_topo_coedge *list = malloc((size_t)(b->n_coedges + uses + 1) * sizeof *list);
    cb_status st = start && list ? CB_OK : cb_error_set(err, CB_ERR_NOMEM, "out of memory");
    int n = 0;
    for (int l = 0; l < b->n_loops && !st; l++) {
        start[l] = n;
        const cb_topo_loop *lp = &b->loops[l];
        for (int k = lp->first; k < lp->first + lp->count; k++) {
            cb_topo_coedge ce = b->coedges[k];
            if (ce.edge != e) {
                list[n++] = ce;
                continue;
            }
            ce.pcurve = -1;
            ce.edge = ce.sense ? first : second;
            list[n++] = ce;
            ce.edge = ce.sense ? second : first;
            list[n++] = ce;
        }
    }
    if (!st) {
        start[b->n_loops] = n;
        st = relay(b, list, start, err);
    }
    free(start);
    free(list);
    return st ? -1 : v;
}

/* Where coedge c crosses the line of its surface at parameter x (+ whole periods) in
 * direction w, its start at (u, v) uv0 (lifted as follow_loop lifts it): the crossing
 * between two N_WALK steps is bisected on the edge curve. Returns the edge curve parameter
 * there, or NAN when c does not cross. */
static double crossing(const cb_topo_body *b, int c, const cb_topo_inverter *inv,
                       const double uv0[2], int w, double x)
{
    double P = inv->period[w], p[3], q[2] = {uv0[0], uv0[1]};
    for (int s = 1; s <= N_WALK; s++) {
        double a[2] = {q[0], q[1]};
        coedge_point(p, b, c, (double)s / N_WALK);
        cb_topo_inverter_invert(q, inv, p, a);
        double ka = floor((a[w] - x) / P), kq = floor((q[w] - x) / P);
        if (ka == kq)
            continue;
        double target = x + P * fmax(ka, kq), lo = (double)(s - 1) / N_WALK,
               hi = (double)s / N_WALK, t = NAN;
        int below = a[w] < target;
        for (int it = 0; it < 60; it++) {
            double mid = 0.5 * (lo + hi), m[2];
            t = coedge_point(p, b, c, mid);
            cb_topo_inverter_invert(m, inv, p, a);
            if ((m[w] < target) == below) {
                lo = mid;
                a[0] = m[0];
                a[1] = m[1];
            } else {
                hi = mid;
            }
        }
        return t;
    }
    return NAN;
}

/* The coedge of loop l (followed: uv) that starts at a vertex on the line of the surface at
 * parameter x in direction w (within tol), or -1. */
static int vertex_on_line(const cb_topo_body *b, int l, const double *uv,
                          const cb_topo_inverter *inv, int w, double x, double tol)
{
    const cb_topo_loop *lp = &b->loops[l];
    for (int k = 0; k < lp->count; k++) {
        double at[2] = {uv[2 * k], uv[2 * k + 1]}, p[3];
        at[w] = x;
        cb_topo_inverter_eval(p, inv, at[0], at[1]);
        if (cb_vec3_dist(p, b->vertices[start_vertex(b, lp->first + k)].p) <= tol)
            return lp->first + k;
    }
    return -1;
}

/* The parameter in direction 1 - w at which the surface collapses to a point (a pole, an apex)
 * on side `side` (+1: above) of the loop followed as uv, or NAN when it does not: the apex of
 * a cone, else the end of the domain on that side. */
static double pole_at(const cb_topo_inverter *inv, const double *uv, int w, int side, double tol)
{
    int across = 1 - w;
    const cb_topo_surface *s = inv->s;
    double x = inv->box[2 * across + (side > 0)];
    if (s->kind == CB_SURFACE_ANALYTIC && s->analytic.kind == CB_ANALYTIC_CONE)
        x = -s->analytic.r1 / tan(s->analytic.angle);
    if (!isfinite(x) || (x - uv[across]) * side <= 0 || !collapses(inv, w, x, tol))
        return NAN;
    return x;
}

/* One step of giving face f a seam when it is a band: its loops wind round the period of its
 * surface in one direction w once each, two of them in opposite senses, or one with the
 * surface collapsing to a pole or apex beyond it on the face's side; every other loop winds
 * round none, and no edge is used twice by the face (it has no seam). The seam is the line
 * of the surface at w = x0 (iso_curve) from the first winding loop to the second or to the
 * pole (a new vertex), x0 the start of the domain in w. A loop with no
 * vertex on that line first gets one: its edge that crosses the line is split there
 * (split_edge; its other face follows), and the step returns 2 to be run again. Otherwise
 * the loops become one: [first loop from its vertex on the line, seam, second loop from its
 * vertex (or the jump along the pole line), seam reversed], the seam running across the face
 * from the first loop, which is the one the face lies beyond in +(1 - w) (to the left of the
 * loop in (u, v) when same_sense is 1; for a lone loop the side the pole is on); returns 1.
 * The loop's coedges lose their pcurves (computed later, joined to the seam's); the two seam
 * coedges get the exact lines of the seam's two copies, a period apart. Returns 0 (nothing
 * changed) when f is no band or has no exact seam line here, -1 on error (CB_ERR_NOMEM). */
static int band_step(cb_topo_body *b, int f, double tol, cb_error *err)
{
    const cb_topo_face *fa = &b->faces[f];
    const cb_topo_surface *s = &b->surfaces[fa->surface];
    /* A band needs two loops; one loop can wind round a period only where the surface ends
     * in a pole (analytic and turned surfaces here: a B-spline face of one loop is too common
     * to follow on every read for the few that are caps). */
    int may_pole = s->kind == CB_SURFACE_REVOLUTION ||
                   (s->kind == CB_SURFACE_ANALYTIC && (s->analytic.kind == CB_ANALYTIC_CONE ||
                                                       s->analytic.kind == CB_ANALYTIC_SPHERE ||
                                                       s->analytic.kind == CB_ANALYTIC_ELLIPSOID));
    if (fa->count < (may_pole ? 1 : 2) ||
        (s->kind == CB_SURFACE_ANALYTIC && s->analytic.kind == CB_ANALYTIC_PLANE))
        return 0;
    /* No edge used twice by the face. */
    for (int l = fa->first; l < fa->first + fa->count; l++)
        for (int c = b->loops[l].first; c < b->loops[l].first + b->loops[l].count; c++)
            for (int l2 = fa->first; l2 < fa->first + fa->count; l2++)
                for (int d = b->loops[l2].first; d < b->loops[l2].first + b->loops[l2].count; d++)
                    if (d != c && b->coedges[d].edge == b->coedges[c].edge)
                        return 0;
    cb_topo_inverter inv;
    cb_error local;
    if (cb_topo_inverter_init(&inv, s, tol, &local))
        return local.status == CB_ERR_NOMEM ? (cb_error_set(err, local.status, "%s", local.msg), -1)
                                            : 0;
    if (!(inv.period[0] > 0) && !(inv.period[1] > 0)) {
        cb_topo_inverter_clear(&inv);
        return 0;
    }
    int r = 0, n_pts = 0;
    for (int l = fa->first; l < fa->first + fa->count; l++)
        n_pts += 2 * b->loops[l].count + 2;
    double *uv = malloc((size_t)n_pts * sizeof *uv);
    int *at = malloc((size_t)(fa->count + 1) * sizeof *at);
    if (!uv || !at) {
        cb_error_set(err, CB_ERR_NOMEM, "out of memory");
        r = -1;
        goto done;
    }
    /* The winding of each loop round each period. */
    int wind_loop[2] = {-1, -1}, wind[2] = {0, 0}, w = -1;
    for (int k = 0, off = 0; k < fa->count; k++) {
        int l = fa->first + k, n = b->loops[l].count;
        at[k] = off;
        if (!follow_loop(uv + off, b, l, &inv))
            goto done;
        for (int i = 0; i < 2; i++) {
            double P = inv.period[i], turns = P > 0 ? (uv[off + 2 * n + i] - uv[off + i]) / P : 0;
            if (fabs(turns - round(turns)) > 0.25)
                goto done; /* the walk lost its way: not decided here */
            int m = (int)round(turns);
            if (m == 0)
                continue;
            if (abs(m) != 1 || (w >= 0 && w != i) || wind_loop[1] >= 0 ||
                (wind_loop[0] >= 0 && wind_loop[0] == l))
                goto done;
            w = i;
            wind[wind_loop[0] < 0 ? 0 : 1] = m;
            wind_loop[wind_loop[0] < 0 ? 0 : 1] = l;
        }
        off += 2 * n + 2;
    }
    if (wind_loop[0] < 0 || (wind_loop[1] >= 0 && wind[0] != -wind[1]))
        goto done;
    int across = 1 - w;
    /* The side (+1: +across) on which the face lies beyond a loop winding once round the
     * period, wind[0]: to the left of it in (u, v) when same_sense is 1. */
    int side = wind[0] * (fa->same_sense ? 1 : -1) * (w == 0 ? 1 : -1);
    double pole = NAN;
    if (wind_loop[1] < 0 &&
        isnan(pole = pole_at(&inv, uv + at[wind_loop[0] - fa->first], w, side, tol)))
        goto done;
    /* A: the loop the face lies beyond in +across, B the other one; a lone loop is A, the
     * face beyond it ending at the pole. */
    int first = wind_loop[1] < 0 || side > 0 ? 0 : 1;
    int la = wind_loop[first], lb = wind_loop[1] < 0 ? -1 : wind_loop[1 - first], wa = wind[first];
    const double *uva = uv + at[la - fa->first], *uvb = lb < 0 ? NULL : uv + at[lb - fa->first];
    /* The seam at the start of the domain in w, where Open CASCADE's FixMissingSeam puts it
     * and brep/prim.h lays out its faces: the loop then spans the first period, as the
     * Booleans' cut windows expect (OCC2368.stp against moved copies, bench_parts: seams at
     * a vertex of each face, u = 4.71 on its face 1, left runs refused that pass so), and a
     * B-spline's line is exact there. */
    double x0 = inv.box[2 * w];
    int ca = vertex_on_line(b, la, uva, &inv, w, x0, tol);
    int cb = lb < 0 ? INT_MAX /* the pole: no vertex to find */
                    : vertex_on_line(b, lb, uvb, &inv, w, x0, tol);
    if (ca < 0 || cb < 0) {
        /* Give the loop a vertex on the line first. */
        int l = ca < 0 ? la : lb, c = -1;
        const double *u = ca < 0 ? uva : uvb;
        double t = NAN;
        for (int k = 0; k < b->loops[l].count && isnan(t); k++) {
            c = b->loops[l].first + k;
            t = crossing(b, c, &inv, u + 2 * k, w, x0);
        }
        const cb_topo_edge *ed = isnan(t) ? NULL : &b->edges[b->coedges[c].edge];
        double p[3];
        if (ed) {
            cb_topo_curve_eval(p, &b->curves[ed->curve], t);
            if (cb_vec3_dist(p, b->vertices[ed->v[0]].p) <= tol ||
                cb_vec3_dist(p, b->vertices[ed->v[1]].p) <= tol)
                ed = NULL; /* at a vertex after all, not found on the line within tol */
        }
        if (ed)
            r = split_edge(b, b->coedges[c].edge, t, err) < 0 ? -1 : 2;
        goto done;
    }
    /* The seam: the line at x0 from A's vertex across the face to B's. */
    double P = inv.period[w], x0w = x0;
    double a0 = uva[2 * (ca - b->loops[la].first) + across];
    double t[2] = {a0, lb < 0 ? pole : uvb[2 * (cb - b->loops[lb].first) + across]};
    double Pa = inv.period[across];
    if (Pa > 0 && lb >= 0)
        t[1] -= Pa * floor((t[1] - t[0]) / Pa);
    if (lb < 0 && side < 0) {
        t[0] = pole;
        t[1] = a0;
    }
    if (!(t[1] - t[0] > 0))
        goto done;
    int ci = seam_curve(b, &inv, across, x0w, t, tol, &local);
    if (ci < 0) {
        if (local.status == CB_ERR_NOMEM) {
            cb_error_set(err, local.status, "%s", local.msg);
            r = -1;
        }
        goto done;
    }
    double at_pole[2];
    at_pole[w] = x0w;
    at_pole[across] = pole;
    int va = start_vertex(b, ca),
        vb = lb >= 0 ? start_vertex(b, cb) : vertex_at(b, &inv, at_pole[0], at_pole[1], -1, err);
    int e = vb < 0 ? -1 : seam_edge(b, ci, t, va, vb, -1, tol, err);
    if (e >= 0) {
        /* From A's vertex to B's or the pole. The seam's ends are the surface points below
         * the loops' vertices: an edge farther from its faces than tol puts its vertex that
         * far from them, and the seam's tolerance takes the gap. */
        cb_topo_edge *se = &b->edges[e];
        se->same_sense = lb >= 0 || side > 0;
        double p0[3], p1[3];
        cb_topo_curve_eval(p0, &b->curves[ci], se->same_sense ? t[0] : t[1]);
        cb_topo_curve_eval(p1, &b->curves[ci], se->same_sense ? t[1] : t[0]);
        se->tol = fmax(se->tol, fmax(cb_vec3_dist(p0, b->vertices[va].p),
                                     cb_vec3_dist(p1, b->vertices[vb].p)));
    }
    /* A runs from x0w to x0w + P when it winds forward, back from x0w + P otherwise: the seam
     * coedge after A lies where A ends, the one after B where B ends (= A's start). */
    double a_end = x0w + (wa > 0 ? P : 0), b_end = x0w + (wa > 0 ? 0 : P);
    int pa = e < 0 ? -1 : seam_pcurve(b, across, a_end, err);
    int pb = pa < 0 ? -1 : seam_pcurve(b, across, b_end, err);
    if (pb < 0) {
        r = -1;
        goto done;
    }
    int *start = malloc((size_t)(b->n_loops + 1) * sizeof *start);
    cb_topo_coedge *list = malloc((size_t)(b->n_coedges + 3) * sizeof *list);
    cb_status st = start && list ? CB_OK : cb_error_set(err, CB_ERR_NOMEM, "out of memory");
    int n = 0;
    for (int l = 0; l < b->n_loops && !st; l++) {
        start[l] = n;
        const cb_topo_loop *lp = &b->loops[l];
        if (l == lb)
            continue;
        if (l != la) {
            memcpy(list + n, b->coedges + lp->first, (size_t)lp->count * sizeof *list);
            n += lp->count;
            continue;
        }
        for (int k = 0; k < lp->count; k++) {
            list[n] = b->coedges[lp->first + (ca - lp->first + k) % lp->count];
            list[n++].pcurve = -1;
        }
        list[n++] = (cb_topo_coedge){e, 1, pa, la};
        /* B, or the jump along the pole line. */
        for (int k = 0; lb >= 0 && k < b->loops[lb].count; k++) {
            const cb_topo_loop *lq = &b->loops[lb];
            list[n] = b->coedges[lq->first + (cb - lq->first + k) % lq->count];
            list[n++].pcurve = -1;
        }
        list[n++] = (cb_topo_coedge){e, 0, pb, la};
    }
    if (!st) {
        start[b->n_loops] = n;
        b->loops[la].outer = 1;
        st = relay(b, list, start, err);
    }
    free(start);
    free(list);
    r = st ? -1 : 1;
done:
    free(uv);
    free(at);
    cb_topo_inverter_clear(&inv);
    return r;
}

/* Gives face f a seam when it is a band (band_step), splitting edges as that needs: 1 when it
 * did, 0 when f is left as it was, -1 on error. */
static int band_face(cb_topo_body *b, int f, double tol, cb_error *err)
{
    /* At most one split per winding loop, then the seam. */
    for (int step = 0; step < 3; step++) {
        int r = band_step(b, f, tol, err);
        if (r != 2)
            return r;
    }
    return 0;
}

cb_status cb_topo_close_faces(cb_topo_body *b, double tol, int *closed, cb_error *err)
{
    int n = 0;
    cb_error local;
    for (int f = 0; f < b->n_faces; f++) {
        int r = close_face(b, f, tol, &local);
        if (r == 0)
            r = band_face(b, f, tol, &local);
        if (r < 0 && local.status == CB_ERR_NOMEM) {
            if (closed)
                *closed = n;
            return cb_error_set(err, local.status, "face %d: %s", f, local.msg);
        }
        /* A seam not found (not expected) leaves the face as it was, for validation to
         * report. */
        n += r > 0;
    }
    if (closed)
        *closed = n;
    return CB_OK;
}
