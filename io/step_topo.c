/* Topology entities: solids, shells, faces, bounds, loops, oriented edges, edges, vertices,
 * and the pcurves the edges carry. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "io/step_internal.h"

static cb_status no_memory(step_file *f)
{
    return cb_error_set(f->err, CB_ERR_NOMEM, "%s: out of memory", f->path);
}

/* The arguments of r, which must be an instance of one of the given types (the first is named
 * in the message), with n parameters. */
static const step_node *args_of(step_file *f, const step_rec *r, const step_type *types,
                                int n_types, int n, const char *role)
{
    for (int k = 0; k < n_types; k++) {
        const step_part *p = step_part_of(f, r, types[k]);
        if (p)
            return step_args(f, r, p, n);
    }
    step_fail(f, r, NULL, CB_ERR_INVALID, "%s expected for the %s", step_type_name(types[0]), role);
    return NULL;
}

/* ---------------------------------------------------------------- memoisation ------------- */

/* The body index record k became as `kind`, or -1. */
static int memo_get(const step_file *f, int k, step_memo_kind kind)
{
    return f->memo_kind[k] == kind ? f->memo[k] : -1;
}

static int memo_set(step_file *f, int k, step_memo_kind kind, int index)
{
    f->memo_kind[k] = (unsigned char)kind;
    return f->memo[k] = index;
}

/* ---------------------------------------------------------------- vertices and edges ------- */

static cb_status vertex(step_file *f, const step_rec *r, int *out)
{
    int k = step_rec_index(f, r);
    if ((*out = memo_get(f, k, STEP_MEMO_VERTEX)) >= 0)
        return CB_OK;
    static const step_type types[] = {STEP_T_VERTEX_POINT};
    const step_node *a = args_of(f, r, types, 1, 2, "vertex");
    const step_rec *q;
    double p[3];
    cb_status st;
    if (!a)
        return f->err->status;
    if ((st = step_get_ref(f, r, step_next(a), "vertex_geometry", &q)) ||
        (st = step_point(f, q, 3, p)))
        return st;
    int v = cb_topo_body_add_vertex(f->body);
    if (v < 0)
        return no_memory(f);
    memcpy(f->body->vertices[v].p, p, sizeof p);
    *out = memo_set(f, k, STEP_MEMO_VERTEX, v);
    return CB_OK;
}

/* A curve index for geometry record r (shared when several edges use one curve). */
static cb_status edge_curve_geometry(step_file *f, const step_rec *r, int *out)
{
    int k = step_rec_index(f, r);
    if ((*out = memo_get(f, k, STEP_MEMO_CURVE)) >= 0)
        return CB_OK;
    int c = cb_topo_body_add_curve(f->body);
    if (c < 0)
        return no_memory(f);
    f->bound_used = 0;
    cb_status st = step_curve(f, r, 3, &f->body->curves[c]);
    if (st)
        return st;
    /* A curve bounded by this edge's vertices (a parabola) is this edge's alone. */
    *out = f->bound_used ? c : memo_set(f, k, STEP_MEMO_CURVE, c);
    return CB_OK;
}

/* Parameter range of the edge from its vertices: the curve runs from a to b (the edge's start
 * and end when same_sense, else swapped). Conics go counterclockwise from a to b (a full turn
 * for a closed edge); a B-spline's ends snap to the domain ends they coincide with: a vertex
 * within 10 unc (the file's uncertainty) of a domain end, whose nearest point on the curve lies
 * within unc of that end. (A curve may run on beyond its edge's vertex by ten uncertainties or
 * more: trj3_s1-ct-214.stp's edge 212 starts 1 before its vertex, with unc 0.1.) */
static void edge_range(cb_topo_edge *e, const cb_topo_curve *c, const double a[3],
                       const double b[3], double unc)
{
    double tol = 10 * unc;
    const double two_pi = 6.283185307179586;
    double lo = 0, hi = 0, ta, tb;
    if (c->kind == CB_CURVE_NURBS)
        cb_nurbs_curve_domain(c->nurbs, &lo, &hi);
    int closed = e->v[0] == e->v[1];
    cb_topo_curve_project(&ta, c, a, lo, hi);
    cb_topo_curve_project(&tb, c, b, lo, hi);
    if (c->kind == CB_CURVE_CIRCLE || c->kind == CB_CURVE_ELLIPSE) {
        tb = ta + fmod(tb - ta + 2 * two_pi, two_pi);
        if (closed || tb - ta <= 0)
            tb = ta + two_pi;
    } else if (c->kind == CB_CURVE_NURBS) {
        double pa[3], pb[3], fa[3], fb[3];
        cb_topo_curve_eval(pa, c, lo);
        cb_topo_curve_eval(pb, c, hi);
        cb_topo_curve_eval(fa, c, ta);
        cb_topo_curve_eval(fb, c, tb);
        if (cb_vec3_dist(a, pa) <= tol && cb_vec3_dist(fa, pa) <= unc)
            ta = lo;
        if (cb_vec3_dist(b, pb) <= tol && cb_vec3_dist(fb, pb) <= unc)
            tb = hi;
        if (closed && ta == tb) {
            ta = lo;
            tb = hi;
        }
        if (!closed && ta > tb) {
            /* The edge runs up the curve from a to b; nearest points the other way round mean
             * the curve passes a vertex twice (a curve shared by several edges that comes back
             * near itself, as an intersection curve does at a node): keep one end and find
             * the other beyond it, whichever pair lies closer. */
            double t1, t2;
            double d1 = cb_topo_curve_project(&t1, c, b, ta, hi);
            double d2 = cb_topo_curve_project(&t2, c, a, lo, tb);
            if (d1 <= d2)
                tb = t1;
            else
                ta = t2;
        }
    }
    e->t0 = ta;
    e->t1 = tb;
}

static cb_status edge(step_file *f, const step_rec *r, int *out)
{
    int k = step_rec_index(f, r);
    if ((*out = memo_get(f, k, STEP_MEMO_EDGE)) >= 0)
        return CB_OK;
    static const step_type types[] = {STEP_T_EDGE_CURVE};
    const step_node *a = args_of(f, r, types, 1, 5, "edge");
    const step_rec *v0, *v1, *g;
    int iv0, iv1, ic = -1, same;
    cb_status st;
    if (!a)
        return f->err->status;
    const step_node *x = step_next(a);
    if ((st = step_get_ref(f, r, x, "edge_start", &v0)) || (st = vertex(f, v0, &iv0)) ||
        (st = step_get_ref(f, r, step_next(x), "edge_end", &v1)) || (st = vertex(f, v1, &iv1)))
        return st;
    x = step_next(step_next(x));
    if ((st = step_get_ref(f, r, x, "edge_geometry", &g)) || (st = step_enter(f, r)))
        return st;
    f->bound_kind = 1;
    f->bound_from_edge = 1;
    memcpy(f->bound_pt[0], f->body->vertices[iv0].p, sizeof f->bound_pt[0]);
    memcpy(f->bound_pt[1], f->body->vertices[iv1].p, sizeof f->bound_pt[1]);
    st = edge_curve_geometry(f, g, &ic);
    f->bound_kind = f->bound_from_edge = 0;
    step_leave(f, r);
    if (st || (st = step_get_bool(f, r, step_next(x), "same_sense", &same)))
        return st;
    int e = cb_topo_body_add_edge(f->body);
    if (e < 0)
        return no_memory(f);
    cb_topo_body *b = f->body;
    cb_topo_edge *ed = &b->edges[e];
    ed->curve = ic;
    ed->same_sense = same;
    ed->v[0] = iv0;
    ed->v[1] = iv1;
    ed->tol = f->uncertainty;
    const double *p0 = b->vertices[iv0].p, *p1 = b->vertices[iv1].p;
    edge_range(ed, &b->curves[ic], same ? p0 : p1, same ? p1 : p0, f->uncertainty);
    *out = memo_set(f, k, STEP_MEMO_EDGE, e);
    return CB_OK;
}

/* ---------------------------------------------------------------- pcurves ------------------ */

/* The PCURVEs of the edge's geometry (a SURFACE_CURVE or SEAM_CURVE) that lie on surface
 * record `surf`: up to two, in the file's order. */
static int pcurves_on(const step_file *f, const step_rec *g, long surf, const step_rec *out[2])
{
    step_type t = step_rec_type(f, g);
    if (g->complex ||
        (t != STEP_T_SURFACE_CURVE && t != STEP_T_SEAM_CURVE && t != STEP_T_INTERSECTION_CURVE))
        return 0;
    const step_node *list = &f->nodes[f->parts[g->part0].args];
    if (list->n != 4)
        return 0;
    const step_node *assoc = step_elem(list, 2);
    if (assoc->kind != STEP_LIST)
        return 0;
    int n = 0;
    const step_node *x = assoc + 1;
    for (int k = 0; k < assoc->n && n < 2; k++, x = step_next(x)) {
        const step_rec *q = x->kind == STEP_REF ? step_find(f, x->v.ref) : NULL;
        if (!q || q->complex || step_rec_type(f, q) != STEP_T_PCURVE)
            continue;
        const step_node *pa = &f->nodes[f->parts[q->part0].args];
        if (pa->n == 3 && step_elem(pa, 1)->kind == STEP_REF && step_elem(pa, 1)->v.ref == surf)
            out[n++] = q;
    }
    return n;
}

/* The factors k[0], k[1] that take surface s's parameters as a file writes them into the body's
 * (1 for a length): ISO 10303-42 measures the angle parameters (u of cylinders and cones, u and
 * v of spheres and tori, the turning angle of surfaces of revolution, u as the body has it) in
 * the plane angle unit of the context, angle_rad radians (a file in degrees writes its pcurves
 * in degrees: trj4_k1_top-pe-214.stp), and the body's surfaces take radians. */
static void param_scale(double k[2], const cb_topo_surface *s, double angle_rad)
{
    k[0] = k[1] = 1;
    if (s->kind == CB_SURFACE_REVOLUTION)
        k[0] = angle_rad;
    if (s->kind != CB_SURFACE_ANALYTIC)
        return;
    switch (s->analytic.kind) {
    case CB_ANALYTIC_SPHERE:
    case CB_ANALYTIC_TORUS:
        k[1] = angle_rad;
        k[0] = angle_rad;
        break;
    case CB_ANALYTIC_CYLINDER:
    case CB_ANALYTIC_CONE:
        k[0] = angle_rad;
        break;
    default:
        break;
    }
}

/* Scales the (u, v) coordinates of pcurve c by k (param_scale): a line's point and velocity, a
 * B-spline's control points, keeping the parameter; a conic as it stands where the scale is
 * uniform, else turned into its rational B-spline over a whole turn first, which has a
 * parameter of its own (an affine image of an ellipse with axes off the u and v directions is
 * no ellipse of the curve kinds; pcurves need not share their edge's parameter). */
static cb_status scale_pcurve(step_file *f, const step_rec *r, cb_topo_curve *c,
                              const double k[2])
{
    if (k[0] == 1 && k[1] == 1)
        return CB_OK;
    if ((c->kind == CB_CURVE_CIRCLE || c->kind == CB_CURVE_ELLIPSE) && k[0] != k[1]) {
        cb_error local;
        cb_nurbs_curve_t nc;
        cb_nurbs_curve_init(nc);
        if (cb_topo_curve_to_nurbs(nc, c, 0, 2 * CB_PI, 0, &local)) {
            cb_nurbs_curve_clear(nc);
            return step_fail(f, r, NULL, local.status, "pcurve: %s", local.msg);
        }
        cb_nurbs_curve_swap(c->nurbs, nc);
        cb_nurbs_curve_clear(nc);
        c->kind = CB_CURVE_NURBS;
    }
    switch (c->kind) {
    case CB_CURVE_LINE: {
        double v[2];
        for (int i = 0; i < 2; i++) {
            c->frame.o[i] *= k[i];
            v[i] = c->r1 * c->frame.z[i] * k[i];
        }
        c->r1 = hypot(v[0], v[1]);
        c->frame.z[0] = v[0] / c->r1;
        c->frame.z[1] = v[1] / c->r1;
        break;
    }
    case CB_CURVE_CIRCLE:
    case CB_CURVE_ELLIPSE:
        for (int i = 0; i < 2; i++)
            c->frame.o[i] *= k[0];
        c->r1 *= k[0];
        c->r2 *= k[0];
        break;
    case CB_CURVE_NURBS:
        for (int j = 0; j < c->nurbs->n; j++)
            for (int i = 0; i < 2; i++)
                c->nurbs->cw[4 * j + i] *= k[i];
        break;
    }
    return CB_OK;
}

/* PCURVE(name, basis_surface, DEFINITIONAL_REPRESENTATION(name, (curve), context)) on surface
 * s, its angle parameters taken into radians (param_scale). */
static cb_status pcurve(step_file *f, const step_rec *r, const cb_topo_surface *s, int *out)
{
    int k = step_rec_index(f, r);
    if ((*out = memo_get(f, k, STEP_MEMO_PCURVE)) >= 0)
        return CB_OK;
    static const step_type pt[] = {STEP_T_PCURVE}, dt[] = {STEP_T_DEFINITIONAL_REPRESENTATION};
    const step_node *a = args_of(f, r, pt, 1, 3, "pcurve"), *da;
    const step_rec *d, *c;
    cb_status st;
    if (!a)
        return f->err->status;
    if ((st = step_get_ref(f, r, step_elem(a - 1, 2), "reference_to_curve", &d)))
        return st;
    if (!(da = args_of(f, d, dt, 1, 3, "pcurve")))
        return f->err->status;
    if ((st = step_get_list(f, d, step_next(da), "items", 1, 1)) ||
        (st = step_get_ref(f, d, step_next(da) + 1, "item", &c)))
        return st;
    int ip = cb_topo_body_add_pcurve(f->body);
    if (ip < 0)
        return no_memory(f);
    double scale[2];
    param_scale(scale, s, f->angle_rad);
    if ((st = step_curve(f, c, 2, &f->body->pcurves[ip])) ||
        (st = scale_pcurve(f, c, &f->body->pcurves[ip], scale)))
        return st;
    *out = memo_set(f, k, STEP_MEMO_PCURVE, ip);
    return CB_OK;
}

/* 2D point of pcurve p at the start (end = 0) or end of coedge c. */
static void pcurve_end(double uv[3], const cb_topo_body *b, int p, const cb_topo_coedge *c, int end)
{
    const cb_topo_edge *e = &b->edges[c->edge];
    int at_t1 = (c->sense == e->same_sense) == end;
    cb_topo_curve_eval(uv, &b->pcurves[p], at_t1 ? e->t1 : e->t0);
}

/* Which of the two pcurves p[0], p[1] of a seam lies on the side of coedge c: 0 or 1, or -1
 * when they are not two copies of one line across the seam. The two are translates of each
 * other across one parameter direction; the face lies to the left of the coedge in (u, v)
 * when it runs along its face's normal (same_sense 1; the right otherwise), on both sides of
 * the seam, so the copy whose left points into the other copy's direction is this coedge's.
 * Decided by geometry alone, as Open CASCADE does (ShapeAnalysis_Curve::SelectForwardSeam): the
 * neighbours cannot tell where the joint is a pole, at which both copies meet the previous
 * coedge's end. */
static int seam_side(const cb_topo_body *b, const int p[2], const cb_topo_coedge *c,
                     int same_sense)
{
    const cb_topo_edge *e = &b->edges[c->edge];
    double m[2][3], a[3], z[3];
    for (int j = 0; j < 2; j++)
        cb_topo_curve_eval(m[j], &b->pcurves[p[j]], 0.5 * (e->t0 + e->t1));
    double d[2] = {m[1][0] - m[0][0], m[1][1] - m[0][1]};
    int across = fabs(d[0]) > fabs(d[1]) ? 0 : 1;
    if (!(fabs(d[1 - across]) <= 1e-6 * fabs(d[across])))
        return -1;
    pcurve_end(a, b, p[0], c, 0);
    pcurve_end(z, b, p[0], c, 1);
    double run[2] = {z[0] - a[0], z[1] - a[1]}, left[2] = {-run[1], run[0]};
    double toward = (same_sense ? 1 : -1) * left[across] * d[across];
    if (toward == 0)
        return -1;
    /* left pointing from p[0] towards p[1]: the face lies between, p[0] is this side */
    return toward > 0 ? 0 : 1;
}

/* Attaches pcurves to the coedges of face fi (whose surface is record surf). A seam edge has
 * two pcurves on the face and two coedges; each coedge takes the one on its side of the seam
 * (seam_side), or failing that the one whose start meets the end of the previous coedge's
 * pcurve in the (u, v) plane. */
static cb_status attach_pcurves(step_file *f, int fi, long surf, const int *geom)
{
    cb_topo_body *b = f->body;
    const cb_topo_face *face = &b->faces[fi];
    for (int pass = 0; pass < 2; pass++)
        for (int l = face->first; l < face->first + face->count; l++) {
            const cb_topo_loop *lp = &b->loops[l];
            for (int k = 0; k < lp->count; k++) {
                int ci = lp->first + k;
                const step_rec *pc[2];
                int n = pcurves_on(f, &f->recs[geom[ci - b->loops[face->first].first]], surf, pc);
                if (!n || (n == 1) != (pass == 0))
                    continue;
                int ip[2] = {-1, -1};
                for (int j = 0; j < n; j++) {
                    cb_status st = pcurve(f, pc[j], &b->surfaces[face->surface], &ip[j]);
                    if (st)
                        return st;
                }
                cb_topo_coedge *c = &b->coedges[ci];
                if (n == 1) {
                    c->pcurve = ip[0];
                    continue;
                }
                const cb_topo_coedge *prev =
                    &b->coedges[lp->first + (k + lp->count - 1) % lp->count];
                int choice = seam_side(b, ip, c, face->same_sense);
                if (choice >= 0) {
                    c->pcurve = ip[choice];
                    continue;
                }
                choice = 0;
                if (prev->pcurve >= 0) {
                    double end[3], s0[3], s1[3];
                    pcurve_end(end, b, prev->pcurve, prev, 1);
                    pcurve_end(s0, b, ip[0], c, 0);
                    pcurve_end(s1, b, ip[1], c, 0);
                    choice = cb_vec3_dist(end, s1) < cb_vec3_dist(end, s0);
                } else {
                    /* No neighbour to go by: the two uses take the two pcurves in turn. */
                    for (int j = face->first; j <= l; j++)
                        for (int m = b->loops[j].first;
                             m < ci && m < b->loops[j].first + b->loops[j].count; m++)
                            choice ^= b->coedges[m].edge == c->edge;
                }
                c->pcurve = ip[choice];
            }
        }
    return CB_OK;
}

/* ---------------------------------------------------------------- faces and shells --------- */

/* One bound of face fi: its loop's coedges, in traversal order (reversed when the bound's
 * orientation, combined with the shell's, is .F.). geom[k] receives the edge geometry record
 * index of the k-th coedge of the face. */
static cb_status bound(step_file *f, const step_rec *r, int fi, int flip, int **geom, int *n_geom,
                       int *cap_geom)
{
    static const step_type bt[] = {STEP_T_FACE_BOUND, STEP_T_FACE_OUTER_BOUND},
                           lt[] = {STEP_T_EDGE_LOOP}, ot[] = {STEP_T_ORIENTED_EDGE};
    const step_node *a = args_of(f, r, bt, 2, 3, "face bound"), *la;
    const step_rec *loop;
    int orient;
    cb_status st;
    if (!a)
        return f->err->status;
    if ((st = step_get_ref(f, r, step_next(a), "bound", &loop)) ||
        (st = step_get_bool(f, r, step_next(step_next(a)), "orientation", &orient)))
        return st;
    if (step_rec_is(f, loop, STEP_T_VERTEX_LOOP))
        return CB_OK;
    if (!(la = args_of(f, loop, lt, 1, 2, "bound")))
        return f->err->status;
    const step_node *list = step_next(la);
    if ((st = step_get_list(f, loop, list, "edge_list", 1, 1 << 24)))
        return st;
    int l = cb_topo_body_add_loop(f->body);
    if (l < 0)
        return no_memory(f);
    int reversed = !orient ^ flip, n = list->n;
    cb_topo_loop *lp = &f->body->loops[l];
    lp->first = f->body->n_coedges;
    lp->count = n;
    lp->face = fi;
    lp->outer = step_rec_is(f, r, STEP_T_FACE_OUTER_BOUND);
    if (*n_geom + n > *cap_geom) {
        int c = 2 * (*n_geom + n);
        int *g = realloc(*geom, (size_t)c * sizeof *g);
        if (!g)
            return no_memory(f);
        *geom = g;
        *cap_geom = c;
    }
    for (int k = 0; k < n; k++) {
        const step_rec *oe, *ec;
        const step_node *oa;
        int ie = -1, o;
        if ((st = step_get_ref(f, loop, step_elem(list, reversed ? n - 1 - k : k), "oriented edge",
                               &oe)))
            return st;
        if (!(oa = args_of(f, oe, ot, 1, 5, "loop")))
            return f->err->status;
        const step_node *x = step_elem(oa - 1, 3);
        if ((st = step_get_ref(f, oe, x, "edge_element", &ec)) ||
            (st = step_get_bool(f, oe, step_next(x), "orientation", &o)) || (st = edge(f, ec, &ie)))
            return st;
        int c = cb_topo_body_add_coedge(f->body);
        if (c < 0)
            return no_memory(f);
        cb_topo_coedge *co = &f->body->coedges[c];
        co->edge = ie;
        co->sense = o ^ reversed;
        co->pcurve = -1;
        co->loop = l;
        /* The edge's geometry record, for the pcurve lookup. */
        const step_node *ea = &f->nodes[step_part_of(f, ec, STEP_T_EDGE_CURVE)->args];
        (*geom)[(*n_geom)++] = step_rec_index(f, step_find(f, step_elem(ea, 3)->v.ref));
    }
    return CB_OK;
}

static cb_status face(step_file *f, const step_rec *r, int shell, int flip)
{
    static const step_type ft[] = {STEP_T_ADVANCED_FACE, STEP_T_FACE_SURFACE};
    const step_node *a = args_of(f, r, ft, 2, 4, "face");
    const step_rec *sr;
    int same;
    cb_status st;
    if (!a)
        return f->err->status;
    const step_node *bounds = step_next(a), *x = step_next(bounds);
    if ((st = step_get_list(f, r, bounds, "bounds", 0, 1 << 20)) ||
        (st = step_get_ref(f, r, x, "face_geometry", &sr)) ||
        (st = step_get_bool(f, r, step_next(x), "same_sense", &same)))
        return st;
    int fi = cb_topo_body_add_face(f->body), k = step_rec_index(f, sr);
    if (fi < 0)
        return no_memory(f);
    int si = memo_get(f, k, STEP_MEMO_SURFACE);
    if (si < 0) {
        if ((si = cb_topo_body_add_surface(f->body)) < 0)
            return no_memory(f);
        if ((st = step_surface(f, sr, &f->body->surfaces[si])))
            return st;
        memo_set(f, k, STEP_MEMO_SURFACE, si);
    }
    cb_topo_face *fc = &f->body->faces[fi];
    fc->surface = si;
    fc->same_sense = same ^ flip;
    fc->shell = shell;
    fc->first = f->body->n_loops;
    int *geom = NULL, n_geom = 0, cap_geom = 0;
    const step_node *y = bounds + 1;
    for (int j = 0; j < bounds->n && !st; j++, y = step_next(y)) {
        const step_rec *br;
        if (!(st = step_get_ref(f, r, y, "bound", &br)))
            st = bound(f, br, fi, flip, &geom, &n_geom, &cap_geom);
    }
    f->body->faces[fi].count = f->body->n_loops - f->body->faces[fi].first;
    if (!st)
        st = attach_pcurves(f, fi, sr->id, geom);
    free(geom);
    return st;
}

/* A shell of faces; flip reverses every face (an ORIENTED_CLOSED_SHELL with .F.). */
static cb_status shell(step_file *f, const step_rec *r, int solid, int flip)
{
    static const step_type ot[] = {STEP_T_ORIENTED_CLOSED_SHELL},
                           st_[] = {STEP_T_CLOSED_SHELL, STEP_T_OPEN_SHELL};
    cb_status st;
    if (step_rec_is(f, r, STEP_T_ORIENTED_CLOSED_SHELL)) {
        const step_node *a = args_of(f, r, ot, 1, 4, "shell");
        const step_rec *inner;
        int o;
        if (!a)
            return f->err->status;
        const step_node *x = step_elem(a - 1, 2);
        if ((st = step_get_ref(f, r, x, "closed_shell_element", &inner)) ||
            (st = step_get_bool(f, r, step_next(x), "orientation", &o)) || (st = step_enter(f, r)))
            return st;
        st = shell(f, inner, solid, flip ^ !o);
        step_leave(f, r);
        return st;
    }
    const step_node *a = args_of(f, r, st_, 2, 2, "shell");
    if (!a)
        return f->err->status;
    const step_node *list = step_next(a);
    if ((st = step_get_list(f, r, list, "faces", 1, 1 << 24)))
        return st;
    int s = cb_topo_body_add_shell(f->body);
    if (s < 0)
        return no_memory(f);
    f->body->shells[s].first = f->body->n_faces;
    f->body->shells[s].count = list->n;
    f->body->shells[s].closed = step_rec_is(f, r, STEP_T_CLOSED_SHELL);
    f->body->shells[s].solid = solid;
    const step_node *x = list + 1;
    for (int k = 0; k < list->n; k++, x = step_next(x)) {
        const step_rec *fr;
        if ((st = step_get_ref(f, r, x, "face", &fr)) || (st = face(f, fr, s, flip)))
            return st;
    }
    return CB_OK;
}

/* A solid or surface model. */
static cb_status item(step_file *f, const step_rec *r)
{
    step_type t = step_rec_type(f, r);
    cb_status st;
    if (t == STEP_T_SHELL_BASED_SURFACE_MODEL) {
        const step_node *a = step_args(f, r, &f->parts[r->part0], 2);
        if (!a)
            return f->err->status;
        const step_node *list = step_next(a);
        if ((st = step_get_list(f, r, list, "sbsm_boundary", 1, 1 << 20)))
            return st;
        const step_node *x = list + 1;
        for (int k = 0; k < list->n; k++, x = step_next(x)) {
            const step_rec *sr;
            if ((st = step_get_ref(f, r, x, "shell", &sr)) || (st = shell(f, sr, -1, 0)))
                return st;
        }
        return CB_OK;
    }
    int voids = t == STEP_T_BREP_WITH_VOIDS;
    const step_node *a = step_args(f, r, &f->parts[r->part0], voids ? 3 : 2);
    const step_rec *outer;
    if (!a)
        return f->err->status;
    int s = cb_topo_body_add_solid(f->body);
    if (s < 0)
        return no_memory(f);
    f->body->solids[s].first = f->body->n_shells;
    if ((st = step_get_ref(f, r, step_next(a), "outer", &outer)) || (st = shell(f, outer, s, 0)))
        return st;
    if (voids) {
        const step_node *list = step_next(step_next(a)), *x = list + 1;
        if ((st = step_get_list(f, r, list, "voids", 1, 1 << 20)))
            return st;
        for (int k = 0; k < list->n; k++, x = step_next(x)) {
            const step_rec *vr;
            if ((st = step_get_ref(f, r, x, "void", &vr)) || (st = shell(f, vr, s, 0)))
                return st;
        }
    }
    f->body->solids[s].count = f->body->n_shells - f->body->solids[s].first;
    return CB_OK;
}

/* Moves everything item() added from the counts in `from` on. */
static void place(cb_topo_body *b, const int from[3], const cb_xform *x)
{
    for (int k = from[0]; k < b->n_vertices; k++)
        cb_xform_apply_point(b->vertices[k].p, x, b->vertices[k].p);
    for (int k = from[1]; k < b->n_curves; k++)
        cb_topo_curve_transform(&b->curves[k], x);
    for (int k = from[2]; k < b->n_surfaces; k++)
        cb_topo_surface_transform(&b->surfaces[k], x);
}

cb_status step_map_body(step_file *f)
{
    int found = 0;
    cb_topo_body *b = f->body;
    for (int k = 0; k < f->n_recs; k++) {
        const step_rec *r = &f->recs[k];
        step_type t = step_rec_type(f, r);
        if (r->complex || (t != STEP_T_MANIFOLD_SOLID_BREP && t != STEP_T_BREP_WITH_VOIDS &&
                           t != STEP_T_SHELL_BASED_SURFACE_MODEL))
            continue;
        cb_xform *xs = NULL;
        int n_xs = 0;
        cb_status st = step_units_for(f, r);
        if (!st)
            st = step_placements_for(f, r, &xs, &n_xs);
        if (st)
            return st;
        if (found && f->length_mm != b->length_unit_mm) {
            free(xs);
            return step_fail(f, r, NULL, CB_ERR_UNSUPPORTED,
                             "length unit of %g mm differs from the %g mm of the first solid",
                             f->length_mm, b->length_unit_mm);
        }
        b->length_unit_mm = f->length_mm;
        b->tol = fmax(b->tol, f->uncertainty);
        /* Each instance gets its own copies, so that a placement moves only its geometry. */
        for (int i = 0; i < n_xs; i++) {
            memset(f->state, STEP_FRESH, (size_t)f->n_recs);
            memset(f->memo_kind, 0, (size_t)f->n_recs);
            int from[3] = {b->n_vertices, b->n_curves, b->n_surfaces};
            if ((st = item(f, r))) {
                free(xs);
                return st;
            }
            place(b, from, &xs[i]);
            found++;
        }
        free(xs);
    }
    if (!found)
        return cb_error_set(f->err, CB_ERR_INVALID,
                            "%s: no MANIFOLD_SOLID_BREP, BREP_WITH_VOIDS or "
                            "SHELL_BASED_SURFACE_MODEL in the file",
                            f->path);
    return CB_OK;
}
