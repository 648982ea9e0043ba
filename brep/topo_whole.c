/* Faces that cover their whole closed surface: the seams and poles that bound them (see
 * cb_topo_close_faces in topo.h). */
#include <math.h>
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
 * the start of its domain, as an exact curve c parameterised by the surface parameter it runs
 * along, over [*t0, *t1] (the domain in that direction). Returns CB_ERR_UNSUPPORTED for a
 * surface kind or direction without such a curve here. */
static cb_status iso_curve(cb_topo_curve *c, double *t0, double *t1, const cb_topo_inverter *inv,
                           int along, cb_error *err)
{
    const cb_topo_surface *s = inv->s;
    *t0 = inv->box[2 * along];
    *t1 = inv->box[2 * along + 1];
    if (s->kind == CB_SURFACE_ANALYTIC) {
        const cb_analytic_surface *a = &s->analytic;
        const cb_frame *f = &a->frame;
        double o[3];
        if ((a->kind == CB_ANALYTIC_SPHERE || a->kind == CB_ANALYTIC_ELLIPSOID) && along == 1) {
            /* The meridian at u = 0: (r1 cos v, 0, r3 sin v) in the frame. */
            double r3 = a->kind == CB_ANALYTIC_SPHERE ? a->r1 : a->r3;
            return conic(c, f->o, f->x, f->z, a->r1, r3, err);
        }
        if (a->kind == CB_ANALYTIC_TORUS && along == 1) {
            /* The meridian at u = 0: the circle of radius r about (R, 0, 0) in the x'z' plane. */
            for (int i = 0; i < 3; i++)
                o[i] = f->o[i] + a->r1 * f->x[i];
            return conic(c, o, f->x, f->z, a->r2, a->r2, err);
        }
        if (a->kind == CB_ANALYTIC_TORUS && along == 0)
            return conic(c, f->o, f->x, f->y, a->r1 + a->r2, a->r1 + a->r2, err);
    } else if (s->kind == CB_SURFACE_NURBS) {
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
        if (along == 1) {
            /* The profile itself is the line at u = 0. */
            *c = s->profile;
            cb_nurbs_curve_init(c->nurbs);
            if (s->profile.kind == CB_CURVE_NURBS)
                return cb_nurbs_curve_set(c->nurbs, s->profile.nurbs, err);
            return CB_OK;
        }
        /* The parallel through the profile's start: turned about the axis. */
        double p[3], foot[3], x[3], y[3];
        cb_topo_curve_eval(p, &s->profile, inv->box[2]);
        const double *z = s->frame.z;
        double along_axis = 0;
        for (int i = 0; i < 3; i++)
            along_axis += (p[i] - s->frame.o[i]) * z[i];
        for (int i = 0; i < 3; i++) {
            foot[i] = s->frame.o[i] + along_axis * z[i];
            x[i] = p[i] - foot[i];
        }
        double r = cb_vec3_normalize(x);
        if (!(r > 0))
            return cb_error_set(err, CB_ERR_UNSUPPORTED, "the profile starts on the axis");
        cb_vec3_cross(y, z, x);
        return conic(c, foot, x, y, r, r, err);
    }
    return cb_error_set(err, CB_ERR_UNSUPPORTED, "no %s line of a %s surface", along ? "v" : "u",
                        cb_topo_surface_type_name(s));
}

/* Appends the iso_curve in direction `along`, checked to lie on the surface within tol, and
 * its range. Returns its index or -1 (err set). */
static int seam_curve(cb_topo_body *b, const cb_topo_inverter *inv, int along, double t[2],
                      double tol, cb_error *err)
{
    int ci = cb_topo_body_add_curve(b);
    if (ci < 0) {
        cb_error_set(err, CB_ERR_NOMEM, "out of memory");
        return -1;
    }
    double t0, t1;
    if (iso_curve(&b->curves[ci], &t0, &t1, inv, along, err))
        return -1;
    double x = inv->box[2 * (1 - along)], worst = 0;
    for (int k = 0; k < N_TEST; k++) {
        double t = t0 + (t1 - t0) * k / (N_TEST - 1), p[3], q[3];
        cb_topo_curve_eval(p, &b->curves[ci], t);
        eval_line(q, inv, along, t, x);
        worst = fmax(worst, cb_vec3_dist(p, q));
    }
    if (!(worst <= tol)) {
        cb_error_set(err, CB_ERR_NUMERIC, "its seam lies %g off the surface", worst);
        return -1;
    }
    t[0] = t0;
    t[1] = t1;
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
        double tu[2], tv[2];
        int cu = seam_curve(b, &inv, 0, tu, tol, err); /* along u, at v0 */
        int cv = cu < 0 ? -1 : seam_curve(b, &inv, 1, tv, tol, err); /* along v, at u0 */
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
        double t[2];
        int ci = seam_curve(b, &inv, along, t, tol, err);
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

cb_status cb_topo_close_faces(cb_topo_body *b, double tol, int *closed, cb_error *err)
{
    int n = 0;
    cb_error local;
    for (int f = 0; f < b->n_faces; f++) {
        int r = close_face(b, f, tol, &local);
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
