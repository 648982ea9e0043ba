/* bench_ssi_score.h — one set of scoring rules for the SSI corpus of graph cases
 * (cb_graph_case, models.h): the runner (bench/bench_ssi_corpus.c, Colibri and Open CASCADE in
 * subprocesses) and the committed subset (tests/test_ssi_corpus.c, Colibri in-process) score
 * every output alike. Header-only (static inline): each is a program of its own.
 *
 * An output is a set of polylines (with Colibri's closed and tangential flags where known) and
 * isolated points, in the world. Everything is measured in the design plane (a world point X
 * taken back to design coordinates (x, y), distances there times the larger of the design
 * axes' scales L[0], L[1]) and relative to the case's size (the diagonal of the box of both
 * control nets; Colibri's default tolerance tol is 1e-6 of it):
 *
 * - on both surfaces: every output point within SSC_RES tol of P and of Q (vertical distance
 *   along the design z axis, an upper bound of the distance to each graph);
 * - on the designed curve: every output point within SSC_OFF size (10 tol) of the designed
 *   curve where that is a transversal branch away from any singular point, within SSC_LOOSE
 *   size near a tangential branch, an isolated contact, or within SSC_SING size of a node,
 *   cusp or touching point (there the surfaces stay within tol of each other over a band about
 *   sqrt(tol) wide, so any point of that band is an intersection point within tolerance);
 * - covered: every point of the designed curve (2000 samples per piece, clipped to the square)
 *   within SSC_TIGHT size of the output (SSC_LOOSE where the point bound is loose): polylines
 *   may cut corners by their chord;
 * - no piece twice: the output segments lying within SSC_JOIN size of another curve, away
 *   from singular points and from their own curve's ends, add up to at most SSC_OVERLAP of the
 *   designed curve's length;
 * - topology: curves joined into components when they come within SSC_JOIN size of each other
 *   anywhere, or both come within SSC_SING size of one designed singular point (a crossing or
 *   contact the band leaves undecided within tolerance); a component no wider than SSC_JOIN
 *   size counts as an isolated point, as does an output point farther than SSC_JOIN size from
 *   every curve (points within SSC_JOIN of each other once); a curve end is free when it is
 *   not within SSC_JOIN size of another curve, of its own other end, of the square's sides,
 *   or within SSC_SING size of a singular point another curve also reaches. A component with
 *   a free end is broken; one without that comes within SSC_JOIN size of the sides is open,
 *   otherwise closed. Right: as many closed and open components and isolated points as
 *   designed, none broken;
 * - tangential flags (Colibri only; Open CASCADE reports none): each curve's flag equals that
 *   of the designed piece nearest its middle point.
 * A result passes when all of these hold. */
#ifndef CB_BENCH_SSI_SCORE_H
#define CB_BENCH_SSI_SCORE_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "models/models.h"
#include "ssi/ssi.h"

#define SSC_RES 10.0    /* times tol */
#define SSC_OFF 1e-5    /* times size: 10 tol */
#define SSC_TIGHT 2e-4  /* times size */
#define SSC_LOOSE 1e-2  /* times size */
#define SSC_OVERLAP 1e-2 /* of the designed curve's length */
#define SSC_SING 5e-3   /* times size */
#define SSC_JOIN 1e-4   /* times size */
#define SSC_SAMPLES 2000

typedef struct {
    int n;
    double *p;      /* 3 n world points */
    int closed;     /* -1 unknown */
    int tangential; /* -1 unknown */
} ssc_curve;

typedef struct {
    int n_curves, n_points;
    ssc_curve *curve;
    double *point; /* 3 n_points */
} ssc_output;

static inline void ssc_output_clear(ssc_output *o)
{
    for (int k = 0; k < o->n_curves; k++)
        free(o->curve[k].p);
    free(o->curve);
    free(o->point);
    memset(o, 0, sizeof *o);
}

/* Appends a curve of n points (copied); 0 when out of memory. */
static inline int ssc_output_add_curve(ssc_output *o, const double *p, int n, int closed,
                                       int tangential)
{
    ssc_curve *c = realloc(o->curve, (size_t)(o->n_curves + 1) * sizeof *c);
    if (!c)
        return 0;
    o->curve = c;
    c += o->n_curves;
    c->p = malloc((size_t)(n ? n : 1) * 3 * sizeof(double));
    if (!c->p)
        return 0;
    memcpy(c->p, p, (size_t)n * 3 * sizeof(double));
    c->n = n;
    c->closed = closed;
    c->tangential = tangential;
    o->n_curves++;
    return 1;
}

static inline int ssc_output_add_point(ssc_output *o, const double X[3])
{
    double *p = realloc(o->point, (size_t)(o->n_points + 1) * 3 * sizeof(double));
    if (!p)
        return 0;
    o->point = p;
    memcpy(p + 3 * o->n_points++, X, 3 * sizeof(double));
    return 1;
}

typedef struct {
    int closed, open, points, broken; /* components found */
    int bad_flags;                    /* tangential flags unlike the designed piece */
    double overlap;                   /* length of output lying on another output curve, over
                                         the designed length */
    double res;         /* largest distance of an output point from P or Q, / tol */
    double off_tight, off_loose; /* largest distance from the designed curve, / size, of the
                                    points held to SSC_OFF and to SSC_LOOSE */
    double cover_tight, cover_loose; /* largest distance of the designed curve from the
                                        output, / size (HUGE_VAL: no output) */
    int topology_ok, geometry_ok;
    char why[200]; /* first reason of failure; empty when it passes */
} ssc_score;

/* ---------------------------------------------------------------- design plane ------------- */

static inline double ssc_seg_dist2(const double *p, const double *a, const double *b)
{
    double dx = b[0] - a[0], dy = b[1] - a[1], wx = p[0] - a[0], wy = p[1] - a[1];
    double dd = dx * dx + dy * dy, t = dd > 0 ? (wx * dx + wy * dy) / dd : 0;
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    double ex = wx - t * dx, ey = wy - t * dy;
    return ex * ex + ey * ey;
}

static inline double ssc_seg_seg(const double *a, const double *b, const double *c,
                                 const double *d)
{
    /* Proper crossing: 0; otherwise the least end-to-segment distance. */
    double d1 = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    double d2 = (b[0] - a[0]) * (d[1] - a[1]) - (b[1] - a[1]) * (d[0] - a[0]);
    double d3 = (d[0] - c[0]) * (a[1] - c[1]) - (d[1] - c[1]) * (a[0] - c[0]);
    double d4 = (d[0] - c[0]) * (b[1] - c[1]) - (d[1] - c[1]) * (b[0] - c[0]);
    if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0)))
        return 0;
    double m = fmin(fmin(ssc_seg_dist2(a, c, d), ssc_seg_dist2(b, c, d)),
                    fmin(ssc_seg_dist2(c, a, b), ssc_seg_dist2(d, a, b)));
    return sqrt(m);
}

/* Distance in the design plane from (x, y) to primitive p (clipped to the square: a sample
 * polyline with the crossings of the square's sides), and to the nearest singular point. */
typedef struct {
    int n_poly;          /* polylines of the clipped primitives */
    int *start, *len;    /* into xy */
    int *prim;           /* primitive of each polyline */
    double *xy;          /* 2 per point */
    int n_xy;
} ssc_truth;

static inline void ssc_truth_clear(ssc_truth *t)
{
    free(t->start);
    free(t->len);
    free(t->prim);
    free(t->xy);
    memset(t, 0, sizeof *t);
}

static inline int ssc_inside(const double *p)
{
    const double e = 1e-12;
    return p[0] >= -e && p[0] <= 1 + e && p[1] >= -e && p[1] <= 1 + e;
}

/* Samples every primitive, clipped to the square; 0 when out of memory. */
static inline int ssc_truth_make(ssc_truth *t, const cb_graph_case *c)
{
    memset(t, 0, sizeof *t);
    int cap = c->n_prims * (SSC_SAMPLES + 8) + 8, pcap = c->n_prims * 32 + 8;
    t->xy = malloc((size_t)cap * 2 * sizeof(double));
    t->start = malloc((size_t)pcap * sizeof(int));
    t->len = malloc((size_t)pcap * sizeof(int));
    t->prim = malloc((size_t)pcap * sizeof(int));
    if (!t->xy || !t->start || !t->len || !t->prim)
        return 0;
    for (int k = 0; k < c->n_prims; k++) {
        const cb_graph_prim *p = c->prim + k;
        double s0, s1, prev_s = 0;
        cb_graph_prim_range(&s0, &s1, p);
        int n = p->kind == CB_GRAPH_POINT ? 1 : SSC_SAMPLES, open = 0, was_in = 0;
        for (int i = 0; i < n; i++) {
            double s = n == 1 ? s0 : s0 + (s1 - s0) * i / (n - 1), q[2];
            cb_graph_prim_point(q, p, s);
            int in = ssc_inside(q);
            if (t->n_poly >= pcap - 1)
                break;
            if (i > 0 && in != was_in) {
                /* The crossing of a side, by bisection. */
                double a = prev_s, b = s, m[2];
                for (int it = 0; it < 60; it++) {
                    double mid = 0.5 * (a + b);
                    cb_graph_prim_point(m, p, mid);
                    if (ssc_inside(m) == was_in)
                        a = mid;
                    else
                        b = mid;
                }
                cb_graph_prim_point(m, p, was_in ? a : b);
                if (!was_in && t->n_poly < pcap) {
                    t->start[t->n_poly] = t->n_xy;
                    t->len[t->n_poly] = 0;
                    t->prim[t->n_poly] = k;
                    open = 1;
                }
                if (open && t->n_xy < cap) {
                    memcpy(t->xy + 2 * t->n_xy++, m, sizeof m);
                    t->len[t->n_poly]++;
                }
                if (was_in) {
                    t->n_poly++;
                    open = 0;
                }
            }
            if (in) {
                if (!open && t->n_poly < pcap) {
                    t->start[t->n_poly] = t->n_xy;
                    t->len[t->n_poly] = 0;
                    t->prim[t->n_poly] = k;
                    open = 1;
                }
                if (t->n_xy < cap) {
                    memcpy(t->xy + 2 * t->n_xy++, q, sizeof q);
                    t->len[t->n_poly]++;
                }
            }
            was_in = in;
            prev_s = s;
        }
        if (open)
            t->n_poly++;
    }
    return 1;
}

/* Distance from (x, y) to the designed curve in the design plane; *prim gets the nearest
 * primitive. */
static inline double ssc_truth_dist(const ssc_truth *t, const double *q, int *prim)
{
    double best = HUGE_VAL;
    *prim = -1;
    for (int k = 0; k < t->n_poly; k++) {
        const double *x = t->xy + 2 * t->start[k];
        int n = t->len[k];
        for (int i = 0; i == 0 || i + 1 < n; i++) {
            double d = ssc_seg_dist2(q, x + 2 * i, n > 1 ? x + 2 * i + 2 : x + 2 * i);
            if (d < best) {
                best = d;
                *prim = t->prim[k];
            }
        }
    }
    return sqrt(best);
}

static inline double ssc_sing_dist(const cb_graph_case *c, const double *q, int *which)
{
    double best = HUGE_VAL;
    *which = -1;
    for (int k = 0; k < c->n_singular; k++) {
        double d = hypot(q[0] - c->singular[k][0], q[1] - c->singular[k][1]);
        if (d < best) {
            best = d;
            *which = k;
        }
    }
    return best;
}

/* ---------------------------------------------------------------- a grid of segments ------- */

/* Output polylines in the design plane, bucketed in a G x G grid over [-0.1, 1.1]^2 (points
 * outside fall in the border cells), so that distance queries look at a few cells only. */
#define SSC_G 128

typedef struct {
    int n_curves;
    int *start, *len; /* into xy */
    double *xy;
    int n_xy;
    int *cell_start, *cell_items; /* CSR: segment ids (curve point index of its first end) */
} ssc_grid;

static inline int ssc_cell(double v)
{
    int k = (int)floor((v + 0.1) / 1.2 * SSC_G);
    return k < 0 ? 0 : k >= SSC_G ? SSC_G - 1 : k;
}

static inline void ssc_grid_clear(ssc_grid *g)
{
    free(g->start);
    free(g->len);
    free(g->xy);
    free(g->cell_start);
    free(g->cell_items);
    memset(g, 0, sizeof *g);
}

/* Segment i of the grid: points i and i + 1 of xy, both of one curve. */
static inline int ssc_grid_make(ssc_grid *g, const cb_graph_case *c, const ssc_output *o)
{
    memset(g, 0, sizeof *g);
    int total = 0;
    for (int k = 0; k < o->n_curves; k++)
        total += o->curve[k].n;
    g->n_curves = o->n_curves;
    g->start = malloc((size_t)(o->n_curves + 1) * sizeof(int));
    g->len = malloc((size_t)(o->n_curves + 1) * sizeof(int));
    g->xy = malloc((size_t)(total + 1) * 2 * sizeof(double));
    g->cell_start = calloc((size_t)SSC_G * SSC_G + 1, sizeof(int));
    if (!g->start || !g->len || !g->xy || !g->cell_start)
        return 0;
    for (int k = 0; k < o->n_curves; k++) {
        g->start[k] = g->n_xy;
        g->len[k] = o->curve[k].n;
        for (int i = 0; i < o->curve[k].n; i++) {
            double p[3];
            cb_graph_case_design(p, c, o->curve[k].p + 3 * i);
            g->xy[2 * g->n_xy] = p[0];
            g->xy[2 * g->n_xy + 1] = p[1];
            g->n_xy++;
        }
    }
    /* Two passes: count the cells each segment's box covers, then fill. */
    long items = 0;
    for (int pass = 0; pass < 2; pass++) {
        int *fill = NULL;
        if (pass == 1) {
            for (int k = 0; k < SSC_G * SSC_G; k++)
                g->cell_start[k + 1] += g->cell_start[k];
            items = g->cell_start[SSC_G * SSC_G];
            g->cell_items = malloc((size_t)(items + 1) * sizeof(int));
            fill = calloc((size_t)SSC_G * SSC_G, sizeof(int));
            if (!g->cell_items || !fill) {
                free(fill);
                return 0;
            }
        }
        for (int k = 0; k < g->n_curves; k++)
            for (int i = 0; i < g->len[k]; i++) {
                /* a single point is a segment of length 0 */
                if (i + 1 >= g->len[k] && g->len[k] > 1)
                    break;
                int s = g->start[k] + i;
                const double *a = g->xy + 2 * s, *b = g->len[k] > 1 ? a + 2 : a;
                int x0 = ssc_cell(fmin(a[0], b[0])), x1 = ssc_cell(fmax(a[0], b[0]));
                int y0 = ssc_cell(fmin(a[1], b[1])), y1 = ssc_cell(fmax(a[1], b[1]));
                for (int x = x0; x <= x1; x++)
                    for (int y = y0; y <= y1; y++) {
                        int cell = x * SSC_G + y;
                        if (pass == 0)
                            g->cell_start[cell + 1]++;
                        else
                            g->cell_items[g->cell_start[cell] + fill[cell]++] = s;
                    }
            }
        free(fill);
    }
    return 1;
}

/* Curve of grid segment s. */
static inline int ssc_grid_curve(const ssc_grid *g, int s)
{
    int lo = 0, hi = g->n_curves - 1;
    while (lo < hi) {
        int mid = (lo + hi + 1) / 2;
        if (g->start[mid] <= s)
            lo = mid;
        else
            hi = mid - 1;
    }
    return lo;
}

static inline const double *ssc_grid_b(const ssc_grid *g, int s)
{
    int k = ssc_grid_curve(g, s);
    return g->len[k] > 1 ? g->xy + 2 * s + 2 : g->xy + 2 * s;
}

/* Distance from q to the output's polylines (all, or all but curve skip) within radius r; a
 * value > r when none is that near. */
static inline double ssc_grid_dist(const ssc_grid *g, const double *q, double r, int skip)
{
    double best = HUGE_VAL;
    int x0 = ssc_cell(q[0] - r), x1 = ssc_cell(q[0] + r), y0 = ssc_cell(q[1] - r),
        y1 = ssc_cell(q[1] + r);
    for (int x = x0; x <= x1; x++)
        for (int y = y0; y <= y1; y++) {
            int cell = x * SSC_G + y;
            for (int i = g->cell_start[cell]; i < g->cell_start[cell + 1]; i++) {
                int s = g->cell_items[i];
                if (skip >= 0 && ssc_grid_curve(g, s) == skip)
                    continue;
                best = fmin(best, ssc_seg_dist2(q, g->xy + 2 * s, ssc_grid_b(g, s)));
            }
        }
    return sqrt(best);
}

/* ---------------------------------------------------------------- scoring ------------------ */

static inline int ssc_find(int *parent, int i)
{
    while (parent[i] != i)
        i = parent[i] = parent[parent[i]];
    return i;
}

static inline void ssc_union(int *parent, int a, int b)
{
    a = ssc_find(parent, a);
    b = ssc_find(parent, b);
    if (a != b)
        parent[a] = b;
}

/* Keeps the first reason of failure. */
static inline void ssc_why(ssc_score *s, const char *text)
{
    if (!s->why[0])
        snprintf(s->why, sizeof s->why, "%s", text);
}

/* Scores output o of case c computed with tolerance tol. Returns 0 when out of memory. */
static inline int ssc_score_output(ssc_score *s, const cb_graph_case *c, const ssc_output *o,
                                   double tol)
{
    memset(s, 0, sizeof *s);
    double size = c->size, L = fmax(c->L[0], c->L[1]);
    /* Bounds in the design plane. */
    double tight = SSC_TIGHT * size / L, loose = SSC_LOOSE * size / L, sing = SSC_SING * size / L,
           join = SSC_JOIN * size / L, truth_len = 0;
    ssc_truth t;
    ssc_grid g;
    int ok = ssc_truth_make(&t, c) && ssc_grid_make(&g, c, o);
    int nc = o->n_curves;
    int *parent = malloc((size_t)(nc + o->n_points + 1) * sizeof(int));
    int *near_sing = malloc((size_t)(nc + 1) * c->n_singular * sizeof(int) + sizeof(int));
    if (!ok || !parent || !near_sing) {
        ssc_truth_clear(&t);
        ssc_grid_clear(&g);
        free(parent);
        free(near_sing);
        return 0;
    }
    memset(near_sing, 0, (size_t)(nc + 1) * c->n_singular * sizeof(int) + sizeof(int));

    /* Every output point: residuals and distance to the designed curve. */
    for (int k = 0; k < nc + 1; k++) {
        int n = k < nc ? o->curve[k].n : o->n_points;
        const double *P = k < nc ? o->curve[k].p : o->point;
        for (int i = 0; i < n; i++) {
            double dp, dq, q[3];
            cb_graph_case_residual(&dp, &dq, c, P + 3 * i);
            s->res = fmax(s->res, fmax(dp, dq) / tol);
            cb_graph_case_design(q, c, P + 3 * i);
            int prim, which;
            double d = ssc_truth_dist(&t, q, &prim), ds = ssc_sing_dist(c, q, &which);
            if (k < nc && ds <= sing)
                near_sing[k * c->n_singular + which] = 1;
            int is_loose = prim < 0 || c->prim[prim].tangential || ds <= sing;
            if (is_loose)
                s->off_loose = fmax(s->off_loose, d * L / size);
            else
                s->off_tight = fmax(s->off_tight, d * L / size);
        }
    }
    /* Coverage. */
    s->cover_tight = s->cover_loose = 0;
    for (int k = 0; k < t.n_poly; k++) {
        int tang = c->prim[t.prim[k]].tangential;
        for (int i = 0; i < t.len[k]; i++) {
            const double *q = t.xy + 2 * (t.start[k] + i);
            int which;
            int is_loose = tang || ssc_sing_dist(c, q, &which) <= sing;
            double r = is_loose ? loose : tight;
            double d = ssc_grid_dist(&g, q, r, -1);
            /* An isolated output point covers too. */
            for (int m = 0; m < o->n_points; m++) {
                double p[3];
                cb_graph_case_design(p, c, o->point + 3 * m);
                d = fmin(d, hypot(p[0] - q[0], p[1] - q[1]));
            }
            if (is_loose)
                s->cover_loose = fmax(s->cover_loose, isfinite(d) ? d * L / size : HUGE_VAL);
            else
                s->cover_tight = fmax(s->cover_tight, isfinite(d) ? d * L / size : HUGE_VAL);
        }
    }

    /* Overlap: output segments on another curve, away from singular points and own ends. */
    for (int k = 0; k < t.n_poly; k++)
        for (int i = 0; i + 1 < t.len[k]; i++) {
            const double *a = t.xy + 2 * (t.start[k] + i);
            truth_len += hypot(a[2] - a[0], a[3] - a[1]);
        }
    for (int k = 0; k < nc; k++) {
        const double *x = g.xy + 2 * g.start[k];
        int n = g.len[k];
        for (int i = 0; i + 1 < n; i++) {
            const double *a = x + 2 * i, *b = a + 2;
            double m[2] = {0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])};
            int which;
            if (hypot(m[0] - x[0], m[1] - x[1]) <= 10 * join ||
                hypot(m[0] - x[2 * n - 2], m[1] - x[2 * n - 1]) <= 10 * join ||
                ssc_sing_dist(c, m, &which) <= sing || ssc_grid_dist(&g, m, join, k) > join)
                continue;
            s->overlap += hypot(b[0] - a[0], b[1] - a[1]);
        }
    }
    s->overlap = truth_len > 0 ? s->overlap / truth_len : s->overlap > 0 ? HUGE_VAL : 0;

    /* Components. */
    for (int k = 0; k < nc; k++)
        parent[k] = k;
    for (int k = 0; k < nc; k++) {
        const double *x = g.xy + 2 * g.start[k];
        int n = g.len[k];
        for (int i = 0; i < n; i++) {
            const double *a = x + 2 * i;
            int x0 = ssc_cell(a[0] - join), x1 = ssc_cell(a[0] + join),
                y0 = ssc_cell(a[1] - join), y1 = ssc_cell(a[1] + join);
            for (int cx = x0; cx <= x1; cx++)
                for (int cy = y0; cy <= y1; cy++) {
                    int cell = cx * SSC_G + cy;
                    for (int m = g.cell_start[cell]; m < g.cell_start[cell + 1]; m++) {
                        int sg = g.cell_items[m], j = ssc_grid_curve(&g, sg);
                        if (j == k || ssc_find(parent, j) == ssc_find(parent, k))
                            continue;
                        const double *b = n > 1 && i + 1 < n ? a + 2 : a;
                        if (ssc_seg_seg(a, b, g.xy + 2 * sg, ssc_grid_b(&g, sg)) <= join)
                            ssc_union(parent, k, j);
                    }
                }
        }
    }
    for (int m = 0; m < c->n_singular; m++) {
        int first = -1;
        for (int k = 0; k < nc; k++)
            if (near_sing[k * c->n_singular + m]) {
                if (first < 0)
                    first = k;
                else
                    ssc_union(parent, first, k);
            }
    }
    /* Per component: free ends, reaches the sides, extent. */
    double *box = malloc((size_t)(nc + 1) * 4 * sizeof(double));
    int *free_ends = calloc((size_t)nc + 1, sizeof(int));
    int *side = calloc((size_t)nc + 1, sizeof(int));
    if (!box || !free_ends || !side) {
        free(box);
        free(free_ends);
        free(side);
        ssc_truth_clear(&t);
        ssc_grid_clear(&g);
        free(parent);
        free(near_sing);
        return 0;
    }
    for (int k = 0; k < nc; k++) {
        box[4 * k] = box[4 * k + 2] = HUGE_VAL;
        box[4 * k + 1] = box[4 * k + 3] = -HUGE_VAL;
    }
    for (int k = 0; k < nc; k++) {
        int r = ssc_find(parent, k), n = g.len[k];
        const double *x = g.xy + 2 * g.start[k];
        for (int i = 0; i < n; i++) {
            const double *a = x + 2 * i;
            box[4 * r] = fmin(box[4 * r], a[0]);
            box[4 * r + 1] = fmax(box[4 * r + 1], a[0]);
            box[4 * r + 2] = fmin(box[4 * r + 2], a[1]);
            box[4 * r + 3] = fmax(box[4 * r + 3], a[1]);
            if (fmin(fmin(a[0], 1 - a[0]), fmin(a[1], 1 - a[1])) <= join)
                side[r] = 1;
        }
        if (n == 0)
            continue;
        int closed = o->curve[k].closed == 1 ||
                     (n > 1 && hypot(x[0] - x[2 * n - 2], x[1] - x[2 * n - 1]) <= join);
        if (closed)
            continue;
        for (int e = 0; e < 2; e++) {
            const double *a = e ? x + 2 * (n - 1) : x;
            if (fmin(fmin(a[0], 1 - a[0]), fmin(a[1], 1 - a[1])) <= join)
                continue;
            if (ssc_grid_dist(&g, a, join, k) <= join)
                continue;
            int which;
            if (ssc_sing_dist(c, a, &which) <= sing) {
                int other = 0;
                for (int j = 0; j < nc; j++)
                    other |= j != k && near_sing[j * c->n_singular + which];
                if (other)
                    continue;
            }
            free_ends[r]++;
        }
    }
    int n_tiny = 0;
    for (int k = 0; k < nc; k++) {
        if (ssc_find(parent, k) != k || g.len[k] == 0)
            continue;
        double w = hypot(box[4 * k + 1] - box[4 * k], box[4 * k + 3] - box[4 * k + 2]);
        if (w <= join && !side[k]) {
            n_tiny++;
            continue;
        }
        if (free_ends[k])
            s->broken++;
        else if (side[k])
            s->open++;
        else
            s->closed++;
    }
    /* Isolated points: away from every curve, each cluster once. */
    int np = o->n_points, *pp = parent + nc;
    for (int m = 0; m < np; m++)
        pp[m] = m;
    double *pxy = malloc((size_t)(np + 1) * 2 * sizeof(double));
    int away = 0;
    if (pxy) {
        for (int m = 0; m < np; m++) {
            double p[3];
            cb_graph_case_design(p, c, o->point + 3 * m);
            pxy[2 * m] = p[0];
            pxy[2 * m + 1] = p[1];
        }
        for (int m = 0; m < np; m++)
            for (int j = 0; j < m; j++)
                if (hypot(pxy[2 * m] - pxy[2 * j], pxy[2 * m + 1] - pxy[2 * j + 1]) <= join)
                    ssc_union(pp, m, j);
        for (int m = 0; m < np; m++)
            if (ssc_find(pp, m) == m && ssc_grid_dist(&g, pxy + 2 * m, join, -1) > join)
                away++;
    }
    s->points = away + n_tiny;

    /* Tangential flags. */
    for (int k = 0; k < nc; k++) {
        if (o->curve[k].tangential < 0 || g.len[k] == 0)
            continue;
        int prim;
        ssc_truth_dist(&t, g.xy + 2 * (g.start[k] + g.len[k] / 2), &prim);
        if (prim >= 0 && c->prim[prim].tangential != o->curve[k].tangential)
            s->bad_flags++;
    }

    s->topology_ok = s->closed == c->closed && s->open == c->open && s->points == c->points &&
                     !s->broken;
    char b[200];
    if (!s->topology_ok) {
        snprintf(b, sizeof b,
                 "topology: %d closed, %d open, %d points, %d broken (true %d, %d, %d)",
                 s->closed, s->open, s->points, s->broken, c->closed, c->open, c->points);
        ssc_why(s, b);
    }
    if (s->bad_flags) {
        snprintf(b, sizeof b, "%d tangential flags wrong", s->bad_flags);
        ssc_why(s, b);
    }
    if (s->res > SSC_RES) {
        snprintf(b, sizeof b, "a point %.2g tol off the surfaces", s->res);
        ssc_why(s, b);
    }
    if (s->overlap > SSC_OVERLAP) {
        snprintf(b, sizeof b, "curves overlap over %.2g of the designed length", s->overlap);
        ssc_why(s, b);
    }
    if (s->off_tight > SSC_OFF || s->off_loose > SSC_LOOSE) {
        snprintf(b, sizeof b, "a point %.2g size off the designed curve (%.2g near contacts)",
                 s->off_tight, s->off_loose);
        ssc_why(s, b);
    }
    if (s->cover_tight > SSC_TIGHT || s->cover_loose > SSC_LOOSE) {
        snprintf(b, sizeof b,
                 "the designed curve %.2g size from the output (%.2g near contacts)",
                 s->cover_tight, s->cover_loose);
        ssc_why(s, b);
    }
    s->geometry_ok = s->res <= SSC_RES && s->off_tight <= SSC_OFF && s->overlap <= SSC_OVERLAP &&
                     s->off_loose <= SSC_LOOSE && s->cover_tight <= SSC_TIGHT &&
                     s->cover_loose <= SSC_LOOSE && !s->bad_flags;
    free(pxy);
    free(box);
    free(free_ends);
    free(side);
    free(parent);
    free(near_sing);
    ssc_truth_clear(&t);
    ssc_grid_clear(&g);
    return 1;
}

/* ---------------------------------------------------------------- Colibri on a case ------- */

/* Refusal reasons of the subdivision route, summed over the failure records of a result (from
 * "subdivision: N of M sub-patch pairs not certified (no direction A, ambiguous boundary roots
 * B, several branches C, marching failed D, over budget E)"). */
#define SSC_N_REASONS 5
static const char *const ssc_reason_name[SSC_N_REASONS] = {
    "no direction", "ambiguous boundary roots", "several branches", "marching failed",
    "over budget"};

typedef struct {
    int status;       /* of cb_ssi_surfaces */
    long failed;      /* patch pairs not certified (1 when the call itself failed) */
    long subpairs, pairs, subdivided; /* sub-patch pairs examined; patch pairs, of them
                                         taken by the subdivision route */
    long reason[SSC_N_REASONS];
    double time, tol; /* seconds of the call; tolerance used */
    char msg[240];    /* the error, or the first failure record's message */
    int n_where;      /* failure records with a region: the first SSC_WHERE of them, the centre
                         of the region on P in design coordinates (x, y), and its size there */
    double where[16][3];
} ssc_run;
#define SSC_WHERE 16

/* Colibri as the corpus runs it: cb_ssi_surfaces(P, Q) with the default tolerance, chords of
 * SSC_TIGHT / 4 of the size, on `threads` threads; the curves and points into o (empty on
 * entry). Returns 0 when out of memory. */
static inline int ssc_colibri(ssc_run *run, ssc_output *o, const cb_graph_case *c, int threads,
                              double (*clock_s)(void))
{
    memset(run, 0, sizeof *run);
    cb_ssi_surface A, B;
    cb_ssi_surface_set_nurbs(&A, c->P);
    cb_ssi_surface_set_nurbs(&B, c->Q);
    cb_ssi_opts opts;
    cb_ssi_opts_default(&opts);
    opts.threads = threads;
    opts.chord = SSC_TIGHT / 4 * c->size;
    cb_ssi_result_t r;
    cb_ssi_result_init(r);
    cb_error err;
    cb_error_clear(&err);
    double t0 = clock_s();
    cb_status st = cb_ssi_surfaces(r, &A, &B, -1, -1, &opts, &err);
    run->time = clock_s() - t0;
    run->status = (int)st;
    run->tol = r->tol > 0 ? r->tol : 1e-6 * c->size;
    run->failed = st ? 1 : (long)r->n_failed + (r->status != CB_OK && !r->n_failed);
    run->subpairs = (long)r->subpairs;
    run->pairs = (long)r->pairs_total;
    run->subdivided = (long)r->pairs_subdivided;
    snprintf(run->msg, sizeof run->msg, "%.230s",
             st ? err.msg : r->n_failed ? r->failed[0].msg : "");
    for (slong k = 0; k < r->n_failed; k++) {
        const cb_ssi_failure *f = r->failed + k;
        if (f->has_box && run->n_where < SSC_WHERE) {
            double X[3], p[3], Y[3], q[3];
            cb_nurbs_surface_eval(X, c->P, 0.5 * (f->box_a[0] + f->box_a[1]),
                                  0.5 * (f->box_a[2] + f->box_a[3]));
            cb_nurbs_surface_eval(Y, c->P, f->box_a[0], f->box_a[2]);
            cb_graph_case_design(p, c, X);
            cb_graph_case_design(q, c, Y);
            double *w = run->where[run->n_where++];
            w[0] = p[0];
            w[1] = p[1];
            w[2] = 2 * hypot(p[0] - q[0], p[1] - q[1]);
        }
        long v[7];
        const char *m = strstr(r->failed[k].msg, "subdivision:");
        if (m && sscanf(m,
                        "subdivision: %ld of %ld sub-patch pairs not certified (no direction "
                        "%ld, ambiguous boundary roots %ld, several branches %ld, marching "
                        "failed %ld, over budget %ld)",
                        v, v + 1, v + 2, v + 3, v + 4, v + 5, v + 6) == 7)
            for (int i = 0; i < SSC_N_REASONS; i++)
                run->reason[i] += v[i + 2];
    }
    int ok = 1;
    double *pts = NULL;
    for (slong k = 0; k < r->n_curves && ok; k++) {
        const cb_ssi_curve *cv = r->curve + k;
        double *m = realloc(pts, (size_t)(cv->n + 1) * 3 * sizeof(double));
        ok = m != NULL;
        if (!ok)
            break;
        pts = m;
        for (slong i = 0; i < cv->n; i++)
            memcpy(pts + 3 * i, cv->pt[i].xyz, 3 * sizeof(double));
        ok = ssc_output_add_curve(o, pts, (int)cv->n, cv->closed, cv->tangential);
    }
    for (slong k = 0; k < r->n_points && ok; k++)
        ok = ssc_output_add_point(o, r->point[k].p.xyz);
    free(pts);
    cb_ssi_result_clear(r);
    return ok;
}

/* The dominant refusal reason of a run: the subdivision reason counted most, else the
 * message with its digits dropped (into buf). */
static inline const char *ssc_refusal_class(const ssc_run *run, char *buf, size_t n)
{
    int best = -1;
    long most = 0;
    for (int i = 0; i < SSC_N_REASONS; i++)
        if (run->reason[i] > most) {
            most = run->reason[i];
            best = i;
        }
    if (best >= 0)
        return ssc_reason_name[best];
    size_t k = 0;
    for (const char *p = run->msg; *p && k + 1 < n && k < 60; p++)
        if (!(*p >= '0' && *p <= '9'))
            buf[k++] = *p;
    buf[k] = 0;
    return buf;
}

#endif
