/* Trimmed faces: preparation (loop polygons with deviation bounds, boundary edges, sample
 * cells), the inside/outside/on test in (u, v), the distance to the face and its normal. */
#include <stdlib.h>
#include <string.h>

#include "brep/face.h"

enum {
    N_START_PIECES = 8, /* pieces per curved pcurve before refinement */
    MAX_SAMPLE_DEPTH = 8,
    MAX_QUERY_DEPTH = 48,
    N_EDGE_SAMPLES = 32
};

/* A polygon piece is accepted when its measured deviation is below this fraction of its
 * chord: queries refine near the point, so the polygon only needs to be right far from it. */
static const double FLAT = 0.05;

/* ---------------------------------------------------------------- preparation -------------- */

typedef struct {
    cb_face_seg *s;
    int n, cap;
} seg_list;

static cb_status push_seg(seg_list *l, const cb_face_seg *sg, cb_error *err)
{
    if (l->n == l->cap) {
        int c = l->cap ? 2 * l->cap : 64;
        cb_face_seg *p = realloc(l->s, (size_t)c * sizeof *p);
        if (!p)
            return cb_error_set(err, CB_ERR_NOMEM, "face: out of memory");
        l->s = p;
        l->cap = c;
    }
    l->s[l->n++] = *sg;
    return CB_OK;
}

static void pc_point(double w[2], const cb_topo_curve *pc, double s, const double shift[2])
{
    double q[3];
    cb_topo_pcurve_eval(q, pc, s);
    w[0] = q[0] + shift[0];
    w[1] = q[1] + shift[1];
}

/* Distance from w to the segment p q in (u, v). */
static double seg_dist(const double w[2], const double p[2], const double q[2])
{
    double dx = q[0] - p[0], dy = q[1] - p[1], l2 = dx * dx + dy * dy, t = 0;
    if (l2 > 0)
        t = fmin(1, fmax(0, ((w[0] - p[0]) * dx + (w[1] - p[1]) * dy) / l2));
    return hypot(w[0] - p[0] - t * dx, w[1] - p[1] - t * dy);
}

/* Appends pcurve pieces over [s0, s1], bisected until their deviation at 3 inner points is
 * below FLAT of the chord. */
static cb_status sample_piece(seg_list *l, const cb_topo_curve *pc, int c, double s0, double s1,
                              const double p[2], const double q[2], const double shift[2],
                              int depth, cb_error *err)
{
    double dev = 0, w[2], mid[2] = {0, 0};
    for (int k = 1; k <= 3; k++) {
        pc_point(w, pc, s0 + (s1 - s0) * k / 4, shift);
        dev = fmax(dev, seg_dist(w, p, q));
        if (k == 2)
            memcpy(mid, w, sizeof mid);
    }
    double chord = hypot(q[0] - p[0], q[1] - p[1]);
    if (dev > FLAT * chord && depth < MAX_SAMPLE_DEPTH) {
        double sm = 0.5 * (s0 + s1);
        cb_status st = sample_piece(l, pc, c, s0, sm, p, mid, shift, depth + 1, err);
        return st ? st : sample_piece(l, pc, c, sm, s1, mid, q, shift, depth + 1, err);
    }
    double scale = fabs(p[0]) + fabs(p[1]) + fabs(q[0]) + fabs(q[1]);
    cb_face_seg sg = {.p = {p[0], p[1]}, .q = {q[0], q[1]}, .s0 = s0, .s1 = s1,
                      .shift = {shift[0], shift[1]}, .dev = 1.5 * dev + 1e-13 * scale,
                      .coedge = c};
    return push_seg(l, &sg, err);
}

static cb_status push_join(seg_list *l, const double p[2], const double q[2], cb_error *err)
{
    if (p[0] == q[0] && p[1] == q[1])
        return CB_OK;
    cb_face_seg sg = {.p = {p[0], p[1]}, .q = {q[0], q[1]}, .coedge = -1};
    return push_seg(l, &sg, err);
}

/* Whole periods k[i] that move b nearest a; zero when a -> b closes on the surface. */
static void periods_between(int k[2], const cb_topo_inverter *inv, const double a[2],
                            const double b[2], double tol)
{
    k[0] = k[1] = 0;
    if (cb_topo_inverter_spread(inv, a, b) <= tol)
        return;
    for (int i = 0; i < 2; i++)
        if (inv->lift[i] > 0)
            k[i] = (int)round((a[i] - b[i]) / inv->lift[i]);
}

/* The extent {lo, hi} of segments [a, z) of s in direction i. */
static void seg_extent(double e[2], const cb_face_seg *s, int a, int z, int i)
{
    e[0] = HUGE_VAL;
    e[1] = -HUGE_VAL;
    for (int k = a; k < z; k++) {
        e[0] = fmin(e[0], fmin(s[k].p[i], s[k].q[i]));
        e[1] = fmax(e[1], fmax(s[k].p[i], s[k].q[i]));
    }
}

/* Samples the loops into f->segs; wraps[l] receives how many periods loop l goes around. */
static cb_status sample_loops(cb_face *f, int (*wraps)[2], cb_error *err)
{
    const cb_topo_body *b = f->b;
    const cb_topo_face *fc = &b->faces[f->face];
    const cb_topo_inverter *inv = &f->inv;
    seg_list l = {0};
    cb_status st = CB_OK;
    int end0 = 0; /* the first loop's segments end here */
    for (int li = 0; li < fc->count && !st; li++) {
        const cb_topo_loop *lp = &b->loops[fc->first + li];
        int first_seg = l.n;
        double first[2] = {0, 0}, prev[2] = {0, 0};
        for (int c = lp->first; c < lp->first + lp->count && !st; c++) {
            const cb_topo_coedge *co = &b->coedges[c];
            if (co->pcurve < 0 || co->pcurve >= b->n_pcurves) {
                st = cb_error_set(err, CB_ERR_INVALID, "face %d: coedge %d has no pcurve",
                                  f->face, c);
                break;
            }
            const cb_topo_curve *pc = &b->pcurves[co->pcurve];
            double s0, s1, e_tol = fmax(f->tol, b->edges[co->edge].tol);
            cb_topo_coedge_pcurve_range(&s0, &s1, b, c, inv, e_tol);
            double zero[2] = {0, 0}, w[2], shift[2];
            int k[2] = {0, 0};
            pc_point(w, pc, s0, zero);
            if (c > lp->first)
                periods_between(k, inv, prev, w, f->tol);
            shift[0] = k[0] * inv->lift[0];
            shift[1] = k[1] * inv->lift[1];
            double p[2] = {w[0] + shift[0], w[1] + shift[1]};
            if (c > lp->first)
                st = push_join(&l, prev, p, err);
            else
                memcpy(first, p, sizeof first);
            int n = pc->kind == CB_CURVE_LINE ? 1 : N_START_PIECES;
            if (pc->kind == CB_CURVE_NURBS)
                n = (int)fmin(64, fmax(n, 2 * (pc->nurbs->n - pc->nurbs->deg)));
            for (int j = 0; j < n && !st; j++) {
                double q[2], sa = s0 + (s1 - s0) * j / n, sb = s0 + (s1 - s0) * (j + 1) / n;
                pc_point(q, pc, sb, shift);
                st = sample_piece(&l, pc, c, sa, sb, p, q, shift, 0, err);
                memcpy(p, q, sizeof p);
            }
            memcpy(prev, p, sizeof prev);
        }
        if (st || l.n == first_seg)
            continue;
        int k[2];
        periods_between(k, inv, prev, first, f->tol);
        double close[2] = {first[0] + k[0] * inv->lift[0], first[1] + k[1] * inv->lift[1]};
        st = push_join(&l, prev, close, err);
        wraps[li][0] = k[0];
        wraps[li][1] = k[1];
        if (li == 0)
            end0 = l.n;
        /* Loops that do not go around a period share the first loop's range there: the lift
         * that brings their middle nearest the first loop's middle. (The first loop's first
         * point, used before, lies at the range's end on a band whose outer loop starts on
         * its seam: a slot half a period away was placed a period off, outside the band.) */
        for (int i = 0; i < 2 && li > 0 && end0 > 0 && l.n > first_seg; i++) {
            double P = inv->lift[i];
            if (P <= 0 || k[i] != 0)
                continue;
            double m0[2], m1[2];
            seg_extent(m0, l.s, 0, end0, i);
            seg_extent(m1, l.s, first_seg, l.n, i);
            double sh = P * round((0.5 * (m0[0] + m0[1]) - 0.5 * (m1[0] + m1[1])) / P);
            for (int s = first_seg; s < l.n; s++) {
                l.s[s].p[i] += sh;
                l.s[s].q[i] += sh;
                l.s[s].shift[i] += sh;
            }
        }
    }
    f->segs = l.s;
    f->n_segs = l.n;
    /* Latitudes written past a pole (v - 2 pi): the loops moved by whole lifts so that their
     * middle lies in the surface's box, where inversion returns points. */
    for (int i = 0; i < 2 && !st && l.n; i++) {
        double L = inv->lift[i], lo = HUGE_VAL, hi = -HUGE_VAL;
        if (L <= 0 || inv->period[i] > 0 || !isfinite(inv->box[2 * i] + inv->box[2 * i + 1]))
            continue;
        for (int k = 0; k < l.n; k++) {
            lo = fmin(lo, fmin(l.s[k].p[i], l.s[k].q[i]));
            hi = fmax(hi, fmax(l.s[k].p[i], l.s[k].q[i]));
        }
        double mid = 0.5 * (inv->box[2 * i] + inv->box[2 * i + 1]);
        double sh = L * round((mid - 0.5 * (lo + hi)) / L);
        for (int k = 0; k < l.n && sh != 0; k++) {
            l.s[k].p[i] += sh;
            l.s[k].q[i] += sh;
            l.s[k].shift[i] += sh;
        }
    }
    return st;
}

/* The distinct edges of the face, with boxes; boundary ones are not seams of this face and
 * not collapsed. */
static cb_status boundary_edges(cb_face *f, cb_error *err)
{
    const cb_topo_body *b = f->b;
    const cb_topo_face *fc = &b->faces[f->face];
    int n = 0;
    for (int l = fc->first; l < fc->first + fc->count; l++)
        n += b->loops[l].count;
    f->edges = malloc((size_t)(n ? n : 1) * sizeof *f->edges);
    if (!f->edges)
        return cb_error_set(err, CB_ERR_NOMEM, "face: out of memory");
    for (int l = fc->first; l < fc->first + fc->count; l++)
        for (int c = b->loops[l].first; c < b->loops[l].first + b->loops[l].count; c++) {
            int e = b->coedges[c].edge, uses = 0, seen = 0;
            for (int l2 = fc->first; l2 < fc->first + fc->count; l2++)
                for (int c2 = b->loops[l2].first; c2 < b->loops[l2].first + b->loops[l2].count;
                     c2++)
                    uses += b->coedges[c2].edge == e;
            for (int k = 0; k < f->n_edges; k++)
                seen |= f->edges[k].edge == e;
            if (seen)
                continue;
            const cb_topo_edge *ed = &b->edges[e];
            const cb_topo_curve *cv = &b->curves[ed->curve];
            int m = N_EDGE_SAMPLES;
            if (cv->kind == CB_CURVE_NURBS)
                m = (int)fmin(512, fmax(m, 8 * (cv->nurbs->n - cv->nurbs->deg)));
            double(*pts)[3] = malloc((size_t)(m + 1) * sizeof *pts), gap = 0;
            if (!pts)
                return cb_error_set(err, CB_ERR_NOMEM, "face: out of memory");
            for (int k = 0; k <= m; k++) {
                cb_topo_curve_eval(pts[k], cv, ed->t0 + (ed->t1 - ed->t0) * k / m);
                if (k)
                    gap = fmax(gap, cb_vec3_dist(pts[k], pts[k - 1]));
            }
            cb_face_edge *fe = &f->edges[f->n_edges++];
            fe->edge = e;
            fe->boundary = uses == 1 && cb_topo_edge_length(b, e) > f->tol;
            fe->samples = pts;
            fe->n = m;
            fe->gap = gap;
            /* The loop boundary in (u, v) is the pcurve: its image strays from the edge by
             * up to the pcurve's error, which the boundary test must absorb. */
            fe->off = 0;
            if (fe->boundary) {
                double range[2];
                fe->off = cb_topo_coedge_pcurve_error(range, b, c, &f->inv, f->tol, 17);
            }
            cb_aabb_of_points(&fe->box, &pts[0][0], (size_t)m + 1, 3);
            for (int i = 0; i < 3; i++) {
                fe->box.lo[i] -= gap;
                fe->box.hi[i] += gap;
            }
        }
    return CB_OK;
}

/* Sample cells for the ray search of surfaces without a closed form. */
static cb_status build_cells(cb_face *f, cb_error *err)
{
    const cb_topo_surface *s = &f->b->surfaces[f->b->faces[f->face].surface];
    if (s->kind == CB_SURFACE_ANALYTIC)
        return CB_OK;
    int n[2] = {16, 16};
    if (s->kind == CB_SURFACE_NURBS) {
        n[0] = (int)fmin(64, fmax(16, 4 * (s->nurbs->n_u - s->nurbs->deg_u)));
        n[1] = (int)fmin(64, fmax(16, 4 * (s->nurbs->n_v - s->nurbs->deg_v)));
    } else if (s->kind == CB_SURFACE_REVOLUTION) {
        n[0] = 32;
    } else {
        n[1] = 8;
    }
    const double *bx = f->uv_box;
    int gu = 2 * n[0] + 1, gv = 2 * n[1] + 1;
    double(*g)[3] = malloc((size_t)gu * gv * sizeof *g);
    f->cells = malloc((size_t)n[0] * n[1] * sizeof *f->cells);
    if (!g || !f->cells) {
        free(g);
        return cb_error_set(err, CB_ERR_NOMEM, "face: out of memory");
    }
    for (int i = 0; i < gu; i++)
        for (int j = 0; j < gv; j++)
            cb_topo_inverter_eval(g[i * gv + j], &f->inv, bx[0] + (bx[1] - bx[0]) * i / (gu - 1),
                                  bx[2] + (bx[3] - bx[2]) * j / (gv - 1));
    for (int i = 0; i < n[0]; i++)
        for (int j = 0; j < n[1]; j++) {
            cb_face_cell *cl = &f->cells[f->n_cells++];
            cl->uv[0] = bx[0] + (bx[1] - bx[0]) * i / n[0];
            cl->uv[1] = bx[0] + (bx[1] - bx[0]) * (i + 1) / n[0];
            cl->uv[2] = bx[2] + (bx[3] - bx[2]) * j / n[1];
            cl->uv[3] = bx[2] + (bx[3] - bx[2]) * (j + 1) / n[1];
            double pts[9][3], dev = 0;
            for (int a = 0; a < 3; a++)
                for (int c = 0; c < 3; c++)
                    memcpy(pts[3 * a + c], g[(2 * i + a) * gv + 2 * j + c], sizeof pts[0]);
            /* Bilinear deviation of the mid points from their neighbours' means. */
            for (int k = 0; k < 3; k++) {
                double m;
                m = fabs(pts[1][k] - 0.5 * (pts[0][k] + pts[2][k]));
                dev = fmax(dev, m);
                m = fabs(pts[7][k] - 0.5 * (pts[6][k] + pts[8][k]));
                dev = fmax(dev, m);
                m = fabs(pts[3][k] - 0.5 * (pts[0][k] + pts[6][k]));
                dev = fmax(dev, m);
                m = fabs(pts[5][k] - 0.5 * (pts[2][k] + pts[8][k]));
                dev = fmax(dev, m);
                m = fabs(pts[4][k] - 0.25 * (pts[0][k] + pts[2][k] + pts[6][k] + pts[8][k]));
                dev = fmax(dev, m);
            }
            cb_aabb_of_points(&cl->box, &pts[0][0], 9, 3);
            for (int k = 0; k < 3; k++) {
                cl->box.lo[k] -= 2 * dev + f->tol;
                cl->box.hi[k] += 2 * dev + f->tol;
            }
        }
    free(g);
    return CB_OK;
}

void cb_face_clear(cb_face *f)
{
    if (f->inv.s)
        cb_topo_inverter_clear(&f->inv);
    free(f->segs);
    for (int k = 0; k < f->n_edges; k++)
        free(f->edges[k].samples);
    free(f->edges);
    free(f->cells);
    memset(f, 0, sizeof *f);
}

cb_status cb_face_init(cb_face *f, const cb_topo_body *b, int face, double tol, cb_error *err)
{
    memset(f, 0, sizeof *f);
    if (face < 0 || face >= b->n_faces)
        return cb_error_set(err, CB_ERR_INVALID, "face %d: out of range (%d faces)", face,
                            b->n_faces);
    if (!(tol > 0))
        return cb_error_set(err, CB_ERR_INVALID, "face %d: tolerance %g is not > 0", face, tol);
    const cb_topo_face *fc = &b->faces[face];
    f->b = b;
    f->face = face;
    f->tol = tol;
    cb_status st = cb_topo_inverter_init(&f->inv, &b->surfaces[fc->surface], tol, err);
    if (st) {
        memset(f, 0, sizeof *f);
        return cb_error_prefix(err, "face %d: ", face);
    }
    int(*wraps)[2] = calloc((size_t)(fc->count ? fc->count : 1), sizeof *wraps);
    if (!wraps) {
        cb_face_clear(f);
        return cb_error_set(err, CB_ERR_NOMEM, "face: out of memory");
    }
    st = sample_loops(f, wraps, err);
    int any[2] = {0, 0}, total[2] = {0, 0};
    for (int l = 0; l < fc->count; l++)
        for (int i = 0; i < 2; i++) {
            any[i] |= wraps[l][i] != 0;
            total[i] += wraps[l][i];
        }
    free(wraps);
    if (!st && any[0] && any[1])
        st = cb_error_set(err, CB_ERR_UNSUPPORTED,
                          "face %d: loops around both periods of its surface", face);
    if (!st && f->n_segs == 0)
        st = cb_error_set(err, CB_ERR_INVALID, "face %d: no loop", face);
    if (st) {
        cb_face_clear(f);
        return st;
    }
    int a = any[1] ? 1 : 0, bb = 1 - a;
    f->a = a;
    double *bx = f->uv_box;
    bx[0] = bx[2] = HUGE_VAL;
    bx[1] = bx[3] = -HUGE_VAL;
    for (int k = 0; k < f->n_segs; k++)
        for (int i = 0; i < 2; i++) {
            const cb_face_seg *sg = &f->segs[k];
            bx[2 * i] = fmin(bx[2 * i], fmin(sg->p[i], sg->q[i]) - sg->dev);
            bx[2 * i + 1] = fmax(bx[2 * i + 1], fmax(sg->p[i], sg->q[i]) + sg->dev);
        }
    if (any[a])
        bx[2 * a + 1] = bx[2 * a] + f->inv.lift[a];
    /* Odd columns close at the pole the wrapping loops keep to their left (right when the
     * face is reversed); left of +a is +b for a = u, -b for a = v. */
    f->pole_up = (total[a] > 0) == (fc->same_sense != 0);
    if (a == 1)
        f->pole_up = !f->pole_up;
    f->pole_b = f->pole_up ? f->inv.box[2 * bb + 1] : f->inv.box[2 * bb];
    if (any[a] && isfinite(f->pole_b)) {
        if (f->pole_up)
            bx[2 * bb + 1] = fmax(bx[2 * bb + 1], f->pole_b);
        else
            bx[2 * bb] = fmin(bx[2 * bb], f->pole_b);
    }
    /* Never past a B-spline's domain (analytic surfaces are defined everywhere: files write
     * sphere latitudes past the poles). */
    for (int i = 0; i < 2; i++)
        if (f->inv.period[i] <= 0 && b->surfaces[fc->surface].kind == CB_SURFACE_NURBS) {
            bx[2 * i] = fmax(bx[2 * i], f->inv.box[2 * i]);
            bx[2 * i + 1] = fmin(bx[2 * i + 1], f->inv.box[2 * i + 1]);
        }
    if ((st = boundary_edges(f, err)) ||
        (st = cb_face_surface_box(&f->box, &b->surfaces[fc->surface], bx, err)) ||
        (st = build_cells(f, err))) {
        cb_face_clear(f);
        return cb_error_prefix(err, "face %d: ", face);
    }
    double diag[3] = {f->box.hi[0] - f->box.lo[0], f->box.hi[1] - f->box.lo[1],
                      f->box.hi[2] - f->box.lo[2]};
    f->size = cb_vec3_norm(diag);
    return CB_OK;
}

void cb_face_box(cb_aabb *box, const cb_face *f) { *box = f->box; }

/* ---------------------------------------------------------------- classification ----------- */

/* 1 when the column a = x crosses the chord p q above b = y (half-open in a). */
static int chord_cross(const double p[2], const double q[2], int a, double x, double y)
{
    int bb = 1 - a;
    if ((p[a] <= x) == (q[a] <= x))
        return 0;
    double yb = p[bb] + (x - p[a]) / (q[a] - p[a]) * (q[bb] - p[bb]);
    return yb > y;
}

/* The halves of the pcurve piece [s0, s1] of sg (chord p q, within dev of it): the middle
 * parameter *sm and point m, and the halves' deviation bounds (twice their midpoint's, at
 * least a quarter of the parent's). */
static void halve_piece(double *sm, double m[2], double *d1, double *d2, const cb_face *f,
                        const cb_face_seg *sg, double s0, double s1, const double p[2],
                        const double q[2], double dev)
{
    const cb_topo_curve *pc = &f->b->pcurves[f->b->coedges[sg->coedge].pcurve];
    double w1[2], w2[2];
    *sm = 0.5 * (s0 + s1);
    pc_point(m, pc, *sm, sg->shift);
    pc_point(w1, pc, 0.5 * (s0 + *sm), sg->shift);
    pc_point(w2, pc, 0.5 * (*sm + s1), sg->shift);
    *d1 = fmax(0.25 * dev, 2 * seg_dist(w1, p, m));
    *d2 = fmax(0.25 * dev, 2 * seg_dist(w2, m, q));
}

/* Crossings of the column a = x above b = y by the pcurve piece [s0, s1] of sg, whose chord
 * p q it stays within dev of: the chord's where the piece cannot reach the point, else the
 * halves'. */
static int piece_cross(const cb_face *f, const cb_face_seg *sg, double s0, double s1,
                       const double p[2], const double q[2], double dev, double x, double y,
                       int depth)
{
    int a = f->a, bb = 1 - a;
    if (x < fmin(p[a], q[a]) - dev || x > fmax(p[a], q[a]) + dev)
        return 0;
    if (fmax(p[bb], q[bb]) + dev < y)
        return 0;
    if (fmin(p[bb], q[bb]) - dev > y || sg->coedge < 0 || depth >= MAX_QUERY_DEPTH ||
        dev <= 1e-15 * (fabs(x) + fabs(y) + 1))
        return chord_cross(p, q, a, x, y);
    double sm, m[2], d1, d2;
    halve_piece(&sm, m, &d1, &d2, f, sg, s0, s1, p, q, dev);
    return piece_cross(f, sg, s0, sm, p, m, d1, x, y, depth + 1) +
           piece_cross(f, sg, sm, s1, m, q, d2, x, y, depth + 1);
}

/* Where the chord a b crosses the straight segment p q: its fraction along a b in (0, 1), or
 * -1 when it does not (or they are parallel). */
static double chord_hit(const double a[2], const double b[2], const double p[2],
                        const double q[2])
{
    double e[2] = {b[0] - a[0], b[1] - a[1]}, g[2] = {q[0] - p[0], q[1] - p[1]};
    double den = e[0] * g[1] - e[1] * g[0];
    if (!(fabs(den) > 0))
        return -1;
    double w[2] = {p[0] - a[0], p[1] - a[1]};
    double x = (w[0] * g[1] - w[1] * g[0]) / den, y = (w[0] * e[1] - w[1] * e[0]) / den;
    return x > 0 && x < 1 && y >= 0 && y <= 1 ? x : -1;
}

typedef struct {
    double **t;
    int *n, *cap;
} hit_list;

static cb_status push_hit(hit_list *h, double x)
{
    if (*h->n == *h->cap) {
        int c = *h->cap ? 2 * *h->cap : 16;
        double *q = realloc(*h->t, (size_t)c * sizeof *q);
        if (!q)
            return CB_ERR_NOMEM;
        *h->t = q;
        *h->cap = c;
    }
    (*h->t)[(*h->n)++] = x;
    return CB_OK;
}

/* Crossings of the chord a b by the pcurve piece [s0, s1] of sg, whose chord p q it stays
 * within dev of: none where the band cannot reach the chord, the chords' crossing where the
 * piece is straight enough, else the halves' (piece_cross's bisection). */
static cb_status piece_hits(hit_list *h, const cb_face *f, const cb_face_seg *sg, double s0,
                            double s1, const double p[2], const double q[2], double dev,
                            const double a[2], const double b[2], int depth)
{
    double x = chord_hit(a, b, p, q);
    if (x < 0 && fmin(fmin(seg_dist(a, p, q), seg_dist(b, p, q)),
                      fmin(seg_dist(p, a, b), seg_dist(q, a, b))) > dev)
        return CB_OK;
    if (sg->coedge < 0 || depth >= MAX_QUERY_DEPTH ||
        dev <= 1e-15 * (fabs(p[0]) + fabs(p[1]) + fabs(q[0]) + fabs(q[1]) + 1))
        return x < 0 ? CB_OK : push_hit(h, x);
    double sm, m[2], d1, d2;
    halve_piece(&sm, m, &d1, &d2, f, sg, s0, s1, p, q, dev);
    cb_status st = piece_hits(h, f, sg, s0, sm, p, m, d1, a, b, depth + 1);
    return st ? st : piece_hits(h, f, sg, sm, s1, m, q, d2, a, b, depth + 1);
}

cb_status cb_face_chord_crossings(double **t, int *n, int *cap, const cb_face *f,
                                  const double a[2], const double b[2])
{
    hit_list h = {t, n, cap};
    double lo[2], hi[2], L[2];
    for (int d = 0; d < 2; d++) {
        lo[d] = fmin(a[d], b[d]);
        hi[d] = fmax(a[d], b[d]);
        L[d] = f->inv.lift[d];
    }
    for (int k = 0; k < f->n_segs; k++) {
        const cb_face_seg *sg = f->segs + k;
        int j0[2] = {0, 0}, j1[2] = {0, 0}, skip = 0;
        for (int d = 0; d < 2 && !skip; d++) {
            double slo = fmin(sg->p[d], sg->q[d]) - sg->dev;
            double shi = fmax(sg->p[d], sg->q[d]) + sg->dev;
            if (L[d] > 0) {
                /* the lifts j of the chord (moved by j L) that reach the segment's band */
                j0[d] = (int)ceil((slo - hi[d]) / L[d]);
                j1[d] = (int)floor((shi - lo[d]) / L[d]);
                skip = j0[d] > j1[d] || j1[d] - j0[d] > 4;
            } else {
                skip = shi < lo[d] || slo > hi[d];
            }
        }
        for (int ju = j0[0]; ju <= j1[0] && !skip; ju++)
            for (int jv = j0[1]; jv <= j1[1]; jv++) {
                double A[2] = {a[0] + ju * L[0], a[1] + jv * L[1]};
                double B[2] = {b[0] + ju * L[0], b[1] + jv * L[1]};
                if (piece_hits(&h, f, sg, sg->s0, sg->s1, sg->p, sg->q, sg->dev, A, B, 0))
                    return CB_ERR_NOMEM;
            }
    }
    return CB_OK;
}

/* Distance from p to face edge fe when it may be within limit, else HUGE_VAL: the stored
 * samples bound it from below, then Newton steps on the squared distance from the nearest
 * point of the sample polyline, clamped to the edge's range; lines and conics also by
 * cb_topo_edge_distance (closed forms). Every value is the distance to an edge point, so the
 * smallest is too. */
static double edge_distance(const cb_topo_body *b, const cb_face_edge *fe, const double p[3],
                            double limit)
{
    const cb_topo_edge *ed = &b->edges[fe->edge];
    const cb_topo_curve *c = &b->curves[ed->curve];
    double best = HUGE_VAL, q[3];
    for (int k = 0; k <= fe->n; k++)
        best = fmin(best, cb_vec3_dist(fe->samples[k], p));
    if (best - fe->gap > limit)
        return HUGE_VAL;
    /* Newton starts on the nearest chord, not at the nearest sample: on a closed edge the
     * first and last samples coincide, and from the wrong one of the two the step points out
     * of the range and stays clamped at its end. */
    double seg = HUGE_VAL, pos = 0;
    for (int k = 0; k < fe->n; k++) {
        double l, d = cb_seg3_nearest(&l, fe->samples[k], fe->samples[k + 1], p);
        if (d < seg) {
            seg = d;
            pos = k + l;
        }
    }
    double t = ed->t0 + (ed->t1 - ed->t0) * pos / fe->n;
    for (int it = 0; it < 12; it++) {
        double d[3][3], r[3];
        cb_topo_curve_eval_derivs(d, c, t);
        for (int i = 0; i < 3; i++)
            r[i] = d[0][i] - p[i];
        double g = cb_vec3_dot(r, d[1]), h = cb_vec3_dot(d[1], d[1]) + cb_vec3_dot(r, d[2]);
        if (!(h > 0))
            h = cb_vec3_dot(d[1], d[1]);
        if (!(h > 0))
            break;
        double step = g / h;
        t = fmin(fmax(t - step, ed->t0), ed->t1);
        if (fabs(step) <= 1e-15 * (fabs(t) + 1))
            break;
    }
    cb_topo_curve_eval(q, c, t);
    best = fmin(best, cb_vec3_dist(q, p));
    if (c->kind != CB_CURVE_NURBS)
        best = fmin(best, cb_topo_edge_distance(b, fe->edge, p));
    return best;
}

static int box_near(const cb_aabb *bx, const double p[3], double limit)
{
    int in = 1;
    for (int i = 0; i < 3; i++)
        in &= p[i] >= bx->lo[i] - limit && p[i] <= bx->hi[i] + limit;
    return in;
}

/* Within tol plus its off of a boundary edge. */
static int near_boundary(const cb_face *f, const double p[3], double tol)
{
    for (int k = 0; k < f->n_edges; k++) {
        const cb_face_edge *fe = &f->edges[k];
        double lim = tol + fe->off;
        if (fe->boundary && box_near(&fe->box, p, lim) && edge_distance(f->b, fe, p, lim) <= lim)
            return 1;
    }
    return 0;
}

double cb_face_boundary_distance(const cb_face *f, const double p[3])
{
    double best = HUGE_VAL;
    for (int k = 0; k < f->n_edges; k++)
        if (f->edges[k].boundary && box_near(&f->edges[k].box, p, best))
            best = fmin(best, edge_distance(f->b, &f->edges[k], p, best));
    return best;
}

/* Parity of the loops around (u, v), the pole closure included. */
static int inside(const cb_face *f, double u, double v)
{
    int a = f->a, bb = 1 - a;
    double w[2] = {u, v};
    double Pa = f->inv.lift[a], Pb = f->inv.lift[bb];
    if (Pb > 0) {
        double lo = f->uv_box[2 * bb];
        w[bb] = lo + (w[bb] - lo) - Pb * floor((w[bb] - lo) / Pb);
    }
    double x = w[a], y = w[bb];
    if (!isfinite(x) || !isfinite(y))
        return 0;
    if (Pa > 0) {
        /* x into one period from the box's low end, so that the copies counted below are a
         * few (a point far out, as a fuzzed body gives, overflowed their count). */
        double lo = isfinite(f->uv_box[2 * a]) ? f->uv_box[2 * a] : 0;
        x = lo + (x - lo) - Pa * floor((x - lo) / Pa);
    }
    int above = 0, total = 0;
    for (int k = 0; k < f->n_segs; k++) {
        const cb_face_seg *sg = &f->segs[k];
        int j0 = 0, j1 = 0;
        double lo = fmin(sg->p[a], sg->q[a]) - sg->dev, hi = fmax(sg->p[a], sg->q[a]) + sg->dev;
        if (Pa > 0) {
            j0 = (int)floor((x - hi) / Pa);
            j1 = (int)ceil((x - lo) / Pa);
        }
        for (int j = j0; j <= j1; j++) {
            double X = x - j * Pa;
            total += chord_cross(sg->p, sg->q, a, X, -HUGE_VAL);
            above += piece_cross(f, sg, sg->s0, sg->s1, sg->p, sg->q, sg->dev, X, y, 0);
        }
    }
    if (total % 2) {
        if (!isfinite(f->pole_b))
            return 0;
        above += f->pole_up;
    }
    return above % 2;
}

cb_face_where cb_face_classify_uv(const cb_face *f, double u, double v, double tol)
{
    double w[2] = {u, v};
    for (int i = 0; i < 2; i++) {
        double lo = f->uv_box[2 * i], hi = f->uv_box[2 * i + 1], m = 0.1 * (hi - lo);
        if (f->inv.lift[i] <= 0 && (w[i] < lo - m || w[i] > hi + m))
            return CB_FACE_OUT;
    }
    double p[3];
    cb_topo_inverter_eval(p, &f->inv, u, v);
    if (near_boundary(f, p, tol))
        return CB_FACE_ON;
    return inside(f, u, v) ? CB_FACE_IN : CB_FACE_OUT;
}

/* ---------------------------------------------------------------- distance, normal --------- */

double cb_face_distance(double uv[2], const cb_face *f, const double p[3])
{
    double best = HUGE_VAL, best_uv[2] = {0, 0};
    double starts[CB_TOPO_MAX_STARTS][2];
    int n = 0;
    if (f->inv.pr.grid)
        n = cb_topo_projector_starts(starts, CB_TOPO_MAX_STARTS, &f->inv.pr, p);
    for (int k = -1; k < n; k++) {
        double w[2];
        double d = cb_topo_inverter_invert(w, &f->inv, p, k < 0 ? NULL : starts[k]);
        if (d < best && inside(f, w[0], w[1])) {
            best = d;
            memcpy(best_uv, w, sizeof best_uv);
        }
    }
    for (int k = 0; k < f->n_edges; k++) {
        if (!box_near(&f->edges[k].box, p, best))
            continue;
        double d = edge_distance(f->b, &f->edges[k], p, best);
        if (d < best) {
            best = d;
            if (uv)
                cb_topo_inverter_invert(best_uv, &f->inv, p, NULL);
        }
    }
    if (uv)
        memcpy(uv, best_uv, sizeof best_uv);
    return best;
}

double cb_face_normal(double n[3], const cb_face *f, double u, double v)
{
    double d[6][3];
    cb_topo_inverter_eval_derivs(d, &f->inv, u, v);
    cb_vec3_cross(n, d[1], d[2]);
    if (!f->b->faces[f->face].same_sense)
        for (int i = 0; i < 3; i++)
            n[i] = -n[i];
    return cb_vec3_normalize(n);
}
