/* cut.c — intersection curves restricted to both trimmed faces and brought into each face's
 * (u, v) window, ready to split the faces (cb_bool_cuts_make). */
#include "boolean/cut_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "brep/geom.h"
#include "brep/parallel.h"

int _cb_cut_run_push(cut_run *r, const cut_pt *p)
{
    if (r->n == r->cap) {
        int cap = r->cap ? 2 * r->cap : 32;
        cut_pt *q = realloc(r->p, (size_t)cap * sizeof *q);
        if (!q)
            return -1;
        r->p = q;
        r->cap = cap;
    }
    r->p[r->n++] = *p;
    return 0;
}

static void lerp_pt(cut_pt *out, const cut_pt *a, const cut_pt *b, double t)
{
    for (int k = 0; k < 3; k++)
        out->xyz[k] = a->xyz[k] + t * (b->xyz[k] - a->xyz[k]);
    for (int s = 0; s < 2; s++)
        for (int k = 0; k < 2; k++)
            out->uv[s][k] = a->uv[s][k] + t * (b->uv[s][k] - a->uv[s][k]);
}

static double norm3(const double a[3])
{
    return sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
}

void cb_bool_cuts_init(cb_bool_cuts *c)
{
    memset(c, 0, sizeof *c);
}

void cb_bool_cuts_clear(cb_bool_cuts *c)
{
    for (int k = 0; k < c->n; k++) {
        free(c->cut[k].xyz);
        free(c->cut[k].uv[0]);
        free(c->cut[k].uv[1]);
        free(c->cut[k].dir);
        free(c->cut[k].duv[0]);
        free(c->cut[k].duv[1]);
    }
    free(c->cut);
    memset(c, 0, sizeof *c);
}

/* Appends run r (at least two points, or a closed run of three) as a cut. */
static void tangents(cb_bool_cut *k, const cb_face *const f[2]);

static cb_status emit(cb_bool_cuts *out, const cut_run *r, const cb_ssi_curve *c, int curve,
                      int closed, double min_gap, const cb_face *const f[2], cb_error *err)
{
    if (out->n == out->cap) {
        int cap = out->cap ? 2 * out->cap : 16;
        cb_bool_cut *q = realloc(out->cut, (size_t)cap * sizeof *q);
        if (!q)
            return cb_error_set(err, CB_ERR_NOMEM, "cuts: out of memory");
        out->cut = q;
        out->cap = cap;
    }
    cb_bool_cut *k = out->cut + out->n;
    memset(k, 0, sizeof *k);
    k->xyz = malloc((size_t)r->n * 3 * sizeof(double));
    k->uv[0] = malloc((size_t)r->n * 2 * sizeof(double));
    k->uv[1] = malloc((size_t)r->n * 2 * sizeof(double));
    k->dir = malloc((size_t)r->n * 3 * sizeof(double));
    k->duv[0] = malloc((size_t)r->n * 2 * sizeof(double));
    k->duv[1] = malloc((size_t)r->n * 2 * sizeof(double));
    if (!k->xyz || !k->uv[0] || !k->uv[1] || !k->dir || !k->duv[0] || !k->duv[1]) {
        free(k->xyz);
        free(k->uv[0]);
        free(k->uv[1]);
        free(k->dir);
        free(k->duv[0]);
        free(k->duv[1]);
        return cb_error_set(err, CB_ERR_NOMEM, "cuts: out of memory");
    }
    /* Points closer than min_gap to the kept one before are dropped (a crossing or an exit
     * found at a polyline point); the last point stays. */
    int m = 0;
    for (int i = 0; i < r->n; i++) {
        if (m > 0) {
            double d2 = 0;
            for (int j = 0; j < 3; j++)
                d2 += (r->p[i].xyz[j] - k->xyz[3 * (m - 1) + j]) *
                      (r->p[i].xyz[j] - k->xyz[3 * (m - 1) + j]);
            if (d2 <= min_gap * min_gap) {
                if (i + 1 < r->n || m == 1)
                    continue;
                m--;
            }
        }
        memcpy(k->xyz + 3 * m, r->p[i].xyz, sizeof r->p[i].xyz);
        memcpy(k->uv[0] + 2 * m, r->p[i].uv[0], 2 * sizeof(double));
        memcpy(k->uv[1] + 2 * m, r->p[i].uv[1], 2 * sizeof(double));
        m++;
    }
    if (m < 2) {
        free(k->xyz);
        free(k->uv[0]);
        free(k->uv[1]);
        free(k->dir);
        free(k->duv[0]);
        free(k->duv[1]);
        return CB_OK;
    }
    k->n = m;
    k->face[0] = c->face_a;
    k->face[1] = c->face_b;
    k->curve = curve;
    k->closed = closed;
    k->tangential = c->tangential;
    tangents(k, f);
    out->n++;
    return CB_OK;
}

/* The extent [*a, *b] of the loops' polygon vertices in direction i. */
static void loop_extent(double *a, double *b, const cb_face *f, int i)
{
    *a = HUGE_VAL;
    *b = -HUGE_VAL;
    for (int k = 0; k < f->n_segs; k++) {
        const cb_face_seg *sg = f->segs + k;
        *a = fmin(*a, fmin(sg->p[i], sg->q[i]));
        *b = fmax(*b, fmax(sg->p[i], sg->q[i]));
    }
}

/* Loops whose extent in a periodic direction is within this fraction of the period of it (or
 * more) span the whole period: rounding of the seam's parameter in files and pcurves. */
#define SEAM_REL 1e-9

/* A curve point within this fraction of the period of a window's end lies on the seam there
 * (the SSI's points on a seam carry the surface's inversion error in the parameter). */
#define SEAM_BAND 1e-7

/* Whether a face's loops span the whole period P from a to b: it has a seam there. */
static int spans_period(double a, double b, double P)
{
    return b - a >= P * (1 - SEAM_REL);
}

/* The window of periodic direction i of a face: [lo, lo + period), centred on the extent of
 * the loops' polygon vertices, so that every point of the trimmed face has one lift in it. The
 * vertices, not the face's uv_box: that box is grown by each segment's deviation from its
 * pcurve, which would move the window's ends off a seam by as much. */
static double window_lo(const cb_face *f, int i)
{
    double P = f->inv.period[i], a, b;
    loop_extent(&a, &b, f, i);
    /* A face spanning the whole period has its seam at the vertices' ends: keep them as the
     * window's, so that a curve is split where it crosses the seam edge. */
    return spans_period(a, b, P) ? a : 0.5 * (a + b) - 0.5 * P;
}

/* Whether (u, v) lies on a window's end of a face that spans the whole period there (its seam;
 * see on_split_boundary). */
static int on_window_end(const cb_face *f, const double uv[2])
{
    for (int d = 0; d < 2; d++) {
        double P = f->inv.period[d], a, b;
        if (!(P > 0))
            continue;
        loop_extent(&a, &b, f, d);
        if (spans_period(a, b, P) && fabs(remainder(uv[d] - a, P)) <= SEAM_BAND * P)
            return 1;
    }
    return 0;
}

/* Whether (u, v) lies on the boundary of the face's split: within near of a boundary edge
 * (cb_face_classify_uv ON), or on a window's end where the face spans the whole period (its
 * seam, which the split's loop polygon has on both ends of the window). */
static int on_split_boundary(const cb_face *f, const double uv[2], double near)
{
    return cb_face_classify_uv(f, uv[0], uv[1], near) == CB_FACE_ON || on_window_end(f, uv);
}

static double wrap(double x, double lo, double P)
{
    double w = lo + fmod(x - lo, P);
    if (w < lo)
        w += P;
    if (w >= lo + P)
        w -= P;
    return w;
}

/* x moved by whole periods P to the lift nearest ref (x itself when P is not positive). */
static double lift_near(double x, double ref, double P)
{
    return P > 0 ? x + P * nearbyint((ref - x) / P) : x;
}

static int length_over(const cut_run *r, double min_len)
{
    double len = 0;
    for (int i = 1; i < r->n && len <= min_len; i++) {
        double d2 = 0;
        for (int k = 0; k < 3; k++)
            d2 += (r->p[i].xyz[k] - r->p[i - 1].xyz[k]) * (r->p[i].xyz[k] - r->p[i - 1].xyz[k]);
        len += sqrt(d2);
    }
    return len > min_len;
}

void _cb_cut_ctx_init(cut_ctx *cx, const cb_face *fa, const cb_face *fb, double tol)
{
    cx->f[0] = fa;
    cx->f[1] = fb;
    cx->min_len = tol;
    for (int s = 0; s < 2; s++)
        for (int d = 0; d < 2; d++) {
            cx->P[s][d] = cx->f[s]->inv.period[d];
            cx->lo[s][d] = cx->P[s][d] > 0 ? window_lo(cx->f[s], d) : 0;
            cx->band[s][d] = -1;
            if (cx->P[s][d] > 0) {
                double a, b;
                loop_extent(&a, &b, cx->f[s], d);
                cx->hi[s][d] = b;
                double e = fabs(b - a - cx->P[s][d]);
                if (e <= SEAM_REL * cx->P[s][d])
                    cx->band[s][d] = 2 * e;
            }
        }
}

/* Solves the 4 x 4 system J d = r in place (Gaussian elimination, partial pivoting); 0 when
 * singular. */
static int solve4(double J[4][4], double r[4])
{
    for (int c = 0; c < 4; c++) {
        int p = c;
        for (int i = c + 1; i < 4; i++)
            if (fabs(J[i][c]) > fabs(J[p][c]))
                p = i;
        if (!(fabs(J[p][c]) > 0))
            return 0;
        for (int k = 0; k < 4; k++) {
            double t = J[c][k];
            J[c][k] = J[p][k];
            J[p][k] = t;
        }
        double t = r[c];
        r[c] = r[p];
        r[p] = t;
        for (int i = c + 1; i < 4; i++) {
            double f = J[i][c] / J[c][c];
            for (int k = c; k < 4; k++)
                J[i][k] -= f * J[c][k];
            r[i] -= f * r[c];
        }
    }
    for (int c = 3; c >= 0; c--) {
        for (int k = c + 1; k < 4; k++)
            r[c] -= J[c][k] * r[k];
        r[c] /= J[c][c];
    }
    return 1;
}

/* Moves m (a point interpolated between two curve points) onto the intersection curve: the
 * point on both surfaces in the plane through m normal to t (unit), by Newton steps from m's
 * parameters. Leaves m as it is when they do not converge within a tenth of the tolerance
 * (tangent surfaces: the system is singular there) or wander farther than reach. */
static void refine_pt(cut_pt *m, const cut_ctx *cx, const double t[3], double reach)
{
    cut_pt x = *m;
    double tol = 0.1 * cx->min_len;
    for (int it = 0; it < 12; it++) {
        double da[6][3], db[6][3];
        cb_topo_inverter_eval_derivs(da, &cx->f[0]->inv, x.uv[0][0], x.uv[0][1]);
        cb_topo_inverter_eval_derivs(db, &cx->f[1]->inv, x.uv[1][0], x.uv[1][1]);
        double r[4], J[4][4], gap = 0, off = 0;
        for (int k = 0; k < 3; k++) {
            r[k] = db[0][k] - da[0][k];
            gap += r[k] * r[k];
            off += (da[0][k] - m->xyz[k]) * t[k];
            J[k][0] = da[1][k];
            J[k][1] = da[2][k];
            J[k][2] = -db[1][k];
            J[k][3] = -db[2][k];
        }
        r[3] = -off;
        J[3][0] = da[1][0] * t[0] + da[1][1] * t[1] + da[1][2] * t[2];
        J[3][1] = da[2][0] * t[0] + da[2][1] * t[1] + da[2][2] * t[2];
        J[3][2] = J[3][3] = 0;
        if (sqrt(gap) <= tol && fabs(off) <= tol) {
            double d[3];
            for (int k = 0; k < 3; k++) {
                x.xyz[k] = 0.5 * (da[0][k] + db[0][k]);
                d[k] = x.xyz[k] - m->xyz[k];
            }
            if (norm3(d) <= reach)
                *m = x;
            return;
        }
        if (!solve4(J, r))
            return;
        x.uv[0][0] += r[0];
        x.uv[0][1] += r[1];
        x.uv[1][0] += r[2];
        x.uv[1][1] += r[3];
    }
}

/* b with every periodic parameter moved by whole periods next to a's, so that the points
 * between the two are interpolated in one lift: interpolating from 0 to nearly a period
 * would run across the other side of the surface, where Newton then lands on another sheet
 * of the curve. */
static void unwrap_next(cut_pt *b, const cut_ctx *cx, const cut_pt *a)
{
    for (int s = 0; s < 2; s++)
        for (int d = 0; d < 2; d++)
            b->uv[s][d] = lift_near(b->uv[s][d], a->uv[s][d], cx->P[s][d]);
}

/* Bisection on the curve between a (where before(a) holds) and b (where it does not): the
 * midpoints are moved onto the curve (refine_pt) while the step is long enough for the chord
 * to stray, then halved until a thousandth of the tolerance. Returns the last point where
 * before holds. */
static void bisect_on_curve(cut_pt *out, const cut_ctx *cx, const cut_pt *a, const cut_pt *b,
                            int (*before)(const cut_ctx *, const cut_pt *, const void *),
                            const void *arg)
{
    cut_pt lo = *a, hi = *b, m;
    for (int it = 0; it < 80; it++) {
        double ch[3];
        for (int k = 0; k < 3; k++)
            ch[k] = hi.xyz[k] - lo.xyz[k];
        double L = norm3(ch);
        if (L <= 1e-3 * cx->min_len)
            break;
        lerp_pt(&m, &lo, &hi, 0.5);
        if (L > 1e-2 * cx->min_len) {
            for (int k = 0; k < 3; k++)
                ch[k] /= L;
            refine_pt(&m, cx, ch, L);
        }
        if (before(cx, &m, arg))
            lo = m;
        else
            hi = m;
    }
    *out = lo;
}

typedef struct {
    int s, d;
    double end;
    int up;
} cross_arg;

/* The point has not reached the window's end yet (parameters unwrapped from the step's
 * start). */
static int short_of_end(const cut_ctx *cx, const cut_pt *p, const void *arg)
{
    (void)cx;
    const cross_arg *c = arg;
    return c->up ? p->uv[c->s][c->d] < c->end : p->uv[c->s][c->d] > c->end;
}

/* Where the step a -> b (wrapped parameters) crosses a window's end first, over both sides
 * and directions: the crossing point as the end of the piece before it and as the start of
 * the piece after it (the same point, its crossed parameter at the window's two ends), and
 * which parameter it crosses (2 side + direction). Returns 0 when the step crosses none. */
static int find_cross(const cut_ctx *cx, const cut_pt *a, const cut_pt *b, cut_pt *before,
                      cut_pt *after, int *which)
{
    double tcross = 2;
    int cs = -1, cd = -1;
    for (int s = 0; s < 2; s++)
        for (int d = 0; d < 2; d++) {
            double P = cx->P[s][d];
            if (P <= 0)
                continue;
            double x = a->uv[s][d], y = b->uv[s][d];
            if (fabs(y - x) <= 0.5 * P)
                continue;
            double yu = y > x ? y - P : y + P; /* y unwrapped next to x */
            double end = yu > x ? cx->lo[s][d] + P : cx->lo[s][d];
            double t = (end - x) / (yu - x);
            if (t < tcross) {
                tcross = t;
                cs = s;
                cd = d;
            }
        }
    if (cs < 0)
        return 0;
    *which = 2 * cs + cd;
    double P = cx->P[cs][cd], lo = cx->lo[cs][cd];
    cut_pt bu = *b; /* both faces may cross a seam on the same step */
    unwrap_next(&bu, cx, a);
    int up = bu.uv[cs][cd] > a->uv[cs][cd]; /* the step runs up across the upper end */
    cross_arg ca = {cs, cd, up ? lo + P : lo, up};
    bisect_on_curve(before, cx, a, &bu, short_of_end, &ca);
    *after = *before;
    before->uv[cs][cd] = up ? lo + P : lo;
    after->uv[cs][cd] = up ? lo : lo + P;
    for (int s = 0; s < 2; s++)
        for (int d = 0; d < 2; d++)
            if (cx->P[s][d] > 0 && (s != cs || d != cd))
                after->uv[s][d] = wrap(after->uv[s][d], cx->lo[s][d], cx->P[s][d]);
    return 1;
}

/* 1 when interior point i of run r lies at a pole of one of the faces (settle_poles' test)
 * where the collapsed parameter differs on its two sides: the curve passes over the pole,
 * and in (u, v) it leaves the pole line elsewhere than it arrived. before and after are the
 * point with that parameter of the arriving and of the leaving side. */
static int pole_split(const cut_ctx *cx, const cut_run *r, int i, cut_pt *before, cut_pt *after)
{
    if (i <= 0 || i + 1 >= r->n)
        return 0;
    for (int s = 0; s < 2; s++) {
        int col = cb_topo_inverter_collapsed(&cx->f[s]->inv, r->p[i].uv[s][0], r->p[i].uv[s][1]);
        for (int d = 0; d < 2; d++) {
            if (!(col & (1 << d)))
                continue;
            double a = r->p[i - 1].uv[s][d], b = r->p[i + 1].uv[s][d];
            if (!(fabs(a - b) > 1e-9 * (1 + fabs(a) + fabs(b))))
                continue;
            *before = *after = r->p[i];
            before->uv[s][d] = a;
            after->uv[s][d] = b;
            return 1;
        }
    }
    return 0;
}

/* The unit tangent of the curve at point i of run r as seen from the side of step (-1: the
 * points before it, 1: after): the cross product of the faces' normals a thousandth of the
 * way towards the nearest point on that side not at i (on that side of a knot line where a
 * B-spline surface is only C0; the SSI may repeat a point there), oriented along the run. 0
 * where the faces are tangent there (no direction) or no such point exists. */
static int side_tangent(double t[3], const cut_ctx *cx, const cut_run *r, int i, int step)
{
    int j = i + step;
    for (;; j += step) {
        if (j < 0 || j >= r->n)
            return 0;
        double e[3];
        for (int k = 0; k < 3; k++)
            e[k] = r->p[j].xyz[k] - r->p[i].xyz[k];
        if (norm3(e) > 1e-3 * cx->min_len)
            break;
    }
    cut_pt q = r->p[j];
    unwrap_next(&q, cx, r->p + i);
    double n[2][3];
    for (int s = 0; s < 2; s++) {
        double dd[6][3], uv[2];
        for (int d = 0; d < 2; d++)
            uv[d] = r->p[i].uv[s][d] + 1e-3 * (q.uv[s][d] - r->p[i].uv[s][d]);
        cb_topo_inverter_eval_derivs(dd, &cx->f[s]->inv, uv[0], uv[1]);
        cb_vec3_cross(n[s], dd[1], dd[2]);
    }
    cb_vec3_cross(t, n[0], n[1]);
    double l = norm3(t), ch[3];
    if (!(l > 1e-3 * norm3(n[0]) * norm3(n[1])))
        return 0;
    for (int k = 0; k < 3; k++)
        ch[k] = j > i ? q.xyz[k] - r->p[i].xyz[k] : r->p[i].xyz[k] - q.xyz[k];
    double sg = cb_vec3_dot(t, ch) < 0 ? -1 : 1;
    for (int k = 0; k < 3; k++)
        t[k] *= sg / l;
    return 1;
}

/* 1 when the curve has a corner at interior point i of run r: where it crosses a crease of
 * a face (a knot line where a B-spline surface is only C0, an edge of a polyline extruded),
 * the intersection curve turns there (by less than 0.9 pi). The cut's curve is G1 at its points (cb_bool_cut_curve),
 * so across a corner its cubics would bulge off the surfaces by about a quarter of the turn
 * times the step: split there (before = after = the point) when that would exceed a tenth of
 * the tolerance. */
static int kink_split(const cut_ctx *cx, const cut_run *r, int i, cut_pt *before, cut_pt *after)
{
    if (i <= 0 || i + 1 >= r->n)
        return 0;
    double tl[3], tr[3];
    if (!side_tangent(tl, cx, r, i, -1) || !side_tangent(tr, cx, r, i, 1))
        return 0;
    double c[3], step = 0;
    cb_vec3_cross(c, tl, tr);
    double turn = atan2(norm3(c), cb_vec3_dot(tl, tr));
    for (int j = i - 1; j <= i; j++) {
        double e[3];
        for (int k = 0; k < 3; k++)
            e[k] = r->p[j + 1].xyz[k] - r->p[j].xyz[k];
        step = fmax(step, norm3(e));
    }
    /* Near a half turn the polyline doubles back on itself (the SSI's points out of order
     * for a step), which a split would only cut into slivers. */
    if (!(turn > 1e-3 && turn < 0.9 * CB_SSI_PI && 0.25 * turn * step > 0.1 * cx->min_len))
        return 0;
    *before = *after = r->p[i];
    return 1;
}

/* The pieces of one run between its splits, before they are emitted: each with the splits
 * it starts and ends at (ids in order along the run; the crossed parameter of a seam crossing,
 * 2 side + direction, or -1 for a pole, a corner or an end of the run). */
typedef struct {
    cut_run run;
    int start_cross, end_cross, start_id, end_id;
    int dropped;
} split_piece;

typedef struct {
    int n, cap;
    split_piece *p;
} split_pieces;

static split_piece *pieces_add(split_pieces *ps, int start_cross, int start_id)
{
    if (ps->n == ps->cap) {
        int cap = ps->cap ? 2 * ps->cap : 8;
        split_piece *q = realloc(ps->p, (size_t)cap * sizeof *q);
        if (!q)
            return NULL;
        ps->p = q;
        ps->cap = cap;
    }
    split_piece *k = ps->p + ps->n++;
    memset(k, 0, sizeof *k);
    k->start_cross = start_cross;
    k->start_id = start_id;
    k->end_cross = k->end_id = -1;
    return k;
}

/* A piece between crossings of two different seams (one of each face, or both of one face)
 * shorter than weld is a sliver: its two ends weld into one node, and the piece would fold
 * onto itself there (the seams of a cone and a sphere on one axis, crossed 0.4 tol apart by
 * a circle, left a 1.7e-6 piece whose weld closed the other piece on itself on one face
 * only). It is dropped and its neighbours meet across both seams: the piece before it ends
 * on the second seam's arriving copy too, the piece after it starts on the first seam's
 * leaving copy. Where the two crossings coincide (a cylinder through a sphere on one axis,
 * both seams in one half-plane) the sliver has length 0, and the piece after it took the
 * first seam's arriving copy (the window's wrap of its end): it leaves on the other now. */
static void merge_slivers(split_pieces *ps, int closed, double weld)
{
    for (int k = 0; k < ps->n; k++) {
        split_piece *m = ps->p + k;
        if (m->start_cross < 0 || m->end_cross < 0 || m->start_cross == m->end_cross ||
            m->run.n < 2 || length_over(&m->run, weld))
            continue;
        int kp = k > 0 ? k - 1 : closed ? ps->n - 1 : -1;
        int kn = k + 1 < ps->n ? k + 1 : closed ? 0 : -1;
        if (kp < 0 || kn < 0 || kp == k || kn == k)
            continue;
        split_piece *a = ps->p + kp, *b = ps->p + kn;
        if (a->dropped || b->dropped || a->end_id != m->start_id || b->start_id != m->end_id ||
            a->run.n < 1 || b->run.n < 1)
            continue;
        int s1 = m->start_cross / 2, d1 = m->start_cross % 2;
        int s2 = m->end_cross / 2, d2 = m->end_cross % 2;
        cut_pt *a_end = a->run.p + a->run.n - 1, *b_start = b->run.p;
        a_end->uv[s2][d2] = m->run.p[m->run.n - 1].uv[s2][d2];
        b_start->uv[s1][d1] = m->run.p[0].uv[s1][d1];
        a->end_cross = b->start_cross = -1; /* one node now, crossed both ways */
        a->end_id = b->start_id = m->start_id;
        m->dropped = 1;
    }
}

/* Wraps the periodic parameters of run r into the faces' windows and splits it where a lift
 * jumps (the curve crosses a window's end, the seam of a face spanning a whole period) and
 * where it passes over a pole (pole_split) or turns a corner (kink_split). A closed run with a
 * split is first rotated to start and end there. Emits the pieces. */
cb_status _cb_cut_split_emit(cb_bool_cuts *out, cut_run *r, int closed, const cut_ctx *cx,
                             const cb_ssi_curve *c, int curve, cb_error *err)
{
    if (!closed && !length_over(r, cx->min_len))
        return CB_OK; /* a curve grazing a corner of a face: no piece to split by */
    for (int i = 0; i < r->n; i++)
        for (int s = 0; s < 2; s++)
            for (int d = 0; d < 2; d++)
                if (cx->P[s][d] > 0)
                    r->p[i].uv[s][d] = wrap(r->p[i].uv[s][d], cx->lo[s][d], cx->P[s][d]);
    /* A point on a window's end (a seam) has two lifts, and rounding picks either: along a
     * curve running on the seam it would jump from one to the other and back, splitting the
     * cut into pieces on both copies of the seam. A point on the seam next to another on it
     * (the curve runs along the seam there) keeps its predecessor's copy; a curve that only
     * crosses the seam, or touches it at one point, is split there (find_cross). */
    for (int i = 1; i < r->n; i++)
        for (int s = 0; s < 2; s++)
            for (int d = 0; d < 2; d++) {
                double P = cx->P[s][d], lo = cx->lo[s][d], *x = &r->p[i].uv[s][d];
                double prev = r->p[i - 1].uv[s][d], band = SEAM_BAND * P;
                if (!(P > 0) || fabs(*x - prev) <= 0.5 * P)
                    continue;
                double next = i + 1 < r->n ? r->p[i + 1].uv[s][d] : HUGE_VAL;
                int x_lo = fabs(*x - lo) <= band, x_hi = fabs(*x - lo - P) <= band;
                int run = fabs(prev - lo) <= band || fabs(prev - lo - P) <= band ||
                          fabs(next - lo) <= band || fabs(next - lo - P) <= band;
                if (run && x_lo)
                    *x += P;
                else if (run && x_hi)
                    *x -= P;
            }
    cut_pt before, after;
    int first = -1, at_pole = 0, which = -1;
    for (int i = 0; i + 1 < r->n && first < 0; i++)
        if ((at_pole = pole_split(cx, r, i, &before, &after) ||
                       kink_split(cx, r, i, &before, &after)) ||
            find_cross(cx, r->p + i, r->p + i + 1, &before, &after, &which))
            first = i;
    if (first < 0)
        return emit(out, r, c, curve, closed, 1e-6 * cx->min_len, cx->f, err);
    cut_run rot = {0, 0, NULL};
    split_pieces ps = {0, 0, NULL};
    int fail = 0;
    /* the split a piece starts at: a crossing's parameter (find_cross), or -1 */
    int start_cross = -1, start_id = -1, n_split = 0;
    if (closed) {
        /* From the split round to it: after, p[first + 1 ..], p[1 .. first], before (the
         * last point repeats the first; at a pole or a corner, p[first] is before and
         * after). */
        fail |= _cb_cut_run_push(&rot, &after);
        for (int i = first + 1; i < r->n; i++)
            fail |= _cb_cut_run_push(&rot, r->p + i);
        for (int i = 1; i < first + !at_pole; i++)
            fail |= _cb_cut_run_push(&rot, r->p + i);
        fail |= _cb_cut_run_push(&rot, &before);
        r = &rot;
        start_cross = at_pole ? -1 : which;
        start_id = n_split++;
    }
    int rot_cross = start_cross, rot_id = start_id;
    split_piece *cur = pieces_add(&ps, start_cross, start_id);
    fail |= !cur;
    for (int i = 0; i < r->n && !fail; i++) {
        int split = 0, w = -1;
        if (pole_split(cx, r, i, &before, &after) || kink_split(cx, r, i, &before, &after)) {
            split = 1;
        } else {
            fail |= _cb_cut_run_push(&cur->run, r->p + i);
            split = i + 1 < r->n &&
                    find_cross(cx, r->p + i, r->p + i + 1, &before, &after, &w);
        }
        /* A step may cross two seams (one of each face, or both of one face), at points
         * apart or at one point (a node on both seams): the rest of the step, from the
         * crossing on, is searched again, so that no piece keeps a jump of a lift. */
        for (int again = 0; split && !fail; again++) {
            fail |= _cb_cut_run_push(&cur->run, &before);
            cur->end_cross = w;
            cur->end_id = n_split;
            cur = fail ? NULL : pieces_add(&ps, w, n_split++);
            fail |= !cur || _cb_cut_run_push(&cur->run, &after);
            cut_pt from = after;
            split = !fail && again < 4 && i + 1 < r->n &&
                    find_cross(cx, &from, r->p + i + 1, &before, &after, &w);
        }
    }
    if (!fail) {
        cur->end_cross = closed ? rot_cross : -1;
        cur->end_id = closed ? rot_id : -1;
        merge_slivers(&ps, closed, CB_BOOL_WELD * cx->min_len);
    }
    cb_status st = CB_OK;
    for (int k = 0; k < ps.n && !fail && !st; k++) {
        cut_run *q = &ps.p[k].run;
        if (!ps.p[k].dropped && q->n >= 2 && length_over(q, 0.1 * cx->min_len))
            st = emit(out, q, c, curve, 0, 1e-6 * cx->min_len, cx->f, err);
    }
    for (int k = 0; k < ps.n; k++)
        free(ps.p[k].run.p);
    free(ps.p);
    free(rot.p);
    if (fail && !st)
        st = cb_error_set(err, CB_ERR_NOMEM, "cuts: out of memory");
    return st;
}

/* Whether p lies in both trimmed faces (ON counting as in). A face spanning a whole period
 * has its seam's two copies at its loops' extremes lo and hi, in general a rounding error
 * e (at most SEAM_REL of the period) short of a period apart or past it; the parity of the loops (cb_face_classify_uv, columns
 * half-open) then counts a column on the seam out (a gap) or crosses its loops twice there (an
 * overlap). A point whose lift lies within band = 2 e of either copy is on the seam and is
 * classified at lo + band, beyond the overlap and short of the gap: a curve running along a
 * seam is inside. */
static int inside_both(const cut_ctx *cx, const cut_pt *p, double cls_tol)
{
    for (int s = 0; s < 2; s++) {
        double uv[2] = {p->uv[s][0], p->uv[s][1]};
        for (int d = 0; d < 2; d++) {
            double lo = cx->lo[s][d], P = cx->P[s][d], band = cx->band[s][d];
            if (band < 0)
                continue;
            double w = wrap(uv[d], lo, P);
            if (w - lo <= band || cx->hi[s][d] - w <= band)
                uv[d] = lo + band;
        }
        /* A point on a pole line (S_u or S_v vanishing: a sphere's pole, a cone's apex) lies
         * on the line that closes a cap in (u, v), which is no edge, so the classification
         * has neither a crossing parity nor an edge to call it ON: it is classified a
         * millionth of the face's extent off the line, inwards, at the parameter the curve
         * has there (a great circle of a sphere face bounded by a VERTEX_LOOP passes over
         * the pole: it was cut there, 0.014 of its length lost, 3 edges unsewn). */
        int col = cb_topo_inverter_collapsed(&cx->f[s]->inv, uv[0], uv[1]);
        for (int q = 0; q < 2; q++)
            if (col & (1 << q)) {
                const double *box = cx->f[s]->uv_box;
                double lo = box[2 - 2 * q], hi = box[3 - 2 * q], *x = uv + 1 - q;
                *x += (*x < 0.5 * (lo + hi) ? 1e-6 : -1e-6) * (hi - lo);
            }
        if (cb_face_classify_uv(cx->f[s], uv[0], uv[1], cls_tol) == CB_FACE_OUT)
            return 0;
    }
    return 1;
}

static int inside_pred(const cut_ctx *cx, const cut_pt *p, const void *arg)
{
    return inside_both(cx, p, *(const double *)arg);
}

/* The point where the curve from a (inside) to b (outside) leaves the faces. */
static void exit_point(cut_pt *out, const cut_ctx *cx, const cut_pt *a, const cut_pt *b,
                       double cls_tol)
{
    cut_pt bu = *b;
    unwrap_next(&bu, cx, a);
    bisect_on_curve(out, cx, a, &bu, inside_pred, &cls_tol);
}

static int cmp_double(const void *x, const void *y)
{
    double a = *(const double *)x, b = *(const double *)y;
    return (a > b) - (a < b);
}

/* Classifying the curve's points alone misses a stretch inside both faces that lies between
 * two points each outside one of them (a line from the SSI's closed forms has points as far
 * apart as it likes: one outside A's hole, the next beyond B's rim), and a dip out of a face
 * between two inside points. So where a step's chord in either face's (u, v) crosses that
 * face's loops (cb_face_chord_crossings), a point is added (moved onto the curve: refine_pt)
 * between every two successive crossings, which the walk in cb_bool_cuts_make then
 * classifies, the exits being bisected as usual. (The chord in (u, v) is not the curve's
 * image: a stretch narrower than that chord error may still be missed.) added[i] (allocated)
 * marks the points added. *pts (n points, replaced) keeps its first and last points. Returns -1
 * when out of memory. */
static int add_crossing_points(cut_pt **pts, char **added, int *n, const cut_ctx *cx)
{
    cut_pt *p = *pts, *out = NULL;
    char *add = NULL;
    int m = 0, cap = 0, nt = 0, tcap = 0, fail = 0;
    double *t = NULL;
    for (int i = 0; i < *n && !fail; i++) {
        int extra = 0;
        cut_pt bu;
        if (i + 1 < *n) {
            bu = p[i + 1];
            unwrap_next(&bu, cx, p + i);
            nt = 0;
            for (int s = 0; s < 2 && !fail; s++)
                fail = cb_face_chord_crossings(&t, &nt, &tcap, cx->f[s], p[i].uv[s], bu.uv[s])
                           ? -1
                           : 0;
            if (nt >= 2) {
                qsort(t, (size_t)nt, sizeof *t, cmp_double);
                extra = nt - 1;
            }
        }
        if (m + 1 + extra > cap) {
            int c = 2 * (m + 1 + extra) + 16;
            cut_pt *q = realloc(out, (size_t)c * sizeof *q);
            char *a = q ? realloc(add, (size_t)c) : NULL;
            if (q)
                out = q;
            if (!a) {
                fail = -1;
                break;
            }
            add = a;
            cap = c;
        }
        add[m] = 0;
        out[m++] = p[i];
        if (!extra)
            continue;
        double ch[3];
        for (int k = 0; k < 3; k++)
            ch[k] = bu.xyz[k] - p[i].xyz[k];
        double L = norm3(ch);
        for (int k = 0; k < 3 && L > 0; k++)
            ch[k] /= L;
        for (int j = 0; j + 1 < nt; j++) {
            if (!(t[j + 1] - t[j] > 1e-9))
                continue; /* one crossing counted twice (a polygon vertex) */
            lerp_pt(out + m, p + i, &bu, 0.5 * (t[j] + t[j + 1]));
            if (L > 1e-2 * cx->min_len)
                refine_pt(out + m, cx, ch, L);
            add[m++] = 1;
        }
    }
    free(t);
    if (fail) {
        free(out);
        free(add);
        return -1;
    }
    free(p);
    *pts = out;
    *added = add;
    *n = m;
    return 0;
}

/* Central (one-sided at open ends, wrapping at closed ones) difference at point i of the
 * dim-vectors pts, and the 3D length of the same step. */
static void difference(double *d, double *len, const cb_bool_cut *k, const double *pts, int dim,
                       int i)
{
    int a = i - 1, z = i + 1;
    if (a < 0)
        a = k->closed ? k->n - 2 : 0;
    if (z >= k->n)
        z = k->closed ? 1 : k->n - 1;
    for (int j = 0; j < dim; j++)
        d[j] = pts[dim * z + j] - pts[dim * a + j];
    double e[3];
    for (int j = 0; j < 3; j++)
        e[j] = k->xyz[3 * z + j] - k->xyz[3 * a + j];
    *len = norm3(e);
}

#define PARABOLA_TURN 0.25 /* radians: parabola_tangent's largest turn between two steps */

/* The tangent direction at point i of cut k from its points alone: the derivative there of
 * the parabola through i and its two neighbours (the two after it, or before it, at an open
 * end), by chord length; (0, 0, 0) where two of them coincide or k has fewer than three
 * points. Second order, where a chord or a central difference is first order with unequal
 * steps (a step split at a seam is next to a whole one): a Hermite arc on a circle of radius
 * R with steps of L leaves the curve by up to L^2 / 8R on a chord's direction. */
static void parabola_tangent(double d[3], const cb_bool_cut *k, int i)
{
    memset(d, 0, 3 * sizeof *d);
    int n = k->n - (k->closed ? 1 : 0); /* distinct points */
    if (n < 3)
        return;
    int id[3]; /* the three points in curve order, and which of them is i */
    int at;
    if (k->closed || (i > 0 && i + 1 < k->n)) {
        id[0] = i > 0 ? i - 1 : n - 1;
        id[1] = i < n ? i : 0;
        id[2] = id[1] + 1 < n ? id[1] + 1 : 0;
        at = 1;
    } else if (i == 0) {
        id[0] = 0, id[1] = 1, id[2] = 2;
        at = 0;
    } else {
        id[0] = k->n - 3, id[1] = k->n - 2, id[2] = k->n - 1;
        at = 2;
    }
    const double *P[3];
    for (int j = 0; j < 3; j++)
        P[j] = k->xyz + 3 * id[j];
    double t[3] = {0, 0, 0}, e[3];
    for (int j = 1; j < 3; j++) {
        for (int q = 0; q < 3; q++)
            e[q] = P[j][q] - P[j - 1][q];
        t[j] = t[j - 1] + norm3(e);
    }
    if (!(t[1] > 0 && t[2] > t[1]))
        return;
    /* Not across a corner (the parabola would round it off and turn the straight
     * segments' tangents): the two steps turn by less than PARABOLA_TURN. */
    double f[3];
    for (int q = 0; q < 3; q++) {
        e[q] = P[1][q] - P[0][q];
        f[q] = P[2][q] - P[1][q];
    }
    if (e[0] * f[0] + e[1] * f[1] + e[2] * f[2] < cos(PARABOLA_TURN) * (t[1] - t[0]) * (t[2] - t[1]))
        return;
    /* The derivatives of the Lagrange basis at t[at]. */
    double w[3], x = t[at];
    for (int j = 0; j < 3; j++) {
        int a = (j + 1) % 3, b = (j + 2) % 3;
        w[j] = (2 * x - t[a] - t[b]) / ((t[j] - t[a]) * (t[j] - t[b]));
    }
    for (int q = 0; q < 3; q++)
        d[q] = w[0] * P[0][q] + w[1] * P[1][q] + w[2] * P[2][q];
}

/* S_u x S_v of the inverter's surface at (u, v), with S_u and S_v. Where one of the partials
 * collapses (a pole of a sphere or an apex written as a B-spline: a whole row of its net is one
 * point) the cross product vanishes or is rounding noise; the normal there is its limit, taken
 * a small step inside along the other parameter. */
static void surface_normal(double n[3], double su[3], double sv[3], const cb_topo_inverter *inv,
                           double u, double v)
{
    double dd[6][3];
    cb_topo_inverter_eval_derivs(dd, inv, u, v);
    memcpy(su, dd[1], sizeof dd[1]);
    memcpy(sv, dd[2], sizeof dd[2]);
    double lu = norm3(dd[1]), lv = norm3(dd[2]);
    int collapsed = lu <= 1e-9 * lv ? 0 : (lv <= 1e-9 * lu ? 1 : -1);
    if (collapsed >= 0) {
        /* step along the parameter that does not collapse, towards the box's middle */
        int d = 1 - collapsed;
        double lo = inv->box[2 * d], hi = inv->box[2 * d + 1], x = d ? v : u;
        double h = 1e-7 * (isfinite(hi - lo) && hi > lo ? hi - lo : 1.0);
        x += (isfinite(lo) && isfinite(hi) && x > 0.5 * (lo + hi)) ? -h : h;
        cb_topo_inverter_eval_derivs(dd, inv, d ? u : x, d ? x : v);
    }
    n[0] = dd[1][1] * dd[2][2] - dd[1][2] * dd[2][1];
    n[1] = dd[1][2] * dd[2][0] - dd[1][0] * dd[2][2];
    n[2] = dd[1][0] * dd[2][1] - dd[1][1] * dd[2][0];
}

/* Tangents of cut k (see cb_bool_cuts_make). */
static void tangents(cb_bool_cut *k, const cb_face *const f[2])
{
    for (int i = 0; i < k->n; i++) {
        double d[6][2][3], n[2][3], chord[3], len;
        difference(chord, &len, k, k->xyz, 3, i);
        /* The end of an open cut may lie on a crease of a face (it was split there:
         * kink_split): its normals are taken a thousandth of the way towards its neighbour,
         * on the cut's side. */
        int nb = k->closed ? i : (i == 0 ? 1 : (i == k->n - 1 ? k->n - 2 : i));
        for (int s = 0; s < 2; s++) {
            const double *a = k->uv[s] + 2 * i, *z = k->uv[s] + 2 * nb;
            surface_normal(n[s], d[1][s], d[2][s], &f[s]->inv, a[0] + 1e-3 * (z[0] - a[0]),
                           a[1] + 1e-3 * (z[1] - a[1]));
        }
        double t[3] = {n[0][1] * n[1][2] - n[0][2] * n[1][1], n[0][2] * n[1][0] - n[0][0] * n[1][2],
                       n[0][0] * n[1][1] - n[0][1] * n[1][0]};
        double tl = norm3(t), cl = norm3(chord);
        double *dir = k->dir + 3 * i;
        if (tl > 1e-6 * norm3(n[0]) * norm3(n[1]) && cl > 0) {
            double sgn = t[0] * chord[0] + t[1] * chord[1] + t[2] * chord[2] < 0 ? -1 : 1;
            for (int j = 0; j < 3; j++)
                dir[j] = sgn * t[j] / tl;
        } else {
            /* The surfaces touch here (a tangential cut): no tangent from the normals. The
             * parabola's, in the common tangent plane (the points' curving along the normal
             * is most of what the chord misses on a curved surface), along the chord. */
            double q[3], nl = norm3(n[0]);
            parabola_tangent(q, k, i);
            if (nl > 0) {
                double qn = (q[0] * n[0][0] + q[1] * n[0][1] + q[2] * n[0][2]) / (nl * nl);
                for (int j = 0; j < 3; j++)
                    q[j] -= qn * n[0][j];
            }
            double ql = norm3(q);
            if (!(ql > 0) || q[0] * chord[0] + q[1] * chord[1] + q[2] * chord[2] <= 0) {
                memcpy(q, chord, sizeof q);
                ql = cl;
            }
            for (int j = 0; j < 3; j++)
                dir[j] = ql > 0 ? q[j] / ql : 0;
        }
        for (int s = 0; s < 2; s++) {
            /* J^T J x = J^T dir, J = [S_u S_v] */
            const double *su = d[1][s], *sv = d[2][s];
            double a = su[0] * su[0] + su[1] * su[1] + su[2] * su[2];
            double b = su[0] * sv[0] + su[1] * sv[1] + su[2] * sv[2];
            double c = sv[0] * sv[0] + sv[1] * sv[1] + sv[2] * sv[2];
            double p = su[0] * dir[0] + su[1] * dir[1] + su[2] * dir[2];
            double q = sv[0] * dir[0] + sv[1] * dir[1] + sv[2] * dir[2];
            double det = a * c - b * b;
            double *w = k->duv[s] + 2 * i;
            if (a <= 1e-18 * c || c <= 1e-18 * a) {
                /* At a pole (settle_poles' test): the collapsed parameter is held at its
                 * neighbour's value, so it does not move; the other follows dir. The solve
                 * would divide round-off by |S_u|^2 ~ 0 and send the pcurve across the
                 * parameter plane at the curve's end. */
                int col = a <= 1e-18 * c ? 0 : 1;
                w[col] = 0;
                w[1 - col] = col ? (a > 0 ? p / a : 0) : (c > 0 ? q / c : 0);
            } else if (det > 1e-12 * a * c && det > 0) {
                w[0] = (c * p - b * q) / det;
                w[1] = (a * q - b * p) / det;
            } else {
                double du[2], l3;
                difference(du, &l3, k, k->uv[s], 2, i);
                w[0] = l3 > 0 ? du[0] / l3 : 0;
                w[1] = l3 > 0 ? du[1] / l3 : 0;
            }
        }
    }
}

double cb_bool_cut_project(double *pos, const cb_bool_cut *c, const double p[3], double lo,
                           double hi)
{
    double best = HUGE_VAL;
    *pos = lo;
    int i0 = (int)floor(lo), i1 = (int)ceil(hi);
    for (int i = i0 < 0 ? 0 : i0; i < i1 && i + 1 < c->n; i++) {
        const double *a = c->xyz + 3 * i, *b = a + 3;
        double ab[3], ap[3], L2 = 0, dot = 0;
        for (int k = 0; k < 3; k++) {
            ab[k] = b[k] - a[k];
            ap[k] = p[k] - a[k];
            L2 += ab[k] * ab[k];
            dot += ab[k] * ap[k];
        }
        /* within the segment's own stretch of [lo, hi]: a point beyond its ends is a
         * neighbour's, and the line extended past them may pass nearer than the polyline */
        double x = fmin(fmin(hi, i + 1), fmax(fmax(lo, i), i + (L2 > 0 ? dot / L2 : 0)));
        double d2 = 0;
        for (int k = 0; k < 3; k++)
            d2 += (ap[k] - (x - i) * ab[k]) * (ap[k] - (x - i) * ab[k]);
        if (d2 < best) {
            best = d2;
            *pos = x;
        }
    }
    return sqrt(best);
}

/* The Bezier control points of segment i of cut c's curve (cb_bool_cut_curve) in 3D (side
 * -1) or in face side's (u, v): the cubic Hermite arc with the points' tangents, scaled by a
 * third of the segment's 3D chord. */
static void seg_ctrl(double P[4][3], const cb_bool_cut *c, int side, int i)
{
    int dim = side < 0 ? 3 : 2;
    const double *pts = side < 0 ? c->xyz : c->uv[side];
    const double *tan = side < 0 ? c->dir : c->duv[side];
    double e[3];
    for (int j = 0; j < 3; j++)
        e[j] = c->xyz[3 * (i + 1) + j] - c->xyz[3 * i + j];
    double L = norm3(e) / 3;
    memset(P, 0, 4 * sizeof P[0]);
    for (int j = 0; j < dim; j++) {
        P[0][j] = pts[dim * i + j];
        P[1][j] = pts[dim * i + j] + L * tan[dim * i + j];
        P[2][j] = pts[dim * (i + 1) + j] - L * tan[dim * (i + 1) + j];
        P[3][j] = pts[dim * (i + 1) + j];
    }
}

void cb_bool_cut_point(double *x, const cb_bool_cut *c, int side, double pos)
{
    int dim = side < 0 ? 3 : 2;
    pos = fmin(fmax(pos, 0), c->n - 1);
    int i = (int)floor(pos);
    if (i > c->n - 2)
        i = c->n - 2;
    double t = pos - i, s = 1 - t, P[4][3];
    seg_ctrl(P, c, side, i);
    for (int j = 0; j < dim; j++)
        x[j] = s * s * s * P[0][j] + 3 * s * s * t * P[1][j] + 3 * s * t * t * P[2][j] +
               t * t * t * P[3][j];
}

cb_status cb_bool_cut_curve(cb_topo_curve *out, const cb_bool_cut *c, int side, cb_error *err)
{
    int m = 3 * (c->n - 1) + 1;
    double *P = calloc((size_t)m * 3, sizeof(double));
    double *K = malloc((size_t)(m + 4) * sizeof(double));
    if (!P || !K) {
        free(P);
        free(K);
        return cb_error_set(err, CB_ERR_NOMEM, "cuts: out of memory");
    }
    for (int i = 0; i + 1 < c->n; i++) {
        double B[4][3];
        seg_ctrl(B, c, side, i);
        memcpy(P + 3 * (3 * i), B, sizeof B);
    }
    /* Knots: 0 four times, every inner position three times, n - 1 four times. */
    int j = 0;
    for (int r = 0; r < 4; r++)
        K[j++] = 0;
    for (int i = 1; i + 1 < c->n; i++)
        for (int r = 0; r < 3; r++)
            K[j++] = i;
    for (int r = 0; r < 4; r++)
        K[j++] = c->n - 1;
    out->kind = CB_CURVE_NURBS;
    cb_status st = cb_nurbs_curve_make(out->nurbs, 3, K, m + 4, P, NULL, m, err);
    free(P);
    free(K);
    return st;
}

/* How far a cut end at x may lie from the same crossing computed on the other side of a face
 * boundary, beyond the weld distance: the largest tolerance of a boundary edge of either of
 * its faces that passes within reach (plus that tolerance) of x, where the tolerance is the
 * edge's own (the reader raises it where the file's faces stray from their shared edge) or
 * the deviation of the face's pcurve from it. The two faces of such an edge meet it only
 * within that tolerance, so the SSI's ends of one crossing, each clipped to its own face,
 * differ by up to twice as much and more where the other surface crosses the edge obliquely.
 * 0 away from every edge; negligible beside the weld distance where the edges' tolerances
 * are the model's. */
static double end_slack(const cb_face *const f[2], const double x[3], double reach)
{
    double s = 0;
    for (int k = 0; k < 2; k++)
        for (int e = 0; e < f[k]->n_edges; e++) {
            const cb_face_edge *E = f[k]->edges + e;
            double t = fmax(f[k]->b->edges[E->edge].tol, E->off);
            if (!E->boundary || t <= s)
                continue;
            double lim = reach + t + E->gap;
            int out_box = 0;
            for (int q = 0; q < 3; q++)
                out_box |= x[q] < E->box.lo[q] - lim || x[q] > E->box.hi[q] + lim;
            for (int i = 0; i <= E->n && !out_box; i++) {
                double g[3] = {E->samples[i][0] - x[0], E->samples[i][1] - x[1],
                               E->samples[i][2] - x[2]};
                if (norm3(g) <= lim) {
                    s = t;
                    break;
                }
            }
        }
    return s;
}

/* Curves that meet at a node (where an intersection curve passes from one face to the next)
 * reach it from two face pairs computed apart, so their ends differ by up to the polyline's
 * chord error. Ends within weld of an earlier end (in cut order) are moved onto it, their
 * parameters found again on both faces from the old ones, so that the pieces sewn at the node
 * meet in (u, v) as well as in space. Where the moved end lay on the boundary of a face the
 * two cuts share (within near) and the earlier end does not, both ends take the moved end's
 * (u, v) on that face: the node is where the curve leaves that face. Two vertices closer than
 * weld (an edge of one operand passing that close to an edge or seam of the other) weld into
 * one, so in that face's split the node must lie on its boundary too, or the cut ending there
 * would end short of it and the region it closes stay open. An end with no earlier end within
 * weld is moved onto the nearest earlier end within weld plus both ends' end_slack (an edge of
 * raised tolerance nearby), keeping its (u, v) on a face the other cut does not share: the
 * node is that face's boundary point, within the edge's tolerance of the other end. */
static void snap_ends(cb_bool_cuts *out, const cb_bool_solid *A, const cb_bool_solid *B,
                      double weld, double near)
{
    /* Per cut end, the slack of end_slack (0 for closed cuts). */
    double *slack = calloc((size_t)(2 * out->n + 1), sizeof(double));
    for (int k = 0; k < out->n && slack; k++) {
        const cb_bool_cut *c = out->cut + k;
        const cb_face *f[2] = {cb_bool_solid_face(A, c->face[0]),
                               cb_bool_solid_face(B, c->face[1])};
        for (int e = 0; e < 2 && !c->closed; e++)
            slack[2 * k + e] = end_slack(f, c->xyz + 3 * (e ? c->n - 1 : 0), weld);
    }
    for (int k = 0; k < out->n; k++) {
        cb_bool_cut *c = out->cut + k;
        if (c->closed)
            continue;
        const cb_face *f[2] = {cb_bool_solid_face(A, c->face[0]),
                               cb_bool_solid_face(B, c->face[1])};
        int moved = 0;
        for (int e = 0; e < 2; e++) {
            int i = e ? c->n - 1 : 0;
            double *x = c->xyz + 3 * i;
            const double *to = NULL;
            cb_bool_cut *d = NULL;
            int dj = 0;
            for (int j = 0; j < k && !to; j++) {
                d = out->cut + j;
                if (d->closed)
                    continue;
                for (int h = 0; h < 2 && !to; h++) {
                    const double *y = d->xyz + 3 * (h ? d->n - 1 : 0);
                    const double *other = c->xyz + 3 * (e ? 0 : c->n - 1);
                    double g[3] = {y[0] - x[0], y[1] - x[1], y[2] - x[2]};
                    /* A cut shorter than weld keeps its ends apart: both on one node would
                     * fold it onto itself. */
                    if (norm3(g) <= weld && norm3(g) > 0 && memcmp(y, other, 3 * sizeof *y)) {
                        to = y;
                        dj = h ? d->n - 1 : 0;
                    }
                }
            }
            /* None within weld, before or after it in cut order (an end already on a node
             * with another stays there): near edges of raised tolerance, the nearest earlier
             * end within weld and both ends' slack. */
            double best = HUGE_VAL;
            int bj = -1, bh = 0, met = 0;
            for (int j = 0; j < out->n && !to && !met && slack && slack[2 * k + e] > 0; j++) {
                const cb_bool_cut *dd = out->cut + j;
                for (int h = 0; h < 2 && j != k && !dd->closed && !met; h++) {
                    const double *y = dd->xyz + 3 * (h ? dd->n - 1 : 0);
                    const double *other = c->xyz + 3 * (e ? 0 : c->n - 1);
                    double g[3] = {y[0] - x[0], y[1] - x[1], y[2] - x[2]}, dist = norm3(g);
                    if (!memcmp(y, other, 3 * sizeof *y))
                        continue;
                    met = dist <= weld;
                    if (j < k && dist <= weld + slack[2 * k + e] + slack[2 * j + h] &&
                        dist < best) {
                        best = dist;
                        bj = j;
                        bh = h;
                    }
                }
            }
            int wide = 0;
            if (!to && !met && bj >= 0) {
                d = out->cut + bj;
                to = d->xyz + 3 * (bh ? d->n - 1 : 0);
                dj = bh ? d->n - 1 : 0;
                wide = 1;
            }
            if (!to)
                continue;
            double old[2][2];
            int on[2];
            for (int s = 0; s < 2; s++) {
                memcpy(old[s], c->uv[s] + 2 * i, sizeof old[s]);
                on[s] = on_split_boundary(f[s], old[s], near);
            }
            memcpy(x, to, 3 * sizeof(double));
            for (int s = 0; s < 2; s++) {
                double guess[2] = {c->uv[s][2 * i], c->uv[s][2 * i + 1]};
                double *uv = c->uv[s] + 2 * i;
                cb_topo_inverter_invert(uv, &f[s]->inv, x, guess);
                /* keep the lift the cut had (a node on a seam has two), and at a pole the
                 * parameter the cut arrived with (settle_poles) */
                int col = cb_topo_inverter_collapsed(&f[s]->inv, uv[0], uv[1]);
                int pole = 0;
                for (int q = 0; q < 2; q++) {
                    double P = f[s]->inv.period[q];
                    if (col & (1 << q)) {
                        uv[q] = guess[q];
                        pole = 1;
                    } else {
                        uv[q] = lift_near(uv[q], guess[q], P);
                    }
                }
                /* Moved further than the weld distance (slack of an edge of raised
                 * tolerance): an end on its face's split boundary stays there in (u, v), the
                 * node being the boundary's point within that tolerance; inverted, it could
                 * land inside the face and leave the cut dangling in its arrangement. */
                if (wide && d->face[s] != c->face[s])
                    memcpy(uv, old[s], sizeof old[s]);
                /* (at a pole the node's (u, v) is the line the cuts arrive on, each its own) */
                if (!on[s] || pole || d->face[s] != c->face[s])
                    continue;
                double *ud = d->uv[s] + 2 * dj;
                if (!on_split_boundary(f[s], ud, near)) {
                    for (int q = 0; q < 2; q++)
                        ud[q] = lift_near(old[s][q], ud[q], f[s]->inv.period[q]);
                    const cb_face *fd[2] = {cb_bool_solid_face(A, d->face[0]),
                                            cb_bool_solid_face(B, d->face[1])};
                    tangents(d, fd);
                }
                /* one point of (u, v), in the lift the cut had */
                for (int q = 0; q < 2; q++)
                    uv[q] = lift_near(ud[q], old[s][q], f[s]->inv.period[q]);
            }
            moved = 1;
        }
        if (moved)
            tangents(c, f);
    }
    free(slack);
}

/* Whether segment sg of face f lies on an edge that can hold boundary points (not a seam of
 * the face, not collapsed, not a straight join along a pole line). */
static int boundary_seg(const cb_face *f, const cb_face_seg *sg)
{
    if (sg->coedge < 0)
        return 0;
    int e = f->b->coedges[sg->coedge].edge;
    for (int k = 0; k < f->n_edges; k++)
        if (f->edges[k].edge == e)
            return f->edges[k].boundary;
    return 0;
}

/* Distance in space from x to face f's surface at pcurve pc's point at parameter s moved by
 * lift. */
static double pcurve_dist(const cb_face *f, const cb_topo_curve *pc, double s,
                          const double lift[2], const double x[3])
{
    double y[3], p[3];
    cb_topo_pcurve_eval(y, pc, s);
    cb_topo_inverter_eval(p, &f->inv, y[0] + lift[0], y[1] + lift[1]);
    double g[3] = {p[0] - x[0], p[1] - x[1], p[2] - x[2]};
    return norm3(g);
}

/* The point of face f's boundary nearest to the point x in space, whose (u, v) on f is uv,
 * into near_uv (lifted next to uv): on the pcurve of the loop polygon's segment nearest to uv
 * in the metric of the surface's derivatives at uv, the point of the surface nearest to x
 * (golden-section search over the segment's pcurve parameters and one segment's length on
 * each side, as the polygon may stray from the pcurve by its deviation), since near a cut the
 * arrangement's loop polylines follow the pcurves (op.c boundary_srcs); the polygon's point
 * where the coedge has no pcurve. Nearest in space, not in (u, v): where the face strays from
 * its edge (an edge of raised tolerance), x, off the surface, inverts to a (u, v) whose
 * nearest boundary point in (u, v) lies along the edge from the edge's point nearest to x,
 * where the face across the edge puts the same crossing. 0 when the face has no boundary
 * segment. */
static int nearest_boundary_uv(double near_uv[2], const cb_face *f, const double uv[2],
                               const double x[3])
{
    double d[6][3];
    cb_topo_inverter_eval_derivs(d, &f->inv, uv[0], uv[1]);
    double sc[2] = {norm3(d[1]), norm3(d[2])}, best = HUGE_VAL, lift[2] = {0, 0};
    const cb_face_seg *bs = NULL;
    for (int k = 0; k < f->n_segs; k++) {
        const cb_face_seg *sg = f->segs + k;
        if (!boundary_seg(f, sg))
            continue;
        double p[2], q[2], x[2], shift[2];
        for (int i = 0; i < 2; i++) {
            shift[i] = lift_near(uv[i], sg->p[i], f->inv.period[i]) - uv[i];
            p[i] = sg->p[i] - shift[i];
            q[i] = sg->q[i] - shift[i];
        }
        double e[2] = {(q[0] - p[0]) * sc[0], (q[1] - p[1]) * sc[1]};
        double w[2] = {(uv[0] - p[0]) * sc[0], (uv[1] - p[1]) * sc[1]};
        double ee = e[0] * e[0] + e[1] * e[1];
        double t = ee > 0 ? fmin(fmax((w[0] * e[0] + w[1] * e[1]) / ee, 0), 1) : 0;
        for (int i = 0; i < 2; i++)
            x[i] = p[i] + t * (q[i] - p[i]);
        double g = hypot((x[0] - uv[0]) * sc[0], (x[1] - uv[1]) * sc[1]);
        if (g < best) {
            best = g;
            near_uv[0] = x[0];
            near_uv[1] = x[1];
            bs = sg;
            lift[0] = sg->shift[0] - shift[0];
            lift[1] = sg->shift[1] - shift[1];
        }
    }
    if (!bs)
        return 0;
    const cb_topo_coedge *co = f->b->coedges + bs->coedge;
    if (co->pcurve < 0)
        return 1;
    const cb_topo_curve *pc = f->b->pcurves + co->pcurve;
    double span = bs->s1 - bs->s0, a = bs->s0 - span, z = bs->s1 + span;
    double lo = fmin(a, z), hi = fmax(a, z);
    /* The pcurve's own parameter range bounds the search. */
    double r0 = fmin(bs->s0, bs->s1), r1 = fmax(bs->s0, bs->s1);
    for (int k = 0; k < f->n_segs; k++)
        if (f->segs[k].coedge == bs->coedge) {
            r0 = fmin(r0, fmin(f->segs[k].s0, f->segs[k].s1));
            r1 = fmax(r1, fmax(f->segs[k].s0, f->segs[k].s1));
        }
    lo = fmax(lo, r0);
    hi = fmin(hi, r1);
    const double gr = 0.6180339887498949;
    double m1 = hi - gr * (hi - lo), m2 = lo + gr * (hi - lo), f1, f2, y[3];
    f1 = pcurve_dist(f, pc, m1, lift, x);
    f2 = pcurve_dist(f, pc, m2, lift, x);
    for (int it = 0; it < 60; it++) {
        if (f1 <= f2) {
            hi = m2;
            m2 = m1;
            f2 = f1;
            m1 = hi - gr * (hi - lo);
            f1 = pcurve_dist(f, pc, m1, lift, x);
        } else {
            lo = m1;
            m1 = m2;
            f1 = f2;
            m2 = lo + gr * (hi - lo);
            f2 = pcurve_dist(f, pc, m2, lift, x);
        }
    }
    double s_best = f1 <= f2 ? m1 : m2;
    cb_topo_pcurve_eval(y, pc, s_best);
    near_uv[0] = y[0] + lift[0];
    near_uv[1] = y[1] + lift[1];
    return 1;
}

int _cb_cut_along_boundary(const cb_bool_cut *c, int side, const cb_face *F, double tol)
{
    double near = CB_BOOL_SNAP * tol;
    int on = 1;
    for (int i = 0; i < c->n && on; i++)
        on = cb_face_classify_uv(F, c->uv[side][2 * i], c->uv[side][2 * i + 1], near) == CB_FACE_ON;
    /* Points on the boundary do not make the curve between them run along it: a cut of two
     * points across a corner of the face has both on it. The middle of each segment on the
     * cut's curve must be ON too, unless the segment is shorter than the weld distance (its
     * pieces weld into points: kept, it would only leave a sliver). */
    for (int i = 0; i + 1 < c->n && on; i++) {
        double m[2], e[3];
        for (int k = 0; k < 3; k++)
            e[k] = c->xyz[3 * (i + 1) + k] - c->xyz[3 * i + k];
        if (norm3(e) <= CB_BOOL_WELD * tol)
            continue;
        cb_bool_cut_point(m, c, side, i + 0.5);
        on = cb_face_classify_uv(F, m[0], m[1], near) == CB_FACE_ON;
    }
    return on;
}

/* An intersection curve inside a face continues, at each end that is not on the face's
 * boundary, in another cut of that face (the curves of closed solids close up). An end that no
 * other cut of the face meets within weld (a cut along the face's boundary does not count), off the
 * face's boundary but within weld of it, is where the curve reaches the boundary through a piece of
 * curve shorter than the weld distance that the intersection did not give (an edge of the other
 * solid passing that close to an edge of this face: their faces' curves meet near both edges); left
 * as it is, the face's arrangement would keep the cut dangling and not split the face along it. Its
 * (u, v) on that face moves to the boundary's pcurve point nearest to it in space (its point in
 * space and its (u, v) on the other face stay): the pieces' ends weld there. Near an edge of raised
 * tolerance the reach is the weld distance plus twice the end's slack (end_slack): the end, welded
 * to the same crossing on the face across the edge, lies within the edge's tolerance of the edge,
 * and this face's boundary within it again. Ends within half the snap distance of the boundary stay
 * as they are: the arrangement joins them to it. */
static void attach_loose_ends(cb_bool_cuts *out, const cb_bool_solid *A, const cb_bool_solid *B,
                              double tol)
{
    double weld = CB_BOOL_WELD * tol, near = CB_BOOL_SNAP * tol;
    for (int k = 0; k < out->n; k++) {
        cb_bool_cut *c = out->cut + k;
        if (c->closed)
            continue;
        const cb_face *f[2] = {cb_bool_solid_face(A, c->face[0]),
                               cb_bool_solid_face(B, c->face[1])};
        int moved = 0;
        for (int e = 0; e < 2; e++) {
            int i = e ? c->n - 1 : 0;
            const double *x = c->xyz + 3 * i;
            double slack = -1; /* end_slack of x, found when first needed */
            for (int s = 0; s < 2; s++) {
                int met = 0;
                for (int j = 0; j < out->n && !met; j++) {
                    const cb_bool_cut *d = out->cut + j;
                    if (j == k || d->closed || d->face[s] != c->face[s])
                        continue;
                    for (int h = 0; h < 2 && !met; h++) {
                        const double *y = d->xyz + 3 * (h ? d->n - 1 : 0);
                        double g[3] = {y[0] - x[0], y[1] - x[1], y[2] - x[2]};
                        met = norm3(g) <= weld;
                    }
                    /* A cut along the face's boundary does not meet it there: the face's
                     * split drops it (near an edge that lies off the surface, the other
                     * solid's small faces along the edge give such cuts, which wander
                     * within the edge's distance around the boundary). */
                    if (met)
                        met = !_cb_cut_along_boundary(d, s, f[s], tol);
                }
                double *uv = c->uv[s] + 2 * i, to[2] = {0, 0}, y[3];
                if (met || cb_topo_inverter_collapsed(&f[s]->inv, uv[0], uv[1]) ||
                    on_window_end(f[s], uv) || !nearest_boundary_uv(to, f[s], uv, x))
                    continue;
                /* Within half the snap distance the arrangement joins the end to the loop
                 * as it is. */
                cb_topo_inverter_eval(y, &f[s]->inv, to[0], to[1]);
                double g[3] = {y[0] - x[0], y[1] - x[1], y[2] - x[2]}, dist = norm3(g);
                if (dist <= 0.5 * near)
                    continue;
                if (slack < 0)
                    slack = end_slack(f, x, weld);
                if (dist > weld + 2 * slack)
                    continue;
                uv[0] = to[0];
                uv[1] = to[1];
                moved = 1;
            }
        }
        if (moved)
            tangents(c, f);
    }
}

cb_status cb_bool_cuts_make(cb_bool_cuts *out, const cb_ssi_result_struct *r,
                            const cb_bool_solid *A, const cb_bool_solid *B, double tol,
                            cb_error *err)
{
    if (!(tol > 0) || !isfinite(tol))
        return cb_error_set(err, CB_ERR_INVALID, "cuts: tolerance %g is not positive", tol);
    cb_status st = CB_OK;
    /* Parity alone decides inside/outside: an ON answer (within this of an edge) counts as
     * inside, and the exit point is then refined by the bisection. */
    double cls_tol = 1e-3 * tol;
    for (slong k = 0; k < r->n_curves && !st; k++) {
        const cb_ssi_curve *c = r->curve + k;
        if (c->n < 2)
            continue;
        cut_ctx cx;
        _cb_cut_ctx_init(&cx, cb_bool_solid_face(A, c->face_a), cb_bool_solid_face(B, c->face_b),
                         tol);
        int n = (int)c->n;
        cut_pt *pts = malloc((size_t)n * sizeof *pts);
        char *in = malloc((size_t)n);
        if (!pts || !in) {
            free(pts);
            free(in);
            return cb_error_set(err, CB_ERR_NOMEM, "cuts: out of memory");
        }
        int n_in = 0, first_out = -1;
        for (int i = 0; i < n; i++) {
            memcpy(pts[i].xyz, c->pt[i].xyz, sizeof pts[i].xyz);
            memcpy(pts[i].uv[0], c->pt[i].uv_a, 2 * sizeof(double));
            memcpy(pts[i].uv[1], c->pt[i].uv_b, 2 * sizeof(double));
        }
        for (int s = 0; s < 2; s++)
            cb_topo_settle_poles(pts[0].uv[s], sizeof *pts, n, &cx.f[s]->inv);
        char *in2 = NULL, *added = NULL;
        if (add_crossing_points(&pts, &added, &n, &cx) || !(in2 = realloc(in, (size_t)n))) {
            free(pts);
            free(in);
            free(added);
            return cb_error_set(err, CB_ERR_NOMEM, "cuts: out of memory");
        }
        in = in2;
        for (int i = 0; i < n; i++) {
            in[i] = (char)inside_both(&cx, pts + i, cls_tol);
            n_in += in[i];
            if (!in[i] && first_out < 0)
                first_out = i;
        }
        cut_run run = {0, 0, NULL};
        if (n_in == n) {
            for (int i = 0; i < n && !st; i++)
                if (_cb_cut_run_push(&run, pts + i))
                    st = cb_error_set(err, CB_ERR_NOMEM, "cuts: out of memory");
            if (!st)
                st = _cb_cut_split_emit(out, &run, c->closed, &cx, c, (int)k, err);
        } else if (n_in > 0) {
            /* Walk the points once (a closed curve from an outside point round to it), one
             * run per stretch inside, cut at the exit points. */
            int start = c->closed ? first_out : 0, steps = c->closed ? n - 1 : n;
            int prev_in = 0;
            const cut_pt *prev = NULL;
            /* A run of points all added between the curve's own (add_crossing_points) and
             * shorter than the weld distance is a graze of a corner the SSI's points did not
             * see: its piece would weld into a point on one face and leave a sliver region
             * on the other. */
            int own = 0;
            double graze = CB_BOOL_WELD * tol;
            for (int j = 0; j <= steps && !st; j++) {
                if (!c->closed && j == steps)
                    break;
                int i = c->closed ? (start + j) % (n - 1) : j;
                const cut_pt *p = pts + i;
                if (in[i] && !prev_in && prev) {
                    cut_pt x;
                    exit_point(&x, &cx, p, prev, cls_tol);
                    if (_cb_cut_run_push(&run, &x))
                        st = cb_error_set(err, CB_ERR_NOMEM, "cuts: out of memory");
                }
                if (in[i] && !st && _cb_cut_run_push(&run, p))
                    st = cb_error_set(err, CB_ERR_NOMEM, "cuts: out of memory");
                own |= in[i] && !added[i];
                if (!in[i] && prev_in && !st) {
                    cut_pt x;
                    exit_point(&x, &cx, prev, p, cls_tol);
                    if (_cb_cut_run_push(&run, &x))
                        st = cb_error_set(err, CB_ERR_NOMEM, "cuts: out of memory");
                    else if (run.n >= 2 && (own || length_over(&run, graze)))
                        st = _cb_cut_split_emit(out, &run, 0, &cx, c, (int)k, err);
                    run.n = 0;
                    own = 0;
                }
                prev_in = in[i];
                prev = p;
            }
            if (!st && run.n >= 2 && (own || length_over(&run, graze)))
                st = _cb_cut_split_emit(out, &run, 0, &cx, c, (int)k, err);
        }
        free(run.p);
        free(pts);
        free(in);
        free(added);
    }
    if (!st)
        st = _cb_cuts_imprint(out, r, A, B, tol, err);
    if (!st)
        snap_ends(out, A, B, CB_BOOL_WELD * tol, CB_BOOL_SNAP * tol);
    if (!st)
        attach_loose_ends(out, A, B, tol);
    if (st)
        cb_bool_cuts_clear(out);
    return st;
}

/* The two solids of _cb_bool_solids_cuts, one per task. */
typedef struct {
    cb_bool_solid **S;
    const cb_topo_body *body[2];
    double tol;
    cb_status st[2];
    cb_error err[2];
} solids_job;

static void solids_body(void *v, size_t begin, size_t end)
{
    solids_job *j = v;
    for (size_t k = begin; k < end; k++)
        j->st[k] = cb_bool_solid_new(j->S + k, j->body[k], j->tol, j->err + k);
}

cb_status _cb_bool_solids_cuts(cb_bool_solid *S[2], cb_bool_cuts *cuts,
                               const cb_ssi_result_struct *r, const cb_topo_body *A,
                               const cb_topo_body *B, double tol, int threads, cb_error *err)
{
    S[0] = S[1] = NULL;
    cb_bool_cuts_init(cuts);
    solids_job j = {S, {A, B}, tol, {CB_OK, CB_OK}, {{0}, {0}}};
    cb_status st = cb_parallel_for(2, 1, threads, solids_body, &j);
    if (st)
        return cb_error_set(err, st, "bool: preparing the solids in parallel failed: %s",
                            cb_status_name(st));
    for (int k = 0; k < 2 && !st; k++)
        if ((st = j.st[k]) && err)
            *err = j.err[k];
    if (!st)
        st = cb_bool_cuts_make(cuts, r, S[0], S[1], tol, err);
    return st;
}
