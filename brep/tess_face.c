/* Triangulation of one trimmed face in its parameter domain (see tess.h for the method). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "brep/geom.h"
#include "brep/tess.h"
#include "brep/tess_internal.h"

/* Refinement stops here: a face needing more points than this is refused (CB_ERR_NUMERIC)
 * rather than exhausting memory on a tolerance far below the model's precision. */
#define FACE_MAX_POINTS 4000000
#define FACE_MAX_PASSES 80
/* The normal test samples the surface at each corner moved this fraction of the way towards
 * each of the other two corners: inside the triangle by far more than rounding, near enough to
 * the corner to stand for it on a smooth surface. */
#define CORNER_INSET 1e-3

void cb_tess_face_mesh_init(cb_tess_face_mesh *fm)
{
    memset(fm, 0, sizeof *fm);
}

void cb_tess_face_mesh_clear(cb_tess_face_mesh *fm)
{
    free(fm->xyz);
    free(fm->tri);
    cb_tess_face_mesh_init(fm);
}

/* ---------------------------------------------------------------- boundary loops ----------- */

/* A line of the surface that collapses to the shared sample id (a pole, an apex), from a to z
 * in (u, v) (unscaled in face_loops, scaled in face_work). */
typedef struct {
    double a[2], z[2];
    int id;
} pole_line;

typedef struct {
    double *uv; /* 2 per point, unscaled parameters */
    int *id;    /* shared sample */
    int n, cap;
    int *loop_end; /* loop k is [loop_end[k - 1], loop_end[k]) */
    int n_loops;
    pole_line *poles;
    int n_poles;
} face_loops;

static void loops_clear(face_loops *L)
{
    free(L->uv);
    free(L->id);
    free(L->loop_end);
    free(L->poles);
}

static int loops_push(face_loops *L, const double uv[2], int id)
{
    if (L->n == L->cap) {
        int c = L->cap ? 2 * L->cap : 256;
        double *nu = realloc(L->uv, (size_t)c * 2 * sizeof(double));
        if (!nu)
            return 0;
        L->uv = nu;
        int *ni = realloc(L->id, (size_t)c * sizeof(int));
        if (!ni)
            return 0;
        L->id = ni;
        L->cap = c;
    }
    L->uv[2 * L->n] = uv[0];
    L->uv[2 * L->n + 1] = uv[1];
    L->id[L->n++] = id;
    return 1;
}

/* Equal up to the rounding of two inversions of one point. */
static int same_uv(const double a[2], const double b[2])
{
    return fabs(a[0] - b[0]) <= 1e-9 * (1 + fabs(a[0])) &&
           fabs(a[1] - b[1]) <= 1e-9 * (1 + fabs(a[1]));
}

/* The shift by whole lifts that brings a onto b, if there is one other than zero: a + shift
 * and b the same point of (u, v), or joined on the surface within gap_tol (two coedges
 * meeting at a vertex welded within the edges' tolerance, their pcurves' ends apart by it). */
static int lifted_onto(double shift[2], const double a[2], const double b[2],
                       const cb_topo_inverter *inv, double gap_tol)
{
    double c[2];
    for (int i = 0; i < 2; i++) {
        shift[i] = inv->lift[i] > 0 ? inv->lift[i] * nearbyint((b[i] - a[i]) / inv->lift[i]) : 0;
        c[i] = a[i] + shift[i];
    }
    return (shift[0] != 0 || shift[1] != 0) &&
           (same_uv(c, b) || cb_topo_inverter_spread(inv, c, b) <= gap_tol);
}

/* Whether a derivative of the surface vanishes at (u, v) against the other: a pole or apex. */
static int at_pole(const cb_topo_inverter *inv, const double uv[2])
{
    double d[6][3];
    cb_topo_inverter_eval_derivs(d, inv, uv[0], uv[1]);
    double a = cb_vec3_norm(d[1]), b = cb_vec3_norm(d[2]);
    return a <= 1e-9 * b || b <= 1e-9 * a;
}

/* Whether the whole line of parameter d through uv (over its period, or the sampled box)
 * lies within gap_tol of S(uv) in space: uv is on a pole line along d. (The end of a
 * degenerate edge running along the pole line has a neighbour on it too, and keeps its
 * place.) */
static int on_pole_line(const cb_topo_inverter *inv, const double uv[2], int d, double gap_tol)
{
    double c[2] = {uv[0], uv[1]};
    double span = inv->period[d] > 0 ? inv->period[d] : inv->box[2 * d + 1] - inv->box[2 * d];
    c[d] += isfinite(span) ? span : 0;
    return !same_uv(c, uv) && cb_topo_inverter_spread(inv, uv, c) <= gap_tol;
}

/* Appends the samples of coedge c in traversal order, placed in (u, v). */
static cb_status coedge_points(face_loops *L, const cb_topo_body *b, int c,
                               const cb_tess_edges *es, const cb_topo_inverter *inv, int have_prev,
                               double gap_tol, cb_error *err)
{
    const cb_topo_coedge *co = &b->coedges[c];
    const cb_topo_edge *E = &b->edges[co->edge];
    int first = es->start[co->edge], m = es->start[co->edge + 1] - first;
    const int *ids = es->ids + first;
    const double *ts = es->t + first;
    int fwd = (co->sense != 0) == (E->same_sense != 0);
    const cb_topo_curve *pc = co->pcurve >= 0 ? &b->pcurves[co->pcurve] : NULL;
    double s0 = 0, s1 = 0, ta = fwd ? ts[0] : ts[m - 1], tb = fwd ? ts[m - 1] : ts[0];
    if (pc)
        cb_topo_coedge_pcurve_range(&s0, &s1, b, c, inv, fmax(b->tol, E->tol));
    double shift[2] = {0, 0}, prev[2] = {0, 0};
    int n0 = L->n;
    if (have_prev) {
        prev[0] = L->uv[2 * (L->n - 1)];
        prev[1] = L->uv[2 * (L->n - 1) + 1];
    }
    for (int k = 0; k < m; k++) {
        int idx = fwd ? k : m - 1 - k;
        const double *P = es->xyz + 3 * ids[idx];
        double uv[2], guess[2];
        const double *g = NULL;
        if (pc) {
            double w[3], s = tb != ta ? s0 + (ts[idx] - ta) / (tb - ta) * (s1 - s0) : s0;
            cb_topo_pcurve_eval(w, pc, s);
            guess[0] = w[0];
            guess[1] = w[1];
            /* Files lift single pcurves by whole periods (a sphere's latitude by 2 pi): move
             * this coedge onto the end of the previous one when a lift makes them meet, unless
             * they already meet along a pole line (the seam coedges of a sphere face leave
             * the pole at u = 2 pi and come back at u = 0: no lift). */
            if (k == 0 && have_prev && !same_uv(guess, prev) &&
                cb_topo_inverter_spread(inv, prev, guess) > gap_tol) {
                double sh[2];
                if (lifted_onto(sh, guess, prev, inv, gap_tol)) {
                    shift[0] = sh[0];
                    shift[1] = sh[1];
                }
            }
            guess[0] += shift[0];
            guess[1] += shift[1];
            g = guess;
        } else if (have_prev || k > 0) {
            g = prev;
        }
        cb_topo_inverter_invert(uv, inv, P, g);
        if (pc && at_pole(inv, g) && cb_topo_inverter_spread(inv, g, uv) <= gap_tol) {
            /* At a pole the inversion slides along the collapsed line towards a vertex a
             * rounding error off the pole (a Boolean's, where a box edge meets the pole): the
             * pcurve's place on the line is the one the loop runs through. */
            uv[0] = g[0];
            uv[1] = g[1];
        }
        if (!(isfinite(uv[0]) && isfinite(uv[1])))
            return cb_error_set(err, CB_ERR_NUMERIC, "coedge %d: sample %d has no (u, v)", c,
                                k);
        int last = L->n - 1;
        if (k == 0 && have_prev) {
            if (L->id[last] != ids[idx])
                return cb_error_set(err, CB_ERR_NUMERIC,
                                    "coedge %d does not start where the previous one ends", c);
            if (cb_topo_inverter_spread(inv, L->uv + 2 * last, uv) > gap_tol)
                return cb_error_set(err, CB_ERR_NUMERIC,
                                    "gap in (u, v) before coedge %d: (%g, %g) to (%g, %g)", c,
                                    L->uv[2 * last], L->uv[2 * last + 1], uv[0], uv[1]);
        }
        int dup = (have_prev || k > 0) && L->id[last] == ids[idx] && same_uv(L->uv + 2 * last, uv);
        if (!dup && !loops_push(L, uv, ids[idx]))
            return cb_error_set(err, CB_ERR_NOMEM, "out of memory");
        prev[0] = uv[0];
        prev[1] = uv[1];
    }
    /* An end at a pole: its place on the pole line is the pcurve's value there, which a
     * curve passing over the pole (a Boolean's cut through it, split there) may carry from
     * the far side; the collapsed parameter is the one the coedge leaves or arrives with,
     * so the loop runs along the pole line between coedges and not across the face. */
    for (int e = 0; e < 2 && L->n - n0 >= 2; e++) {
        int i = e ? L->n - 1 : n0, j = e ? L->n - 2 : n0 + 1;
        for (int d = 0; d < 2; d++)
            if (on_pole_line(inv, L->uv + 2 * i, d, gap_tol) &&
                !on_pole_line(inv, L->uv + 2 * j, d, gap_tol))
                L->uv[2 * i + d] = L->uv[2 * j + d];
    }
    return CB_OK;
}

/* Twice the signed area in (u, v) of the closed polygon pts[2 start .. 2 end). */
static double loop_area2(const double *uv, int start, int end)
{
    double a = 0;
    for (int i = start; i < end; i++) {
        int j = i + 1 < end ? i + 1 : start;
        a += uv[2 * i] * uv[2 * j + 1] - uv[2 * j] * uv[2 * i + 1];
    }
    return a;
}

/* A face's only loop has the face on its left in (u, v) (signed area of sign `want`: +1 when
 * the face runs with its surface). Where it meets two pole lines of a surface periodic along
 * them (half an ellipsoid cut through both poles, as a Boolean leaves it: two meridians and
 * no seam edge), its samples do not say which way it runs along them: the meridians' lift
 * by a period decides whether the strip between them or the rest of the surface is inside.
 * The part between the two pole junctions is moved by the period that puts the face on the
 * left. A loop that meets no pole or one pole, or already turns the right way, is kept. */
static void lift_pole_strip(face_loops *L, int start, const cb_topo_inverter *inv, int want,
                            double gap_tol)
{
    int end = L->n, jn[2], n_j = 0;
    for (int i = start; i < end; i++) {
        int j = i + 1 < end ? i + 1 : start;
        if (L->id[i] == L->id[j] && !same_uv(L->uv + 2 * i, L->uv + 2 * j) &&
            cb_topo_inverter_spread(inv, L->uv + 2 * i, L->uv + 2 * j) <= gap_tol) {
            if (n_j == 2)
                return;
            jn[n_j++] = i;
        }
    }
    double a = loop_area2(L->uv, start, end);
    if (n_j != 2 || !(a * want < 0))
        return;
    /* The pole lines run along the parameter whose period is used. */
    const double *p = L->uv + 2 * jn[0], *q = L->uv + 2 * (jn[0] + 1 < end ? jn[0] + 1 : start);
    int d = fabs(p[0] - q[0]) >= fabs(p[1] - q[1]) ? 0 : 1;
    double per = inv->period[d];
    if (!(per > 0))
        return;
    for (int sgn = -1; sgn <= 1; sgn += 2) {
        for (int i = jn[0] + 1; i <= jn[1]; i++)
            L->uv[2 * i + d] += sgn * per;
        if (loop_area2(L->uv, start, end) * want > 0)
            return;
        for (int i = jn[0] + 1; i <= jn[1]; i++)
            L->uv[2 * i + d] -= sgn * per;
    }
}

/* The loops of a face as closed polygons in (u, v) (the closing segment implied). A junction
 * of two coedges at different (u, v) must lie on a line of the surface that collapses to the
 * junction's vertex (a pole): its spread on the surface must stay within gap_tol. */
static cb_status build_loops(face_loops *L, const cb_topo_body *b, int face,
                             const cb_tess_edges *es, const cb_topo_inverter *inv, double gap_tol,
                             cb_error *err)
{
    const cb_topo_face *F = &b->faces[face];
    L->loop_end = malloc((size_t)(F->count + 1) * sizeof(int));
    if (!L->loop_end)
        return cb_error_set(err, CB_ERR_NOMEM, "out of memory");
    for (int l = 0; l < F->count; l++) {
        const cb_topo_loop *lp = &b->loops[F->first + l];
        int start = L->n;
        for (int k = 0; k < lp->count; k++) {
            int c = lp->first + k;
            cb_status st = coedge_points(L, b, c, es, inv, k > 0, gap_tol, err);
            if (st)
                return cb_error_prefix(err, "loop %d: ", F->first + l);
        }
        if (L->n - start >= 2) {
            int last = L->n - 1;
            const double *a = L->uv + 2 * last, *z = L->uv + 2 * start;
            double sh[2];
            if (L->id[last] != L->id[start])
                return cb_error_set(err, CB_ERR_NUMERIC, "loop %d is not closed",
                                    F->first + l);
            if (same_uv(a, z))
                L->n--;
            else if (cb_topo_inverter_spread(inv, a, z) <= gap_tol)
                ; /* closed along a pole line: the closing segment runs on the collapsed line */
            else if (lifted_onto(sh, a, z, inv, gap_tol))
                return cb_error_set(err, CB_ERR_UNSUPPORTED,
                                    "loop %d wraps around the periodic surface without a seam "
                                    "edge",
                                    F->first + l);
            else
                return cb_error_set(err, CB_ERR_NUMERIC,
                                    "loop %d does not close in (u, v): (%g, %g) to (%g, %g)",
                                    F->first + l, a[0], a[1], z[0], z[1]);
        }
        if (L->n - start < 3)
            return cb_error_set(err, CB_ERR_NUMERIC, "loop %d has fewer than 3 points in (u, v)",
                                F->first + l);
        if (F->count == 1)
            lift_pole_strip(L, start, inv, F->same_sense ? 1 : -1, gap_tol);
        L->loop_end[L->n_loops++] = L->n;
    }
    return CB_OK;
}

/* Most pole copies put on one pole line. */
#define POLE_MAX_COPIES 256
static const double TWO_PI = 6.283185307179586;

/* Finds the pole lines of the loops (consecutive points of one sample at different (u, v)
 * whose segment collapses on the surface: a loop's jump along a pole, a collapsed edge) and
 * puts copies of the pole sample along each, one per angle_tol of the turn the line spans
 * (its length over the period, or over the domain, times 2 pi). Round the pole the mesh must
 * turn as u runs along the line; copies spread along it give the triangles near the pole
 * corners there from the start, where two ends alone would join everything near the pole
 * to one end (see pole_fold for what that does). */
static cb_status densify_poles(face_loops *L, const cb_topo_inverter *inv, double angle_tol,
                               double gap_tol, cb_error *err)
{
    face_loops N = {0};
    N.loop_end = malloc((size_t)(L->n_loops + 1) * sizeof(int));
    if (!N.loop_end)
        return cb_error_set(err, CB_ERR_NOMEM, "out of memory");
    int cap_poles = 0;
    for (int l = 0, start = 0; l < L->n_loops; start = L->loop_end[l++]) {
        for (int k = start; k < L->loop_end[l]; k++) {
            int next = k + 1 < L->loop_end[l] ? k + 1 : start;
            const double *a = L->uv + 2 * k, *z = L->uv + 2 * next;
            if (!loops_push(&N, a, L->id[k]))
                goto nomem;
            if (L->id[k] != L->id[next] || same_uv(a, z) ||
                cb_topo_inverter_spread(inv, a, z) > gap_tol)
                continue;
            if (N.n_poles == cap_poles) {
                cap_poles = cap_poles ? 2 * cap_poles : 4;
                pole_line *np = realloc(N.poles, (size_t)cap_poles * sizeof *np);
                if (!np)
                    goto nomem;
                N.poles = np;
            }
            N.poles[N.n_poles++] = (pole_line){{a[0], a[1]}, {z[0], z[1]}, L->id[k]};
            double turn = 0;
            for (int i = 0; i < 2; i++) {
                double ext = inv->period[i] > 0 ? inv->period[i]
                                                : inv->box[2 * i + 1] - inv->box[2 * i];
                if (isfinite(ext) && ext > 0)
                    turn = fmax(turn, TWO_PI * fabs(z[i] - a[i]) / ext);
            }
            int n = (int)fmin(ceil(turn / angle_tol), POLE_MAX_COPIES);
            for (int j = 1; j < n; j++) {
                double uv[2] = {a[0] + (z[0] - a[0]) * j / n, a[1] + (z[1] - a[1]) * j / n};
                if (!loops_push(&N, uv, L->id[k]))
                    goto nomem;
            }
        }
        N.loop_end[N.n_loops++] = N.n;
    }
    loops_clear(L);
    *L = N;
    return CB_OK;
nomem:
    loops_clear(&N);
    return cb_error_set(err, CB_ERR_NOMEM, "out of memory");
}

/* ---------------------------------------------------------------- refinement --------------- */

typedef struct {
    const cb_topo_body *b;
    const cb_topo_inverter *inv;
    const cb_tess_opts *o;
    const double *es_xyz; /* the shared samples */
    const cb_tess_edges *es;
    int face;
    double su, sv;   /* metric: x = su u, y = sv v */
    double sign;     /* +1: face normal S_u x S_v */
    double cos_tol;  /* cos(angle_tol) */
    double min_side; /* triangles smaller than this are never split */
    double min_normal_width; /* nor split for their normals when narrower than this */
    cb_tess_cdt d;
    int *gid;      /* per triangulation point: shared sample, -1 own point, -2 enclosing */
    double *xyz;   /* per point, 3D */
    int cap;
    const pole_line *poles; /* scaled (u, v) */
    int n_poles;
    cb_tess_zone *zones; /* this face's, where the chordal tolerance is tighter */
    int n_zones;
    const int *splits; /* cb_tess_hints */
    int n_splits;
} face_work;

static void work_clear(face_work *w)
{
    free(w->zones);
    cb_tess_cdt_clear(&w->d);
    free(w->gid);
    free(w->xyz);
}

/* Unit face normal from surface derivatives; 0 where S_u x S_v vanishes (a pole). */
static void face_normal(double n[3], const double d[6][3], double sign)
{
    cb_vec3_cross(n, d[1], d[2]);
    double l = cb_vec3_norm(n), s = cb_vec3_norm(d[1]) * cb_vec3_norm(d[2]);
    if (!(l > 1e-10 * s) || !(l > 0)) {
        n[0] = n[1] = n[2] = 0;
        return;
    }
    for (int i = 0; i < 3; i++)
        n[i] *= sign / l;
}

/* Records the data of triangulation point k (just inserted). */
static cb_status point_data(face_work *w, int k, int gid, const double *xyz, cb_error *err)
{
    if (k >= w->cap) {
        int c = w->cap ? 2 * w->cap : 256;
        while (c <= k)
            c *= 2;
        int *ng = realloc(w->gid, (size_t)c * sizeof(int));
        if (ng)
            w->gid = ng;
        double *nx = realloc(w->xyz, (size_t)c * 3 * sizeof(double));
        if (nx)
            w->xyz = nx;
        if (!ng || !nx)
            return cb_error_set(err, CB_ERR_NOMEM, "out of memory");
        w->cap = c;
    }
    w->gid[k] = gid;
    if (gid == -2) {
        memset(w->xyz + 3 * k, 0, sizeof(double[3]));
        return CB_OK;
    }
    if (xyz)
        memcpy(w->xyz + 3 * k, xyz, sizeof(double[3]));
    else
        cb_topo_inverter_eval(w->xyz + 3 * k, w->inv, w->d.p[2 * k] / w->su,
                              w->d.p[2 * k + 1] / w->sv);
    return CB_OK;
}

/* Distance from x to the segment p q. */
static double segment_distance(const double x[3], const double p[3], const double q[3])
{
    double lambda;
    return cb_seg3_nearest(&lambda, p, q, x);
}

/* Distance from x to the triangle p q r: to its plane when x projects inside it, else to the
 * nearest side. */
static double triangle_distance(const double x[3], const double p[3], const double q[3],
                                const double r[3])
{
    double b1, b2, d = cb_tri3_foot(&b1, &b2, p, q, r, x);
    if (d >= 0 && b1 >= 0 && b2 >= 0 && b1 + b2 <= 1)
        return d;
    return fmin(segment_distance(x, p, q),
                fmin(segment_distance(x, q, r), segment_distance(x, r, p)));
}

/* The chordal error of a side p q (r NULL) or of a triangle p q r at the surface point of the
 * scaled (u, v) point x: its distance to the side or triangle, not to the point of it that x
 * maps to linearly. Where the parameterisation runs unevenly along a side, its (u, v) midpoint
 * lands off its 3D midpoint, along the side: no distance from the mesh, yet, beside a boundary
 * segment (which refinement may not split), no insertion could remove it, and centroids chased
 * it into fans of needles against the segment. */
static double chord_error(const face_work *w, const double x[2], const double *p,
                          const double *q, const double *r)
{
    double s[3];
    cb_topo_inverter_eval(s, w->inv, x[0] / w->su, x[1] / w->sv);
    return r ? triangle_distance(s, p, q, r) : segment_distance(s, p, q);
}

/* Edge of interior sample g of es and its index among the edge's samples (the interior samples
 * are numbered edge by edge after the vertices: edge e's first one is n_vertices + start[e] -
 * 2 e). */
static int sample_edge(const face_work *w, int g, int *pos)
{
    const cb_tess_edges *es = w->es;
    int lo = 0, hi = es->n_edges - 1, nv = w->b->n_vertices;
    while (lo < hi) {
        int mid = (lo + hi + 1) / 2;
        if (nv + es->start[mid] - 2 * mid <= g)
            lo = mid;
        else
            hi = mid - 1;
    }
    *pos = g - (nv + es->start[lo] - 2 * lo) + 1;
    return lo;
}

/* Whether the segment between shared samples a and b joins two samples of one edge of the
 * face that are not neighbours along it, or two vertices an edge of another face joins. The
 * face on the edge's other side holds both samples too and may join them the same way: two
 * faces' triangles would then share that segment, an edge of four triangles in the body's mesh
 * (seen where two faces hug a curved edge from its concave side). */
static int same_edge_chord(const face_work *w, int a, int b)
{
    const cb_tess_edges *es = w->es;
    int nv = w->b->n_vertices;
    if (a >= nv && b >= nv) {
        int pa, pb, ea = sample_edge(w, a, &pa), eb = sample_edge(w, b, &pb);
        return ea == eb && abs(pa - pb) > 1;
    }
    if (a >= nv || b >= nv) {
        int v = a < nv ? a : b, pos, e = sample_edge(w, a < nv ? b : a, &pos);
        int m = es->start[e + 1] - es->start[e];
        return (es->ids[es->start[e]] == v && pos > 1) ||
               (es->ids[es->start[e + 1] - 1] == v && pos < m - 2);
    }
    /* Two vertices: joined by an edge of this face sampled in more than one piece, or by an
     * edge of other faces at all (sampled as this one segment, it would be that edge). */
    const cb_topo_body *B = w->b;
    for (int e = 0; e < B->n_edges; e++) {
        int x = B->edges[e].v[0], y = B->edges[e].v[1];
        if (!((x == a && y == b) || (x == b && y == a)))
            continue;
        int mine = 0;
        for (int k = B->edge_start[e]; k < B->edge_start[e + 1] && !mine; k++)
            mine = B->loops[B->coedges[B->edge_coedges[k]].loop].face == w->face;
        if (!mine || es->start[e + 1] - es->start[e] > 2)
            return 1;
    }
    return 0;
}

/* Whether cb_tess_body listed the segment between shared samples a and b as one no face may
 * keep (it found it a side of triangles of two faces: an edge of four triangles). */
static int listed_split(const face_work *w, int a, int b)
{
    for (int k = 0; k < w->n_splits; k++) {
        int x = w->splits[2 * k], y = w->splits[2 * k + 1];
        if ((x == a && y == b) || (x == b && y == a))
            return 1;
    }
    return 0;
}

/* Whether the (u, v) segment a b (scaled) maps to the single point p: its middle within the
 * chordal tolerance of p. */
static int collapsed(const face_work *w, const double a[2], const double b[2], const double p[3])
{
    double m[3];
    cb_topo_inverter_eval(m, w->inv, 0.5 * (a[0] + b[0]) / w->su, 0.5 * (a[1] + b[1]) / w->sv);
    return cb_vec3_dist(m, p) <= w->o->chord_tol;
}

/* Whether triangle t turns the wrong way round a pole in space: the corner k (0 .. 2) that is
 * a copy of the pole, with depth[0], depth[1] the distances of the next two corners from the
 * pole line; -1 when t is no such triangle. Near a pole the surface is polar: a point's angle
 * round the pole is its position along the pole line, its distance from the pole its
 * distance from the line. A triangle (c, p, q), c a copy of the pole, is in space the pole's
 * fan piece from p to q, whatever c's place on the line: it turns round the pole as
 * (c', p, q) turns in (u, v), c' the point of the line at the middle of p's and q's positions
 * along it. When (c', p, q) turns the other way than (c, p, q), c lies beyond both along the
 * line and the piece folds back over its neighbours in space (thin triangles along a cone's
 * seam, whose corners near the apex the triangulation ordered by direction from c in (u, v)
 * rather than by position along the line: OCCT's B-spline cone against a box crossed itself
 * there). */
static int pole_fold(const face_work *w, int t, double depth[2])
{
    const cb_tess_tri *T = &w->d.t[t];
    for (int k = 0; k < 3; k++) {
        int c = T->v[k], p = T->v[(k + 1) % 3], q = T->v[(k + 2) % 3], g = w->gid[c];
        if (g < 0 || w->gid[p] == g || w->gid[q] == g)
            continue;
        const double *C = w->d.p + 2 * c, *P = w->d.p + 2 * p, *Q = w->d.p + 2 * q;
        for (int j = 0; j < w->n_poles; j++) {
            const pole_line *pl = &w->poles[j];
            if (pl->id != g)
                continue;
            double d[2] = {pl->z[0] - pl->a[0], pl->z[1] - pl->a[1]}, len = hypot(d[0], d[1]);
            if (!(len > 0))
                continue;
            d[0] /= len;
            d[1] /= len;
            /* c on this line: its distance across it and its position along it. */
            double across = (C[0] - pl->a[0]) * d[1] - (C[1] - pl->a[1]) * d[0];
            double sc = (C[0] - pl->a[0]) * d[0] + (C[1] - pl->a[1]) * d[1];
            if (fabs(across) > 1e-9 * len || sc < -1e-9 * len || sc > len * (1 + 1e-9))
                continue;
            double sp = (P[0] - pl->a[0]) * d[0] + (P[1] - pl->a[1]) * d[1];
            double sq = (Q[0] - pl->a[0]) * d[0] + (Q[1] - pl->a[1]) * d[1];
            double sm = 0.5 * (sp + sq), m[2] = {pl->a[0] + sm * d[0], pl->a[1] + sm * d[1]};
            /* (corners at one place along the line: in space on one ruling with the pole, a
             * triangle of no area) */
            if (cb_tess_orient2d(m, P, Q) > 0 && fabs(sp - sq) > 1e-12 * len)
                return -1;
            depth[0] = fabs((P[0] - pl->a[0]) * d[1] - (P[1] - pl->a[1]) * d[0]);
            depth[1] = fabs((Q[0] - pl->a[0]) * d[1] - (Q[1] - pl->a[1]) * d[0]);
            return k;
        }
    }
    return -1;
}

/* Flips the folded pole triangles (pole_fold) out of the pole's fans: of t = (c, p, q), the
 * edge from c to the corner farther from the pole, or failing that to the other (when the
 * quad round it is convex), so that corner leaves c's fan and the nearer one stays, which is
 * how the pole's neighbours follow each other round it in space. Each flip takes one
 * triangle from a pole's fan, so this ends; a fold no flip can remove is left as it is. */
static void untangle_poles(face_work *w)
{
    for (int changed = 1, round = 0; changed && round < 1000; round++) {
        changed = 0;
        for (int t = 0; t < w->d.nt; t++) {
            double depth[2];
            int k = w->d.t[t].in ? pole_fold(w, t, depth) : -1;
            if (k < 0)
                continue;
            /* The edge c-p is the side opposite q, c-q the side opposite p. */
            int far = depth[0] >= depth[1] ? (k + 2) % 3 : (k + 1) % 3;
            int near = far == (k + 2) % 3 ? (k + 1) % 3 : (k + 2) % 3;
            if (cb_tess_cdt_flip(&w->d, t, far) || cb_tess_cdt_flip(&w->d, t, near))
                changed = 1;
        }
    }
}

/* Where triangle t must be split, if at all: -1 nowhere; 0 .. 2 at the (u, v) midpoint of its
 * side opposite v[k], a side joining two samples of one edge across the face (same_edge_chord),
 * which a centroid might leave in place; 3 at its centroid, when it is too far from the surface
 * or too steep against it. */
static int split_side(const face_work *w, int t)
{
    const cb_tess_tri *T = &w->d.t[t];
    const double *P[3], *X[3];
    for (int k = 0; k < 3; k++) {
        if (w->gid[T->v[k]] < -1)
            return -1;
        P[k] = w->xyz + 3 * T->v[k];
        X[k] = w->d.p + 2 * T->v[k];
    }
    /* Two corners that are copies of one sample: at a pole (the line between them collapses
     * to that point) the triangle is one of the pole's fan and is left as it is; across a seam
     * (copies a period apart) it spans the face and must be split like any other. */
    for (int k = 0; k < 3; k++) {
        int i = (k + 1) % 3, j = (k + 2) % 3;
        if (w->gid[T->v[i]] >= 0 && w->gid[T->v[i]] == w->gid[T->v[j]] &&
            collapsed(w, X[i], X[j], P[i]))
            return -1;
    }
    double e1[3], e2[3], N[3], longest = 0;
    for (int k = 0; k < 3; k++) {
        longest = fmax(longest, cb_vec3_dist(P[k], P[(k + 1) % 3]));
        e1[k] = P[1][k] - P[0][k];
        e2[k] = P[2][k] - P[0][k];
    }
    if (longest < w->min_side)
        return -1;
    for (int k = 0; k < 3; k++) {
        int a = w->gid[T->v[(k + 1) % 3]], c = w->gid[T->v[(k + 2) % 3]];
        if (!T->c[k] && a >= 0 && c >= 0 && (same_edge_chord(w, a, c) || listed_split(w, a, c)))
            return k;
    }
    /* A flat triangle on a boundary side: its error comes from the boundary samples, which
     * refinement may not move; splitting it would only crowd points against the side. */
    double area2 = fabs((X[1][0] - X[0][0]) * (X[2][1] - X[0][1]) -
                        (X[1][1] - X[0][1]) * (X[2][0] - X[0][0]));
    for (int k = 0; k < 3; k++) {
        if (!T->c[k])
            continue;
        const double *A = X[(k + 1) % 3], *B = X[(k + 2) % 3];
        double side2 = (B[0] - A[0]) * (B[0] - A[0]) + (B[1] - A[1]) * (B[1] - A[1]);
        if (area2 < 0.125 * side2)
            return -1;
    }
    if (w->o->max_edge > 0 && longest > w->o->max_edge)
        return 3;
    /* The triangle's normal as emitted: flipped with the face. */
    cb_vec3_cross(N, e1, e2);
    double area2_3d = cb_vec3_normalize(N);
    if (!(area2_3d > 0))
        return 3;
    for (int k = 0; k < 3; k++)
        N[k] *= w->sign;
    double c[2] = {(X[0][0] + X[1][0] + X[2][0]) / 3, (X[0][1] + X[1][1] + X[2][1]) / 3};
    double tol = w->o->chord_tol;
    for (int z = 0; z < w->n_zones; z++) {
        const cb_tess_zone *Z = &w->zones[z];
        /* The triangle lies within `longest` of its corner: far zones are passed over at
         * the price of one distance. */
        if (Z->chord_tol < tol && cb_vec3_dist(Z->c, P[0]) <= Z->r + longest &&
            triangle_distance(Z->c, P[0], P[1], P[2]) <= Z->r)
            tol = Z->chord_tol;
    }
    if (chord_error(w, c, P[0], P[1], P[2]) > tol)
        return 3;
    for (int k = 0; k < 3; k++) {
        if (T->c[k])
            continue;
        int i = (k + 1) % 3, j = (k + 2) % 3;
        double m[2] = {0.5 * (X[i][0] + X[j][0]), 0.5 * (X[i][1] + X[j][1])};
        if (chord_error(w, m, P[i], P[j], NULL) > tol)
            return 3;
    }
    /* Its normal is not tested when it is narrower (its smallest height) than min_normal_width:
     * an error across so little is invisible, and the normal of a sliver along a curved line of
     * the surface is that line's osculating plane, not the surface's: splitting it only makes
     * thinner slivers that fail again (seen beside a seam near a cone-like pole). */
    if (area2_3d < w->min_normal_width * longest)
        return -1;
    /* The surface normals at the corners are taken a little inside the triangle
     * (CORNER_INSET), as the triangle sees them: at a corner on a C0 knot line of a B-spline,
     * the derivatives at the corner itself may be those of the span beyond the line, whose
     * normal no triangle on this side can follow however small (trj5: a boundary vertex whose
     * span-beyond normal is 90 degrees off chased triangles into needles against the
     * boundary). */
    for (int k = 0; k < 4; k++) {
        double x[2], der[6][3], n[3];
        for (int i = 0; i < 2; i++)
            x[i] = k == 3 ? c[i]
                          : X[k][i] + CORNER_INSET * (X[(k + 1) % 3][i] + X[(k + 2) % 3][i] -
                                                      2 * X[k][i]);
        cb_topo_inverter_eval_derivs(der, w->inv, x[0] / w->su, x[1] / w->sv);
        face_normal(n, der, w->sign);
        if ((n[0] != 0 || n[1] != 0 || n[2] != 0) && cb_vec3_dot(n, N) < w->cos_tol)
            return 3;
    }
    return -1;
}

static cb_status refine(face_work *w, cb_context *ctx, cb_error *err)
{
    double *cand = NULL;
    int cap = 0;
    cb_status st = CB_OK;
    for (int pass = 0; pass < FACE_MAX_PASSES; pass++) {
        if (cb_context_cancelled(ctx)) {
            st = cb_error_set(err, CB_ERR_CANCELLED, "cancelled");
            break;
        }
        int n = 0;
        for (int t = 0; t < w->d.nt; t++) {
            /* A triangle kept in an earlier pass and not changed since is kept again. */
            if (!w->d.t[t].in || w->d.t[t].settled)
                continue;
            int side = split_side(w, t);
            if (side < 0) {
                w->d.t[t].settled = 1;
                continue;
            }
            if (n == cap) {
                cap = cap ? 2 * cap : 256;
                double *nc = realloc(cand, (size_t)cap * 2 * sizeof(double));
                if (!nc) {
                    st = cb_error_set(err, CB_ERR_NOMEM, "out of memory");
                    break;
                }
                cand = nc;
            }
            const cb_tess_tri *T = &w->d.t[t];
            for (int i = 0; i < 2; i++)
                cand[2 * n + i] =
                    side == 3 ? (w->d.p[2 * T->v[0] + i] + w->d.p[2 * T->v[1] + i] +
                                 w->d.p[2 * T->v[2] + i]) /
                                    3
                              : 0.5 * (w->d.p[2 * T->v[(side + 1) % 3] + i] +
                                       w->d.p[2 * T->v[(side + 2) % 3] + i]);
            n++;
        }
        if (st || n == 0)
            break;
        if (w->d.np + n > FACE_MAX_POINTS) {
            st = cb_error_set(err, CB_ERR_NUMERIC,
                              "more than %d points needed for the tolerances", FACE_MAX_POINTS);
            break;
        }
        for (int k = 0; k < n && !st; k++) {
            int idx, before = w->d.np;
            st = cb_tess_cdt_insert(&w->d, cand[2 * k], cand[2 * k + 1], 1, &idx, err);
            if (!st && idx >= before)
                st = point_data(w, idx, -1, NULL, err);
        }
        if (st)
            break;
    }
    free(cand);
    return st;
}

/* ---------------------------------------------------------------- the face ----------------- */

typedef struct {
    int id, k;
} id_at;

static int cmp_id_at(const void *x, const void *y)
{
    const id_at *a = x, *b = y;
    return a->id != b->id ? (a->id < b->id ? -1 : 1) : (a->k > b->k) - (a->k < b->k);
}

/* A vertex the loops pass through twice at one place (a hole touching the outer boundary, or
 * two holes touching: a pinch) gets its (u, v) from two pcurves, which may differ by
 * round-off; as two triangulation points a hair apart, the loop's segments through them
 * cross and the constraints cannot be recovered. Copies of one sample closer than `near`
 * (scaled (u, v), about 3D length) take the first copy's (u, v); seam and pole copies lie far
 * apart and keep theirs. */
static cb_status unify_pinches(face_loops *L, double su, double sv, double near, cb_error *err)
{
    id_at *order = malloc((size_t)(L->n + 1) * sizeof *order);
    if (!order)
        return cb_error_set(err, CB_ERR_NOMEM, "out of memory");
    for (int k = 0; k < L->n; k++)
        order[k] = (id_at){L->id[k], k};
    qsort(order, (size_t)L->n, sizeof *order, cmp_id_at);
    for (int i = 0, j; i < L->n; i = j) {
        for (j = i + 1; j < L->n && order[j].id == order[i].id; j++)
            for (int q = i; q < j; q++) {
                double *a = L->uv + 2 * order[q].k, *b = L->uv + 2 * order[j].k;
                if (hypot((b[0] - a[0]) * su, (b[1] - a[1]) * sv) <= near) {
                    b[0] = a[0];
                    b[1] = a[1];
                    break;
                }
            }
    }
    free(order);
    return CB_OK;
}

/* A segment of the loops: sample k to the next of its loop, its scaled x range. */
typedef struct {
    double x0, x1;
    int k, next;
} loop_seg;

static int cmp_seg_x0(const void *x, const void *y)
{
    const loop_seg *a = x, *b = y;
    return (a->x0 > b->x0) - (a->x0 < b->x0);
}

/* Finds two segments of the loops (scaled (u, v)) that cross at a point inside both: chords of
 * a curved edge cutting past a vertex or chord of another edge that lies nearer to the curve
 * than the chords' sag. Such constraints cannot both be edges of a triangulation. Returns 1
 * with the loop samples of the two segments, k_out[0] -> k_out[1] and k_out[2] -> k_out[3];
 * 0 when none cross, -1 when out of memory. A sweep over x: each segment is tested against
 * those whose x range begins inside its own. */
static int chords_cross(const face_loops *L, double su, double sv, int k_out[4])
{
    loop_seg *s = malloc((size_t)(L->n + 1) * sizeof *s);
    if (!s)
        return -1;
    int n = 0;
    for (int l = 0, start = 0; l < L->n_loops; start = L->loop_end[l++])
        for (int k = start; k < L->loop_end[l]; k++) {
            int next = k + 1 < L->loop_end[l] ? k + 1 : start;
            double xa = L->uv[2 * k] * su, xb = L->uv[2 * next] * su;
            s[n++] = (loop_seg){fmin(xa, xb), fmax(xa, xb), k, next};
        }
    qsort(s, (size_t)n, sizeof *s, cmp_seg_x0);
    int found = 0;
    for (int i = 0; i < n && !found; i++)
        for (int j = i + 1; j < n && s[j].x0 <= s[i].x1 && !found; j++) {
            double p[4][2];
            int ks[4] = {s[i].k, s[i].next, s[j].k, s[j].next};
            for (int q = 0; q < 4; q++) {
                p[q][0] = L->uv[2 * ks[q]] * su;
                p[q][1] = L->uv[2 * ks[q] + 1] * sv;
            }
            /* Segments meeting at a sample (neighbours in a loop, a pinch) do not cross. */
            if (cb_tess_orient2d(p[0], p[1], p[2]) * cb_tess_orient2d(p[0], p[1], p[3]) < 0 &&
                cb_tess_orient2d(p[2], p[3], p[0]) * cb_tess_orient2d(p[2], p[3], p[1]) < 0) {
                memcpy(k_out, ks, sizeof ks);
                found = 1;
            }
        }
    free(s);
    return found;
}

/* After a failed triangulation: when chords of the loops cross, where (cross: the 3D point
 * on the surface at the crossing, and the longer of the two chords, the reach of the
 * refinement cb_tess_body makes there) and an error saying so in place of err's. */
static cb_status crossing_chords(double cross[4], const face_work *w, const face_loops *L,
                                 cb_error *err)
{
    int k[4];
    int found = chords_cross(L, w->su, w->sv, k);
    if (found < 0)
        return cb_error_set(err, CB_ERR_NOMEM, "out of memory");
    if (!found)
        return CB_ERR_NUMERIC;
    /* Where the two segments cross, by their parameter along the first. */
    const double *a = L->uv + 2 * k[0], *b = L->uv + 2 * k[1], *c = L->uv + 2 * k[2],
                 *d = L->uv + 2 * k[3];
    double den = (b[0] - a[0]) * (d[1] - c[1]) - (b[1] - a[1]) * (d[0] - c[0]);
    double t = den != 0 ? ((c[0] - a[0]) * (d[1] - c[1]) - (c[1] - a[1]) * (d[0] - c[0])) / den
                        : 0.5;
    t = fmin(fmax(t, 0), 1);
    cb_topo_inverter_eval(cross, w->inv, a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]));
    const double *x = w->es_xyz;
    cross[3] = fmax(cb_vec3_dist(x + 3 * L->id[k[0]], x + 3 * L->id[k[1]]),
                    cb_vec3_dist(x + 3 * L->id[k[2]], x + 3 * L->id[k[3]]));
    return cb_error_set(err, CB_ERR_NUMERIC,
                        "triangulation: two chords of the boundary cross in (u, v) near "
                        "(%.9g, %.9g, %.9g), chords %.3g and %.3g long: the loops touch or "
                        "cross there, or a curved edge's samples cut past another edge",
                        cross[0], cross[1], cross[2],
                        cb_vec3_dist(x + 3 * L->id[k[0]], x + 3 * L->id[k[1]]),
                        cb_vec3_dist(x + 3 * L->id[k[2]], x + 3 * L->id[k[3]]));
}

static cb_status triangulate(face_work *w, const face_loops *L, cb_error *err)
{
    double box[4] = {HUGE_VAL, -HUGE_VAL, HUGE_VAL, -HUGE_VAL};
    for (int k = 0; k < L->n; k++) {
        double x = L->uv[2 * k] * w->su, y = L->uv[2 * k + 1] * w->sv;
        box[0] = fmin(box[0], x);
        box[1] = fmax(box[1], x);
        box[2] = fmin(box[2], y);
        box[3] = fmax(box[3], y);
    }
    if (!(box[1] > box[0]) || !(box[3] > box[2]))
        return cb_error_set(err, CB_ERR_NUMERIC, "the loops span no area in (u, v)");
    cb_status st = cb_tess_cdt_init(&w->d, box, err);
    for (int k = 0; k < 3 && !st; k++)
        st = point_data(w, k, -2, NULL, err);
    int *map = malloc((size_t)(L->n + 1) * sizeof(int));
    if (!st && !map)
        st = cb_error_set(err, CB_ERR_NOMEM, "out of memory");
    for (int k = 0; k < L->n && !st; k++) {
        int before = w->d.np;
        st = cb_tess_cdt_insert(&w->d, L->uv[2 * k] * w->su, L->uv[2 * k + 1] * w->sv, 0, &map[k],
                                err);
        if (st)
            break;
        /* Boundary points keep the shared sample's exact coordinates. */
        if (map[k] >= before)
            st = point_data(w, map[k], L->id[k], w->es_xyz + 3 * L->id[k], err);
        else if (w->gid[map[k]] != L->id[k])
            st = cb_error_set(err, CB_ERR_NUMERIC,
                              "two boundary samples at the same (u, v) (%g, %g)", L->uv[2 * k],
                              L->uv[2 * k + 1]);
    }
    for (int l = 0, start = 0; l < L->n_loops && !st; start = L->loop_end[l++])
        for (int k = start; k < L->loop_end[l] && !st; k++) {
            int next = k + 1 < L->loop_end[l] ? k + 1 : start;
            st = cb_tess_cdt_constrain(&w->d, map[k], map[next], err);
        }
    free(map);
    if (st)
        return st;
    cb_tess_cdt_delaunay(&w->d);
    return cb_tess_cdt_classify(&w->d, err);
}

static cb_status emit(cb_tess_face_mesh *fm, const face_work *w, int n_shared, int same_sense,
                      cb_error *err)
{
    int *local = malloc((size_t)w->d.np * sizeof(int));
    int n_own = 0, n_tri = 0;
    if (!local)
        return cb_error_set(err, CB_ERR_NOMEM, "out of memory");
    for (int k = 0; k < w->d.np; k++)
        local[k] = w->gid[k] >= 0 ? w->gid[k] : w->gid[k] == -1 ? n_shared + n_own++ : -1;
    for (int t = 0; t < w->d.nt; t++)
        n_tri += w->d.t[t].in;
    fm->xyz = malloc((size_t)(n_own + 1) * 3 * sizeof(double));
    fm->tri = malloc((size_t)(n_tri + 1) * 3 * sizeof(int));
    if (!fm->xyz || !fm->tri) {
        free(local);
        return cb_error_set(err, CB_ERR_NOMEM, "out of memory");
    }
    fm->cap_points = n_own + 1;
    fm->cap_tris = n_tri + 1;
    for (int k = 0; k < w->d.np; k++)
        if (w->gid[k] == -1)
            memcpy(fm->xyz + 3 * fm->n_points++, w->xyz + 3 * k, sizeof(double[3]));
    for (int t = 0; t < w->d.nt; t++) {
        const cb_tess_tri *T = &w->d.t[t];
        if (!T->in)
            continue;
        int a = local[T->v[0]], b = local[T->v[1]], c = local[T->v[2]];
        if (a < 0 || b < 0 || c < 0 || a == b || b == c || a == c)
            continue; /* two copies of a pole */
        int *o = fm->tri + 3 * fm->n_tris++;
        o[0] = a;
        o[1] = same_sense ? b : c;
        o[2] = same_sense ? c : b;
    }
    free(local);
    /* Every face bounds some area; a face that kept no triangle would leave a hole in the mesh
     * that only the mesh check would see. */
    if (fm->n_tris == 0)
        return cb_error_set(err, CB_ERR_NUMERIC, "triangulation: no triangle left");
    return CB_OK;
}

static cb_status face_run(cb_tess_face_mesh *fm, const cb_topo_body *b, int face,
                          const cb_tess_edges *es, const cb_tess_opts *o,
                          const cb_tess_hints *h, cb_context *ctx,
                          const cb_topo_inverter *inv, double cross[4], cb_error *err)
{
    const cb_topo_face *F = &b->faces[face];
    if (F->count == 0)
        return cb_error_set(err, CB_ERR_UNSUPPORTED,
                            "no loops (a closed surface not cut along a seam)");
    face_loops L = {0};
    face_work w;
    memset(&w, 0, sizeof w);
    cb_status st = build_loops(&L, b, face, es, inv, fmax(o->chord_tol, b->tol), err);
    if (!st) {
        double su = 0, sv = 0;
        for (int k = 0; k < L.n; k++) {
            double d[6][3];
            cb_topo_inverter_eval_derivs(d, inv, L.uv[2 * k], L.uv[2 * k + 1]);
            su += cb_vec3_norm(d[1]);
            sv += cb_vec3_norm(d[2]);
        }
        w.su = su > 0 ? su / L.n : sv > 0 ? sv / L.n : 1;
        w.sv = sv > 0 ? sv / L.n : w.su;
        w.b = b;
        w.inv = inv;
        w.o = o;
        w.es_xyz = es->xyz;
        w.es = es;
        w.face = face;
        int n_zones = h ? h->n_zones : 0;
        w.zones = n_zones ? malloc((size_t)n_zones * sizeof *w.zones) : NULL;
        if (n_zones && !w.zones)
            st = cb_error_set(err, CB_ERR_NOMEM, "out of memory");
        for (int z = 0; z < n_zones && !st; z++)
            if (h->zones[z].face == face)
                w.zones[w.n_zones++] = h->zones[z];
        w.splits = h ? h->splits : NULL;
        w.n_splits = h ? h->n_splits : 0;
        w.sign = F->same_sense ? 1 : -1;
        w.cos_tol = cos(o->angle_tol);
        /* Below the chordal tolerance a normal error is invisible, and chasing one across a
         * crease of the surface (a C0 knot line) would never end. */
        w.min_side = 0.1 * o->chord_tol;
        w.min_normal_width = 2 * o->chord_tol;
        if (!st)
            st = densify_poles(&L, inv, o->angle_tol, fmax(o->chord_tol, b->tol), err);
        for (int k = 0; k < L.n_poles; k++) {
            pole_line *pl = &L.poles[k];
            pl->a[0] *= w.su;
            pl->z[0] *= w.su;
            pl->a[1] *= w.sv;
            pl->z[1] *= w.sv;
        }
        w.poles = L.poles;
        w.n_poles = L.n_poles;
        if (!st)
            st = unify_pinches(&L, w.su, w.sv, b->tol > 0 ? b->tol : 1e-9 * o->chord_tol, err);
        if (!st)
            st = triangulate(&w, &L, err);
        if (st == CB_ERR_NUMERIC)
            st = crossing_chords(cross, &w, &L, err);
    }
    if (!st)
        st = refine(&w, ctx, err);
    if (!st)
        untangle_poles(&w);
    if (!st)
        st = emit(fm, &w, es->n_points, F->same_sense, err);
    loops_clear(&L);
    work_clear(&w);
    return st;
}

cb_status cb_tess_face(cb_tess_face_mesh *fm, const cb_topo_body *b, int face,
                       const cb_tess_edges *es, const cb_tess_opts *o, cb_context *ctx,
                       cb_error *err)
{
    return cb_tess_face_hinted(fm, b, face, es, o, NULL, ctx, err);
}

cb_status cb_tess_face_hinted(cb_tess_face_mesh *fm, const cb_topo_body *b, int face,
                              const cb_tess_edges *es, const cb_tess_opts *o,
                              const cb_tess_hints *h, cb_context *ctx, cb_error *err)
{
    cb_tess_face_mesh_clear(fm);
    if (face < 0 || face >= b->n_faces)
        return cb_error_set(err, CB_ERR_INVALID, "tessellation: face %d out of range [0, %d)",
                            face, b->n_faces);
    if (es->n_edges != b->n_edges)
        return cb_error_set(err, CB_ERR_INVALID,
                            "tessellation: edge samples of another body (%d edges, not %d)",
                            es->n_edges, b->n_edges);
    cb_topo_inverter inv;
    double cross[4] = {0, 0, 0, 0};
    cb_status st = cb_topo_inverter_init(&inv, &b->surfaces[b->faces[face].surface], b->tol, err);
    if (!st) {
        st = face_run(fm, b, face, es, o, h, ctx, &inv, cross, err);
        cb_topo_inverter_clear(&inv);
    }
    if (st) {
        cb_tess_face_mesh_clear(fm);
        memcpy(fm->cross_at, cross, sizeof fm->cross_at);
        fm->cross_r = cross[3];
        if (st != CB_ERR_CANCELLED)
            cb_error_prefix(err, "tessellation: face %d: ", face);
    }
    return st;
}
