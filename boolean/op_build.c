/* op_build.c — the result body of a Boolean from the kept face pieces: new faces on copies of
 * the operands' surfaces, their loops made of the pieces, pieces sewn into shared edges. */
#include "boolean/op_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    double mid[3]; /* curve point halfway along the piece, to tell edges with equal ends apart */
    int uses;
    int cut, side, src; /* where its curve comes from: cut index (cut = 1), or the original
                           edge src of operand side */
    int reserved;       /* made by a piece with a partner (has_partner): for that partner only */
} edge_info;

typedef struct {
    cb_topo_body *b;
    edge_info *info;
    int cap_info;
    double weld;
    const cb_bool_cuts *cuts;
    cb_topo_curve *cut_curve; /* per cut, its 3D curve (cb_bool_cut_curve), made when first used */
    char *cut_made;
    double *mid_uv; /* per coedge of a boundary piece: (u, v) of its middle in the face's window,
                       to lift the computed pcurve there; NaN for cut pieces */
    int cap_mid;
    struct source_piece *keys; /* every piece that makes an edge, by key (count_sources) */
    int n_keys;
} builder;

/* The curve a piece lies on (a cut, or an original edge of one side) and its welded ends. */
typedef struct {
    int cut, side, src, lo, hi;
} source_key;

static int cmp_source_key(const void *a, const void *b)
{
    const source_key *x = a, *y = b;
    int d[5] = {x->cut - y->cut, x->side - y->side, x->src - y->src, x->lo - y->lo,
                x->hi - y->hi};
    for (int k = 0; k < 5; k++)
        if (d[k])
            return d[k] < 0 ? -1 : 1;
    return 0;
}

/* The 3D curve of cut k, made on first use. NULL when out of memory or invalid. */
static const cb_topo_curve *cut_curve(builder *bd, int k, cb_error *err)
{
    if (!bd->cut_made[k]) {
        if (cb_bool_cut_curve(bd->cut_curve + k, bd->cuts->cut + k, -1, err))
            return NULL;
        bd->cut_made[k] = 1;
    }
    return bd->cut_curve + k;
}

static double dist3(const double a[3], const double b[3])
{
    return sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                (a[2] - b[2]) * (a[2] - b[2]));
}

/* Distance from p to curve c over [t0, t1] (the nearest point of the whole curve, moved to the
 * nearer end of the range when it falls outside). */
static double range_distance(const cb_topo_curve *c, double t0, double t1, const double p[3])
{
    double t, q[3];
    cb_topo_curve_project(&t, c, p, t0, t1);
    if (c->kind == CB_CURVE_CIRCLE || c->kind == CB_CURVE_ELLIPSE) {
        while (t < t0)
            t += 2 * CB_SSI_PI;
        while (t >= t0 + 2 * CB_SSI_PI)
            t -= 2 * CB_SSI_PI;
        if (t > t1)
            t = t - t1 < t0 + 2 * CB_SSI_PI - t ? t1 : t0;
    }
    cb_topo_curve_eval(q, c, fmin(t1, fmax(t0, t)));
    return dist3(q, p);
}

/* The vertex at p: an existing one within weld (the first found, in creation order), else a
 * new one. -1 when out of memory. */
static int weld_vertex(builder *bd, const double p[3])
{
    cb_topo_body *b = bd->b;
    for (int v = 0; v < b->n_vertices; v++)
        if (dist3(b->vertices[v].p, p) <= bd->weld)
            return v;
    int v = cb_topo_body_add_vertex(b);
    if (v >= 0)
        memcpy(b->vertices[v].p, p, 3 * sizeof(double));
    return v;
}

/* Position pos (segment index + fraction) along a polyline of n points of dimension dim. */
static void at_pos(double *out, const double *pts, int n, int dim, double pos)
{
    int i = (int)floor(pos);
    if (i >= n - 1)
        i = n - 2;
    if (i < 0)
        i = 0;
    double f = pos - i;
    for (int k = 0; k < dim; k++)
        out[k] = pts[dim * i + k] + f * (pts[dim * (i + 1) + k] - pts[dim * i + k]);
}

static cb_status copy_curve(cb_topo_curve *dst, const cb_topo_curve *src, cb_error *err)
{
    dst->kind = src->kind;
    dst->frame = src->frame;
    dst->r1 = src->r1;
    dst->r2 = src->r2;
    if (src->kind == CB_CURVE_NURBS)
        return cb_nurbs_curve_set(dst->nurbs, src->nurbs, err);
    return CB_OK;
}

static cb_status copy_surface(cb_topo_surface *dst, const cb_topo_surface *src, cb_error *err)
{
    dst->kind = src->kind;
    dst->analytic = src->analytic;
    dst->frame = src->frame;
    memcpy(dst->dir, src->dir, sizeof dst->dir);
    cb_status st = CB_OK;
    if (src->kind == CB_SURFACE_NURBS)
        st = cb_nurbs_surface_set(dst->nurbs, src->nurbs, err);
    if (!st && (src->kind == CB_SURFACE_REVOLUTION || src->kind == CB_SURFACE_EXTRUSION))
        st = copy_curve(&dst->profile, &src->profile, err);
    return st;
}

/* The edge a piece becomes, with the ends of its traversal and whether it runs along the
 * edge curve. */
typedef struct {
    const cb_topo_curve *curve; /* the piece's own curve (the cut's, or the original edge's) */
    int cut; /* a cut piece: its curve and pcurve are the cut's polyline */
    int src; /* the cut's index, or the original edge's */
    int v_start, v_end;
    double t_start, t_end; /* edge curve parameters at the traversal's start and end */
    double mid[3];
} piece_geom;

/* Geometry of piece p of region r: the two end vertices (welded) and the parameters. */
static cb_status piece_ends(piece_geom *g, builder *bd, const op_region *r, const op_piece *p,
                            const cb_topo_body *X, const cb_topo_inverter *inv, cb_error *err)
{
    const op_src *s = r->srcs + p->src;
    double a = p->fwd ? p->pos0 : p->pos1, z = p->fwd ? p->pos1 : p->pos0;
    double pa[3], pz[3];
    if (s->kind == OP_CUT) {
        const cb_topo_curve *C = cut_curve(bd, s->index, err);
        if (!C)
            return CB_ERR_NOMEM;
        cb_topo_curve_eval(pa, C, a);
        cb_topo_curve_eval(pz, C, z);
        cb_topo_curve_eval(g->mid, C, 0.5 * (a + z));
        g->t_start = a;
        g->t_end = z;
        g->cut = 1;
        g->curve = C;
        g->src = s->index;
    } else {
        const cb_topo_coedge *co = X->coedges + s->index;
        const cb_topo_edge *e = X->edges + co->edge;
        const cb_topo_curve *C = X->curves + e->curve;
        int increasing = co->sense == e->same_sense;
        double uv[2], q[3];
        double t[2];
        double pos[2] = {a, z};
        double *pt[2] = {pa, pz};
        for (int k = 0; k < 2; k++) {
            if (pos[k] <= 1e-9)
                t[k] = increasing ? e->t0 : e->t1;
            else if (pos[k] >= s->n - 1 - 1e-9)
                t[k] = increasing ? e->t1 : e->t0;
            else {
                at_pos(uv, s->uv, s->n, 2, pos[k]);
                cb_topo_inverter_eval(q, inv, uv[0], uv[1]);
                cb_topo_curve_project(t + k, C, q, e->t0, e->t1);
                if (C->kind == CB_CURVE_CIRCLE || C->kind == CB_CURVE_ELLIPSE) {
                    /* conics project into [0, 2 pi): bring t into the edge's range */
                    while (t[k] < e->t0 - 1e-12)
                        t[k] += 2 * CB_SSI_PI;
                    while (t[k] > e->t1 + 1e-12)
                        t[k] -= 2 * CB_SSI_PI;
                }
            }
            cb_topo_curve_eval(pt[k], C, t[k]);
        }
        g->t_start = t[0];
        g->t_end = t[1];
        cb_topo_curve_eval(g->mid, C, 0.5 * (t[0] + t[1]));
        g->cut = 0;
        g->curve = C;
        g->src = co->edge;
    }
    g->v_start = weld_vertex(bd, pa);
    g->v_end = weld_vertex(bd, pz);
    return g->v_start < 0 || g->v_end < 0 ? CB_ERR_NOMEM : CB_OK;
}

static source_key key_of(const piece_geom *g, int side, int lo, int hi)
{
    return (source_key){g->cut, g->cut ? 0 : side, g->src, lo, hi};
}

/* Whether edge info in was made from the curve of key k. */
static int same_source(const edge_info *in, const source_key *k)
{
    return in->cut == k->cut && in->src == k->src && (k->cut || in->side == k->side);
}

/* A piece by its key, with its curve's range. */
typedef struct source_piece {
    source_key key;
    const cb_topo_curve *curve;
    double t0, t1;
} source_piece;

/* Whether another piece lies on the same curve between the same ends as the one of key k, over
 * its midpoint mid (not the other half of a closed curve between the same two vertices): its
 * natural partner, which it sews onto rather than onto a curve of another source that merely
 * passes within the weld distance (which one is met first depends on the order of faces). */
static int has_partner(const builder *bd, const source_key *k, const double mid[3])
{
    int lo = 0, hi = bd->n_keys, n = 0;
    while (lo < hi) { /* the first key >= k */
        int m = (lo + hi) / 2;
        if (cmp_source_key(&bd->keys[m].key, k) < 0)
            lo = m + 1;
        else
            hi = m;
    }
    for (int i = lo; i < bd->n_keys && !cmp_source_key(&bd->keys[i].key, k); i++) {
        const source_piece *x = bd->keys + i;
        n += range_distance(x->curve, x->t0, x->t1, mid) <= bd->weld;
    }
    return n >= 2; /* the piece itself and another */
}

static int grow_info(builder *bd)
{
    if (bd->b->n_edges < bd->cap_info)
        return 0;
    int cap = bd->cap_info ? 2 * bd->cap_info : 64;
    edge_info *q = realloc(bd->info, (size_t)cap * sizeof *q);
    if (!q)
        return -1;
    bd->info = q;
    bd->cap_info = cap;
    return 0;
}

/* The coedge of loop `loop` for piece p: sewn onto the existing edge used once with the same
 * ends whose curve passes nearest its midpoint (within the weld distance), or on a new edge.
 * Where another piece lies on the piece's curve between the same ends (has_partner), the two
 * sew only with each other. */
static cb_status add_coedge(builder *bd, int loop, const op_region *r, const op_piece *p,
                            const cb_topo_body *X, const cb_bool_cuts *cuts,
                            const cb_topo_inverter *inv, cb_error *err)
{
    cb_topo_body *b = bd->b;
    piece_geom g;
    cb_status pst = piece_ends(&g, bd, r, p, X, inv, err);
    if (pst)
        return pst == CB_ERR_NOMEM ? cb_error_set(err, pst, "bool: out of memory") : pst;
    /* A piece shorter than the weld distance (two vertices of the face's split closer than
     * that but farther than the snap) welds into a point: no edge. */
    if (g.v_start == g.v_end && dist3(g.mid, b->vertices[g.v_start].p) <= bd->weld)
        return CB_OK;
    int up = g.t_start < g.t_end;
    int lo = up ? g.v_start : g.v_end, hi = up ? g.v_end : g.v_start;
    const op_src *s = r->srcs + p->src;
    int edge = -1;
    source_key key = key_of(&g, r->side, lo < hi ? lo : hi, lo < hi ? hi : lo);
    int partnered = has_partner(bd, &key, g.mid);
    double nearest = bd->weld;
    for (int e = 0; e < b->n_edges; e++) {
        const edge_info *in = bd->info + e;
        if (in->uses != 1 ||
            !((b->edges[e].v[0] == lo && b->edges[e].v[1] == hi) ||
              (b->edges[e].v[0] == hi && b->edges[e].v[1] == lo)) ||
            ((partnered || in->reserved) && !same_source(in, &key)))
            continue;
        double d = range_distance(b->curves + b->edges[e].curve, b->edges[e].t0, b->edges[e].t1,
                                  g.mid);
        if (d <= nearest) {
            nearest = d;
            edge = e;
        }
    }
    int sense;
    if (edge < 0) {
        if (grow_info(bd))
            return cb_error_set(err, CB_ERR_NOMEM, "bool: out of memory");
        edge = cb_topo_body_add_edge(b);
        int cv = cb_topo_body_add_curve(b);
        if (edge < 0 || cv < 0)
            return cb_error_set(err, CB_ERR_NOMEM, "bool: out of memory");
        cb_topo_edge *e = b->edges + edge;
        e->curve = cv;
        e->same_sense = 1;
        e->t0 = fmin(g.t_start, g.t_end);
        e->t1 = fmax(g.t_start, g.t_end);
        e->v[0] = lo;
        e->v[1] = hi;
        e->tol = b->tol;
        cb_status st;
        if (g.cut) {
            st = copy_curve(b->curves + cv, bd->cut_curve + s->index, err);
        } else {
            const cb_topo_edge *oe = X->edges + X->coedges[s->index].edge;
            st = copy_curve(b->curves + cv, X->curves + oe->curve, err);
        }
        if (st)
            return st;
        memcpy(bd->info[edge].mid, g.mid, sizeof g.mid);
        bd->info[edge].uses = 0;
        bd->info[edge].cut = g.cut;
        bd->info[edge].side = r->side;
        bd->info[edge].src = g.src;
        bd->info[edge].reserved = partnered;
    }
    const edge_info *in = bd->info + edge;
    int own_curve = same_source(in, &key);
    if (own_curve) {
        /* The edge's curve is this piece's own (the same cut's positions, or the same
         * original edge's curve): along the edge when the traversal runs up the curve. */
        sense = g.t_start < g.t_end;
    } else {
        /* Sewn onto the curve of another source (a face's edge and the cut a coincident face
         * drew along it): along the edge when two points of the traversal, a quarter from
         * each end, project onto the edge's curve in increasing order. */
        const cb_topo_edge *e = b->edges + edge;
        double q[3], s1, s2;
        cb_topo_curve_eval(q, g.curve, g.t_start + 0.25 * (g.t_end - g.t_start));
        cb_topo_curve_project(&s1, b->curves + e->curve, q, e->t0, e->t1);
        cb_topo_curve_eval(q, g.curve, g.t_start + 0.75 * (g.t_end - g.t_start));
        cb_topo_curve_project(&s2, b->curves + e->curve, q, e->t0, e->t1);
        sense = s1 < s2;
    }
    bd->info[edge].uses++;
    int co = cb_topo_body_add_coedge(b);
    if (co < 0)
        return cb_error_set(err, CB_ERR_NOMEM, "bool: out of memory");
    if (co >= bd->cap_mid) {
        int cap = bd->cap_mid ? 2 * bd->cap_mid : 256;
        double *q = realloc(bd->mid_uv, (size_t)cap * 2 * sizeof(double));
        if (!q)
            return cb_error_set(err, CB_ERR_NOMEM, "bool: out of memory");
        bd->mid_uv = q;
        bd->cap_mid = cap;
    }
    /* A cut piece on the curve it was made from takes the cut's pcurve (the same
     * parameter), a piece of the face's own edge that edge's pcurve (copied, lifted to the
     * piece's middle); any other piece gets one computed later, lifted likewise. */
    int cut_pcurve = g.cut && own_curve;
    if (cut_pcurve)
        bd->mid_uv[2 * co] = bd->mid_uv[2 * co + 1] = NAN;
    else
        at_pos(bd->mid_uv + 2 * co, s->uv, s->n, 2, 0.5 * (p->pos0 + p->pos1));
    b->coedges[co].edge = edge;
    b->coedges[co].sense = sense;
    b->coedges[co].loop = loop;
    b->coedges[co].pcurve = -1;
    if (cut_pcurve) {
        int pc = cb_topo_body_add_pcurve(b);
        if (pc < 0)
            return cb_error_set(err, CB_ERR_NOMEM, "bool: out of memory");
        cb_status st = cb_bool_cut_curve(b->pcurves + pc, cuts->cut + s->index, r->side, err);
        if (st)
            return st;
        b->coedges[co].pcurve = pc;
    } else if (!g.cut && own_curve && X->coedges[s->index].pcurve >= 0 &&
               cb_topo_pcurve_convention_gap(X->pcurves + X->coedges[s->index].pcurve, b, edge,
                                             inv, b->tol) <= b->tol) {
        /* A piece of one of the face's own edges, on that edge's curve, whose pcurve follows
         * the edge's parameter within the body's tolerance: it holds the piece exactly;
         * fitting one again by inversion can fail near a crease of the surface. Lifted to
         * the piece's middle like a computed one. A pcurve that follows it only within a
         * raised edge tolerance (a file's) would put the piece's end, at the edge parameter
         * of a cut's end, that far along the pcurve from the cut's end in (u, v): the loop
         * would not close, and the face's area would be off by the gap's share. */
        int pc = cb_topo_body_add_pcurve(b);
        if (pc < 0)
            return cb_error_set(err, CB_ERR_NOMEM, "bool: out of memory");
        cb_status st = copy_curve(b->pcurves + pc, X->pcurves + X->coedges[s->index].pcurve, err);
        if (st)
            return st;
        b->coedges[co].pcurve = pc;
    }
    return CB_OK;
}

/* (u, v) of coedge co's middle in its face's window: the piece's middle, or for a cut piece
 * its pcurve at the middle of its edge's range. */
static void coedge_mid_uv(double uv[2], const builder *bd, int co)
{
    const cb_topo_body *b = bd->b;
    if (!isnan(bd->mid_uv[2 * co])) {
        uv[0] = bd->mid_uv[2 * co];
        uv[1] = bd->mid_uv[2 * co + 1];
        return;
    }
    const cb_topo_edge *e = b->edges + b->coedges[co].edge;
    double w[3];
    cb_topo_pcurve_eval(w, b->pcurves + b->coedges[co].pcurve, 0.5 * (e->t0 + e->t1));
    uv[0] = w[0];
    uv[1] = w[1];
}

/* Whether face f folds onto itself: each of its coedges lies on an edge whose only other use is
 * a coedge of f running the other way with its middle at the same place in (u, v), less than
 * half a period away (the two sides of a seam are a period apart). Such a face is a sliver
 * whose two sides, from different curves less than the weld distance apart, were sewn onto the
 * same edges: it bounds nothing. */
static int face_folds(const builder *bd, int f, const cb_topo_inverter *inv)
{
    const cb_topo_body *b = bd->b;
    const cb_topo_face *F = b->faces + f;
    int first = b->loops[F->first].first, end = b->n_coedges;
    if (end == first)
        return 0;
    for (int c = first; c < end; c++) {
        const cb_topo_coedge *C = b->coedges + c;
        if (bd->info[C->edge].uses != 2)
            return 0;
        int partner = -1;
        for (int o = first; o < end && partner < 0; o++)
            if (o != c && b->coedges[o].edge == C->edge && b->coedges[o].sense != C->sense)
                partner = o;
        if (partner < 0)
            return 0;
        double a[2], z[2];
        coedge_mid_uv(a, bd, c);
        coedge_mid_uv(z, bd, partner);
        for (int i = 0; i < 2; i++)
            if (!(fabs(a[i] - z[i]) < (inv->period[i] > 0 ? 0.5 * inv->period[i] : INFINITY)))
                return 0;
    }
    return 1;
}

/* Moves pcurve pc by (du, dv). */
static void shift_pcurve(cb_topo_curve *pc, double du, double dv)
{
    if (pc->kind == CB_CURVE_NURBS) {
        for (int i = 0; i < pc->nurbs->n; i++) {
            double *w = pc->nurbs->cw + 4 * i;
            w[0] += du * w[3];
            w[1] += dv * w[3];
        }
    } else {
        pc->frame.o[0] += du;
        pc->frame.o[1] += dv;
    }
}

/* cb_topo_compute_pcurves places each loop in a lift of its own choosing, and the two sides
 * of a seam by a rule of its own: shift every computed pcurve by whole periods to the lift of
 * the piece it was made for, the face's window in which the face was split. */
static cb_status lift_pcurves(builder *bd, cb_error *err)
{
    cb_topo_body *b = bd->b;
    for (int f = 0; f < b->n_faces; f++) {
        cb_topo_inverter inv;
        cb_status st = cb_topo_inverter_init(&inv, b->surfaces + b->faces[f].surface, b->tol, err);
        if (st)
            return st;
        for (int l = b->faces[f].first; l < b->faces[f].first + b->faces[f].count; l++)
            for (int c = b->loops[l].first; c < b->loops[l].first + b->loops[l].count; c++) {
                const double *target = bd->mid_uv + 2 * c;
                if (isnan(target[0]) || b->coedges[c].pcurve < 0)
                    continue;
                cb_topo_curve *pc = b->pcurves + b->coedges[c].pcurve;
                double q[3], d[2] = {0, 0}, s0, s1;
                /* the part the coedge uses: a copied pcurve from a file may be
                 * parameterised otherwise than the edge */
                cb_topo_coedge_pcurve_range(&s0, &s1, b, c, &inv, b->tol);
                cb_topo_pcurve_eval(q, pc, 0.5 * (s0 + s1));
                for (int k = 0; k < 2; k++)
                    if (inv.lift[k] > 0)
                        d[k] = inv.lift[k] * nearbyint((target[k] - q[k]) / inv.lift[k]);
                if (d[0] != 0 || d[1] != 0)
                    shift_pcurve(pc, d[0], d[1]);
            }
        cb_topo_inverter_clear(&inv);
    }
    return CB_OK;
}

/* ---------------------------------------------------------------- T-junctions ------------- */

typedef struct {
    int face, region, piece; /* where the piece sits */
    piece_geom g;
    cb_aabb box; /* of 9 points of its curve, grown by the weld distance */
    double *split; /* source positions to split at */
    int n_split, cap_split;
} piece_rec;

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static int rec_lo(const piece_rec *r)
{
    return r->g.v_start < r->g.v_end ? r->g.v_start : r->g.v_end;
}

static int rec_hi(const piece_rec *r)
{
    return r->g.v_start < r->g.v_end ? r->g.v_end : r->g.v_start;
}

static int same_ends(const piece_rec *x, const piece_rec *y)
{
    return rec_lo(x) == rec_lo(y) && rec_hi(x) == rec_hi(y);
}

/* Whether p lies within weld of record y's curve (between its ends). */
static int same_curve(const piece_rec *y, const double p[3], double weld)
{
    const piece_geom *g = &y->g;
    return range_distance(g->curve, fmin(g->t_start, g->t_end), fmax(g->t_start, g->t_end), p) <=
           weld;
}

/* A record's end vertices (lower first) and index, to sort by. */
typedef struct {
    int lo, hi, i;
} rec_key;

static int cmp_rec_key(const void *a, const void *b)
{
    const rec_key *x = a, *y = b;
    if (x->lo != y->lo)
        return x->lo < y->lo ? -1 : 1;
    if (x->hi != y->hi)
        return x->hi < y->hi ? -1 : 1;
    return (x->i > y->i) - (x->i < y->i);
}

/* Position along boundary source s between pos a and z whose surface point projects onto the
 * edge curve C at t (the projection is monotone along the piece): bisection. */
static double boundary_pos(const op_src *s, const cb_topo_inverter *inv, const cb_topo_curve *C,
                           const cb_topo_edge *e, double a, double z, double ta, double tz,
                           double t)
{
    for (int it = 0; it < 50; it++) {
        double m = 0.5 * (a + z), uv[2], q[3], tm;
        at_pos(uv, s->uv, s->n, 2, m);
        cb_topo_inverter_eval(q, inv, uv[0], uv[1]);
        cb_topo_curve_project(&tm, C, q, e->t0, e->t1);
        if (C->kind == CB_CURVE_CIRCLE || C->kind == CB_CURVE_ELLIPSE) {
            while (tm < fmin(ta, tz) - 1e-12)
                tm += 2 * CB_SSI_PI;
            while (tm > fmax(ta, tz) + 1e-12)
                tm -= 2 * CB_SSI_PI;
        }
        if ((tm < t) == (ta < tz))
            a = m;
        else
            z = m;
    }
    return 0.5 * (a + z);
}

/* Every piece of the kept regions that makes an edge (not one welded into a point, see
 * add_coedge), with its geometry, in face, region and piece order: *out (*m of them, to be
 * freed). The pieces' end vertices are welded here: all vertices exist after it. */
static cb_status edge_pieces(piece_rec **out, int *m, builder *bd, const op_face *faces,
                             int n_faces, const cb_topo_body *A, const cb_topo_body *B,
                             double tol, cb_error *err)
{
    int n = 0;
    for (int fi = 0; fi < n_faces; fi++)
        for (int ri = 0; ri < faces[fi].n_regions; ri++)
            n += faces[fi].regions[ri].loop_start[faces[fi].regions[ri].n_loops];
    piece_rec *rec = *out = calloc((size_t)n + 1, sizeof *rec);
    *m = 0;
    if (!rec)
        return cb_error_set(err, CB_ERR_NOMEM, "bool: out of memory");
    cb_status st = CB_OK;
    for (int fi = 0; fi < n_faces && !st; fi++) {
        const op_face *of = faces + fi;
        if (!of->n_regions)
            continue;
        const cb_topo_body *X = of->side ? B : A;
        cb_topo_inverter inv;
        st = cb_topo_inverter_init(&inv, X->surfaces + X->faces[of->face].surface, tol, err);
        for (int ri = 0; ri < of->n_regions && !st; ri++) {
            const op_region *r = of->regions + ri;
            for (int k = 0; k < r->loop_start[r->n_loops] && !st; k++) {
                if (r->srcs[r->pieces[k].src].kind == OP_JOIN)
                    continue;
                piece_geom g;
                st = piece_ends(&g, bd, r, r->pieces + k, X, &inv, err);
                if (st) {
                    st = st == CB_ERR_NOMEM ? cb_error_set(err, st, "bool: out of memory") : st;
                    break;
                }
                if (g.v_start == g.v_end && dist3(g.mid, bd->b->vertices[g.v_start].p) <= bd->weld)
                    continue;
                rec[(*m)++] = (piece_rec){.face = fi, .region = ri, .piece = k, .g = g};
            }
        }
        cb_topo_inverter_clear(&inv);
    }
    return st;
}

/* Every piece that makes an edge, sorted by key, into bd->keys (has_partner). */
static cb_status count_sources(builder *bd, const op_face *faces, int n_faces,
                               const cb_topo_body *A, const cb_topo_body *B, double tol,
                               cb_error *err)
{
    piece_rec *rec;
    int m;
    cb_status st = edge_pieces(&rec, &m, bd, faces, n_faces, A, B, tol, err);
    bd->keys = st ? NULL : malloc((size_t)(m + 1) * sizeof *bd->keys);
    if (!st && !bd->keys)
        st = cb_error_set(err, CB_ERR_NOMEM, "bool: out of memory");
    for (int i = 0; i < m && !st; i++) {
        const piece_geom *g = &rec[i].g;
        int side = faces[rec[i].face].regions[rec[i].region].side;
        bd->keys[i] = (source_piece){key_of(g, side, rec_lo(rec + i), rec_hi(rec + i)), g->curve,
                                     fmin(g->t_start, g->t_end), fmax(g->t_start, g->t_end)};
    }
    if (!st) {
        bd->n_keys = m;
        qsort(bd->keys, (size_t)m, sizeof *bd->keys, cmp_source_key);
    }
    free(rec);
    return st;
}

/* Splits region pieces where a vertex of another piece lies inside them (within weld of the
 * piece's curve, farther than weld from its ends): the two sides of a curve are split at the
 * same points only when they see the same cuts, which coincident faces break (a face's edge
 * along a circle that a coincident face's imprint and a third face's curve split at
 * different points). Each such piece becomes two or more, in traversal order. */
static cb_status split_t_junctions(builder *bd, op_face *faces, int n_faces,
                                   const cb_topo_body *A, const cb_topo_body *B, double tol,
                                   cb_error *err)
{
    piece_rec *rec;
    int m;
    cb_status st = edge_pieces(&rec, &m, bd, faces, n_faces, A, B, tol, err);
    if (st) {
        free(rec);
        return st;
    }
    /* Pass 1: every piece's box: 9 samples, grown by half the longest chord between them (the
     * curve bulges past its samples: a circle's lowest point between two of them, where
     * another face's cut ended, was outside the box and was never split). */
    for (int i = 0; i < m; i++) {
        piece_rec *pr = rec + i;
        const piece_geom *g = &pr->g;
        double q[27], chord = 0;
        for (int j = 0; j <= 8; j++) {
            cb_topo_curve_eval(q + 3 * j, g->curve, g->t_start + (g->t_end - g->t_start) * j / 8);
            if (j)
                chord = fmax(chord, dist3(q + 3 * j, q + 3 * j - 3));
        }
        cb_aabb_of_points(&pr->box, q, 9, 3);
        for (int k = 0; k < 3; k++) {
            pr->box.lo[k] -= bd->weld + 0.5 * chord;
            pr->box.hi[k] += bd->weld + 0.5 * chord;
        }
    }
    /* Pieces that will sew (another with the same ends and midpoint) stay whole; the others
     * may be split, at the ends of other unsewn pieces only. */
    const cb_topo_body *b = bd->b;
    rec_key *order = malloc((size_t)(m + 1) * sizeof *order);
    char *lone = calloc((size_t)m + 1, 1), *end_v = calloc((size_t)b->n_vertices + 1, 1);
    if (!st && (!order || !lone || !end_v))
        st = cb_error_set(err, CB_ERR_NOMEM, "bool: out of memory");
    for (int i = 0; i < m && !st; i++)
        order[i] = (rec_key){rec_lo(rec + i), rec_hi(rec + i), i};
    if (!st)
        qsort(order, (size_t)m, sizeof *order, cmp_rec_key);
    for (int a = 0; a < m && !st; a++) {
        const piece_rec *x = rec + order[a].i;
        int paired = 0;
        for (int z = a - 1; z >= 0 && !paired && same_ends(x, rec + order[z].i); z--)
            paired = same_curve(rec + order[z].i, x->g.mid, bd->weld);
        for (int z = a + 1; z < m && !paired && same_ends(x, rec + order[z].i); z++)
            paired = same_curve(rec + order[z].i, x->g.mid, bd->weld);
        if (!paired) {
            lone[order[a].i] = 1;
            end_v[x->g.v_start] = end_v[x->g.v_end] = 1;
        }
    }
    /* Pass 2: the vertices inside each lone piece, as positions along its source. */
    for (int i = 0; i < m && !st; i++) {
        piece_rec *pr = rec + i;
        if (!lone[i])
            continue;
        const piece_geom *g = &pr->g;
        const op_face *of = faces + pr->face;
        const op_region *r = of->regions + pr->region;
        const cb_topo_body *X = of->side ? B : A;
        cb_topo_inverter inv;
        int have_inv = 0;
        for (int v = 0; v < b->n_vertices && !st; v++) {
            const double *P = b->vertices[v].p;
            if (!end_v[v] || v == g->v_start || v == g->v_end || P[0] < pr->box.lo[0] ||
                P[0] > pr->box.hi[0] || P[1] < pr->box.lo[1] || P[1] > pr->box.hi[1] ||
                P[2] < pr->box.lo[2] || P[2] > pr->box.hi[2])
                continue;
            double t, lo = fmin(g->t_start, g->t_end), hi = fmax(g->t_start, g->t_end);
            double d = g->cut ? cb_bool_cut_project(&t, bd->cuts->cut + g->src, P, lo, hi)
                              : cb_topo_curve_project(&t, g->curve, P, lo, hi);
            /* A conic's projection is in [0, 2 pi); the piece's range may start below 0 (a
             * sphere's seam meridian runs over [-pi/2, pi/2]): the lift in [lo, lo + 2 pi). */
            if (g->curve->kind == CB_CURVE_CIRCLE || g->curve->kind == CB_CURVE_ELLIPSE)
                t -= 2 * CB_SSI_PI * floor((t - lo) / (2 * CB_SSI_PI));
            if (d > bd->weld || !(t > lo && t < hi) ||
                dist3(P, b->vertices[g->v_start].p) <= bd->weld ||
                dist3(P, b->vertices[g->v_end].p) <= bd->weld)
                continue;
            double pos = t;
            const op_piece *p = r->pieces + pr->piece;
            const op_src *s = r->srcs + p->src;
            if (!g->cut) {
                if (!have_inv) {
                    st = cb_topo_inverter_init(&inv, X->surfaces + X->faces[of->face].surface,
                                               tol, err);
                    if (st)
                        break;
                    have_inv = 1;
                }
                double a = p->fwd ? p->pos0 : p->pos1, z = p->fwd ? p->pos1 : p->pos0;
                const cb_topo_edge *e = X->edges + X->coedges[s->index].edge;
                pos = boundary_pos(s, &inv, g->curve, e, a, z, g->t_start, g->t_end, t);
            }
            if (pr->n_split == pr->cap_split) {
                int cap = pr->cap_split ? 2 * pr->cap_split : 8;
                double *q = realloc(pr->split, (size_t)cap * sizeof *q);
                if (!q) {
                    st = cb_error_set(err, CB_ERR_NOMEM, "bool: out of memory");
                    break;
                }
                pr->split = q;
                pr->cap_split = cap;
            }
            pr->split[pr->n_split++] = pos;
        }
        if (have_inv)
            cb_topo_inverter_clear(&inv);
    }
    free(order);
    free(lone);
    free(end_v);
    /* Replace each split piece by its parts, region by region. */
    for (int i = 0; i < m && !st; i++) {
        if (!rec[i].n_split)
            continue;
        op_region *r = faces[rec[i].face].regions + rec[i].region;
        int total = r->loop_start[r->n_loops], add = rec[i].n_split;
        op_piece *q = realloc(r->pieces, (size_t)(total + add) * sizeof *q);
        if (!q) {
            st = cb_error_set(err, CB_ERR_NOMEM, "bool: out of memory");
            break;
        }
        r->pieces = q;
        int k = rec[i].piece;
        op_piece p = q[k];
        memmove(q + k + 1 + add, q + k + 1, (size_t)(total - k - 1) * sizeof *q);
        /* Positions pos0 < splits (sorted) < pos1; the parts in traversal order. */
        double *cut = rec[i].split;
        for (int a = 0; a < add; a++)
            cut[a] = fmin(fmax(cut[a], p.pos0), p.pos1);
        qsort(cut, (size_t)add, sizeof *cut, cmp_double);
        for (int j = 0; j <= add; j++) {
            int at = p.fwd ? j : add - j;
            double a = at ? cut[at - 1] : p.pos0, z = at < add ? cut[at] : p.pos1;
            q[k + j] = (op_piece){p.src, a, z, p.fwd};
        }
        for (int l = 0; l <= r->n_loops; l++)
            if (r->loop_start[l] > k)
                r->loop_start[l] += add;
        /* Later records of this region point past the inserted pieces. */
        for (int j = i + 1; j < m; j++)
            if (rec[j].face == rec[i].face && rec[j].region == rec[i].region && rec[j].piece > k)
                rec[j].piece += add;
    }
    for (int i = 0; i < m; i++)
        free(rec[i].split);
    free(rec);
    return st;
}

cb_status _cb_bool_build(cb_topo_body **out, int *unmatched, char *where, size_t n_where,
                         op_face *faces, int n_faces,
                         const cb_topo_body *A, const cb_topo_body *B, const cb_bool_cuts *cuts,
                         double tol, double weld, cb_error *err)
{
    *out = NULL;
    *unmatched = 0;
    builder bd = {cb_topo_body_new(), NULL, 0, weld, cuts,
                  calloc((size_t)cuts->n + 1, sizeof(cb_topo_curve)), calloc((size_t)cuts->n + 1, 1),
                  NULL, 0, NULL, 0};
    if (!bd.b || !bd.cut_curve || !bd.cut_made) {
        cb_topo_body_free(bd.b);
        free(bd.cut_curve);
        free(bd.cut_made);
        return cb_error_set(err, CB_ERR_NOMEM, "bool: out of memory");
    }
    for (int k = 0; k < cuts->n; k++)
        cb_topo_curve_init(bd.cut_curve + k);
    cb_topo_body *b = bd.b;
    b->tol = tol;
    b->length_unit_mm = A->length_unit_mm;
    int solid = cb_topo_body_add_solid(b), shell = cb_topo_body_add_shell(b);
    cb_status st = solid < 0 || shell < 0 ? cb_error_set(err, CB_ERR_NOMEM, "bool: out of memory")
                                          : CB_OK;
    if (!st) {
        b->solids[solid].first = shell;
        b->solids[solid].count = 1;
        b->shells[shell].solid = solid;
        b->shells[shell].closed = 1;
        b->shells[shell].first = 0;
    }
    if (!st)
        st = split_t_junctions(&bd, faces, n_faces, A, B, tol, err);
    if (!st)
        st = count_sources(&bd, faces, n_faces, A, B, tol, err);
    for (int fi = 0; fi < n_faces && !st; fi++) {
        const op_face *of = faces + fi;
        if (of->n_regions == 0)
            continue;
        const cb_topo_body *X = of->side ? B : A;
        const cb_topo_face *xf = X->faces + of->face;
        cb_topo_inverter inv;
        st = cb_topo_inverter_init(&inv, X->surfaces + xf->surface, tol, err);
        if (st)
            break;
        for (int ri = 0; ri < of->n_regions && !st; ri++) {
            const op_region *r = of->regions + ri;
            int n_edges = b->n_edges, n_curves = b->n_curves, n_pcurves = b->n_pcurves;
            int n_coedges = b->n_coedges;
            int sf = cb_topo_body_add_surface(b), f = cb_topo_body_add_face(b);
            if (sf < 0 || f < 0) {
                st = cb_error_set(err, CB_ERR_NOMEM, "bool: out of memory");
                break;
            }
            st = copy_surface(b->surfaces + sf, X->surfaces + xf->surface, err);
            b->faces[f].surface = sf;
            b->faces[f].same_sense = xf->same_sense ^ r->flip;
            b->faces[f].shell = shell;
            b->faces[f].first = b->n_loops;
            b->faces[f].count = 0;
            for (int l = 0; l < r->n_loops && !st; l++) {
                int lp = cb_topo_body_add_loop(b);
                if (lp < 0) {
                    st = cb_error_set(err, CB_ERR_NOMEM, "bool: out of memory");
                    break;
                }
                b->loops[lp].face = f;
                b->loops[lp].outer = l == 0;
                b->loops[lp].first = b->n_coedges;
                for (int k = r->loop_start[l]; k < r->loop_start[l + 1] && !st; k++)
                    if (r->srcs[r->pieces[k].src].kind != OP_JOIN)
                        st = add_coedge(&bd, lp, r, r->pieces + k, X, cuts, &inv, err);
                b->loops[lp].count = b->n_coedges - b->loops[lp].first;
                b->faces[f].count++;
            }
            int empty = !st;
            for (int l = b->faces[f].first; l < b->faces[f].first + b->faces[f].count && empty; l++)
                empty = b->loops[l].count == 0;
            if (!st && !empty && face_folds(&bd, f, &inv)) {
                /* Its edges with their curves and pcurves are its own (no other face uses
                 * them): they go with it. The neighbours' pieces along the sliver's sides are
                 * sewn to each other, as they would have been had it come after them. */
                for (int k = n_curves; k < b->n_curves; k++)
                    cb_topo_curve_clear(b->curves + k);
                for (int k = n_pcurves; k < b->n_pcurves; k++)
                    cb_topo_curve_clear(b->pcurves + k);
                b->n_edges = n_edges;
                b->n_curves = n_curves;
                b->n_pcurves = n_pcurves;
                b->n_coedges = n_coedges;
                empty = 1;
            }
            if (empty) {
                /* Every piece of the region welded into a point (a sliver between a cut and the
                 * boundary, narrower than the weld distance), or the region folds onto itself:
                 * no face. The other side's pieces along it weld into the same points. */
                b->n_loops = b->faces[f].first;
                b->n_faces--;
                cb_topo_surface_clear(b->surfaces + sf);
                b->n_surfaces--;
            }
        }
        cb_topo_inverter_clear(&inv);
    }
    if (!st) {
        b->shells[shell].count = b->n_faces;
        if (b->n_faces == 0)
            b->n_solids = b->n_shells = 0; /* the empty result: no solid at all */
        for (int e = 0; e < b->n_edges; e++) {
            const edge_info *in = bd.info + e;
            if (in->uses == 2)
                continue;
            if ((*unmatched)++ == 0 && n_where > 0) {
                char what[64];
                if (in->cut)
                    snprintf(what, sizeof what, "intersection curve %d", in->src);
                else
                    snprintf(what, sizeof what, "%s's edge %d", in->side ? "B" : "A", in->src);
                snprintf(where, n_where,
                         "first near (%.9g, %.9g, %.9g): a piece of %s (faces using it: %d)",
                         in->mid[0], in->mid[1], in->mid[2], what, in->uses);
            }
        }
        for (int e = 0; e < b->n_edges; e++)
            b->edges[e].tol = fmax(b->tol, weld);
        st = cb_topo_body_index(b, err);
    }
    if (!st && !*unmatched)
        st = cb_topo_compute_pcurves(b, tol, err);
    if (!st && !*unmatched)
        st = lift_pcurves(&bd, err);
    if (!st && !*unmatched)
        st = _cb_bool_split_shells(b, err);
    if (!st && !*unmatched)
        st = cb_topo_body_index(b, err);
    free(bd.info);
    free(bd.mid_uv);
    free(bd.keys);
    for (int k = 0; k < cuts->n; k++)
        cb_topo_curve_clear(bd.cut_curve + k);
    free(bd.cut_curve);
    free(bd.cut_made);
    if (st) {
        cb_topo_body_free(b);
        return st;
    }
    *out = b;
    return CB_OK;
}
