/* bbox.c — exact AABBs, oriented boxes fitted by PCA and exact rotation steps, SAT test. */
#include "brep/bbox.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* A point set read in place, Euclidean (x, y, z) or homogeneous (wx, wy, wz, w), so that the
 * box of a control net needs no copy and no allocation. */
typedef struct {
    const double *p;
    size_t n, stride;
    int homogeneous;
} point_set;

static void point_get(double q[3], const point_set *s, size_t i)
{
    const double *x = s->p + i * s->stride;
    for (int k = 0; k < 3; k++)
        q[k] = s->homogeneous ? x[k] / x[3] : x[k];
}

/* Coordinate of p along a measured from o. Sizing a box and testing containment both go
 * through this one formula, so an input point is inside its box bit for bit. */
static double coord(const double p[3], const double o[3], const double a[3])
{
    double d[3] = {p[0] - o[0], p[1] - o[1], p[2] - o[2]};
    return cb_vec3_dot(d, a);
}

/* ---------------------------------------------------------------- AABB --------------------- */

static void aabb_fit(cb_aabb *b, const point_set *s)
{
    for (int k = 0; k < 3; k++) {
        b->lo[k] = INFINITY;
        b->hi[k] = -INFINITY;
    }
    for (size_t i = 0; i < s->n; i++) {
        double q[3];
        point_get(q, s, i);
        for (int k = 0; k < 3; k++) {
            b->lo[k] = fmin(b->lo[k], q[k]);
            b->hi[k] = fmax(b->hi[k], q[k]);
        }
    }
}

void cb_aabb_of_points(cb_aabb *b, const double *pts, size_t n, size_t stride)
{
    point_set s = {pts, n, stride, 0};
    aabb_fit(b, &s);
}

static int aabb_empty(const cb_aabb *b)
{
    return b->lo[0] > b->hi[0] || b->lo[1] > b->hi[1] || b->lo[2] > b->hi[2];
}

double cb_aabb_volume(const cb_aabb *b)
{
    if (aabb_empty(b))
        return 0.0;
    return (b->hi[0] - b->lo[0]) * (b->hi[1] - b->lo[1]) * (b->hi[2] - b->lo[2]);
}

int cb_aabb_overlap(const cb_aabb *a, const cb_aabb *b, double tol)
{
    if (aabb_empty(a) || aabb_empty(b))
        return 0;
    for (int k = 0; k < 3; k++)
        if (a->lo[k] - b->hi[k] > tol || b->lo[k] - a->hi[k] > tol)
            return 0;
    return 1;
}

/* ---------------------------------------------------------------- OBB fitting -------------- */

/* Trial directions of the search (spread over a hemisphere), the short list refined by
 * descent, the most points the search starts with (larger sets are thinned to a kernel), and
 * the rounds that then add the kernel's misses on the chosen box, 6 points each. */
#define OBB_GRID 16
#define OBB_KEEP 3
#define OBB_WORK 256
#define OBB_ROUNDS 4
#define OBB_CAP (OBB_WORK + 6 * OBB_ROUNDS)

/* Points the rotation search works on, relative to the centroid of the set, and their
 * indices in it. */
typedef struct {
    double p[OBB_CAP][3];
    size_t idx[OBB_CAP];
    int n;
} work_set;

/* A candidate frame: orthonormal rows a[k] and the extents of the work set along them. */
typedef struct {
    double a[3][3];
    double lo[3], hi[3];
} frame_fit;

static void fit_extents(frame_fit *f, const work_set *w)
{
    for (int k = 0; k < 3; k++) {
        f->lo[k] = INFINITY;
        f->hi[k] = -INFINITY;
        for (int i = 0; i < w->n; i++) {
            double t = cb_vec3_dot(w->p[i], f->a[k]);
            f->lo[k] = t < f->lo[k] ? t : f->lo[k];
            f->hi[k] = t > f->hi[k] ? t : f->hi[k];
        }
    }
}

/* Volume of the box as it will be returned, pad included: comparing padded volumes also ranks
 * flat sets (zero volume in any frame containing the plane) by their area in the plane. */
static double fit_measure(const frame_fit *f, double pad)
{
    double v = 1.0;
    for (int k = 0; k < 3; k++)
        v *= f->hi[k] - f->lo[k] + 2 * pad;
    return v;
}

/* Rows a[0], a[1] normalised and made orthogonal, a[2] = a[0] x a[1]; a must already be
 * orthonormal up to round-off. */
static void frame_orthonormalize(double a[3][3])
{
    cb_vec3_normalize(a[0]);
    double d = cb_vec3_dot(a[1], a[0]);
    for (int k = 0; k < 3; k++)
        a[1][k] -= d * a[0][k];
    cb_vec3_normalize(a[1]);
    cb_vec3_cross(a[2], a[0], a[1]);
}

/* Rows: a[0] = d (unit), a[1] the world axis least aligned with d made orthogonal to it,
 * a[2] = a[0] x a[1]; the world axes give the world frame. */
static void frame_from_axis(double a[3][3], const double d[3])
{
    int m = 0;
    for (int k = 1; k < 3; k++)
        if (fabs(d[k]) < fabs(d[m]))
            m = k;
    for (int k = 0; k < 3; k++) {
        a[0][k] = d[k];
        a[1][k] = (k == m) - d[m] * d[k];
    }
    cb_vec3_normalize(a[1]);
    frame_orthonormalize(a);
}

/* Direction g of a spherical Fibonacci set of `count` unit vectors spread evenly over the
 * hemisphere z > 0. */
static void fibonacci_dir(double d[3], int g, int count)
{
    double z = (g + 0.5) / count, r = sqrt(1 - z * z), phi = 2.39996322972865332 * g;
    d[0] = r * cos(phi);
    d[1] = r * sin(phi);
    d[2] = z;
}

/* Sorts the n points xy by (x, y); insertion sort, as n <= OBB_CAP and the hot case is a
 * Bezier net of 9 to 25 points. */
static void sort_xy(double xy[][2], int n)
{
    for (int m = 1; m < n; m++) {
        double x = xy[m][0], y = xy[m][1];
        int at = m;
        for (; at > 0 && (xy[at - 1][0] > x || (xy[at - 1][0] == x && xy[at - 1][1] > y)); at--) {
            xy[at][0] = xy[at - 1][0];
            xy[at][1] = xy[at - 1][1];
        }
        xy[at][0] = x;
        xy[at][1] = y;
    }
}

static double turn2(const double a[2], const double b[2], const double c[2])
{
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

/* Convex hull of the n >= 1 points xy, sorted by (x, y), counter-clockwise without collinear
 * vertices (Andrew's monotone chain); hull needs room for 2 n points. Returns the vertex
 * count. Round-off can only drop or keep a nearly collinear vertex. */
static int hull2(double hull[][2], const double xy[][2], int n)
{
    int h = 0;
    for (int m = 0; m < n; m++) {
        while (h >= 2 && turn2(hull[h - 2], hull[h - 1], xy[m]) <= 0)
            h--;
        hull[h][0] = xy[m][0];
        hull[h][1] = xy[m][1];
        h++;
    }
    for (int m = n - 2, low = h + 1; m >= 0; m--) {
        while (h >= low && turn2(hull[h - 2], hull[h - 1], xy[m]) <= 0)
            h--;
        hull[h][0] = xy[m][0];
        hull[h][1] = xy[m][1];
        h++;
    }
    return n > 1 ? h - 1 : h;
}

/* One exact descent step: rotates f about its axis k to the orientation whose other two axes
 * give the least padded rectangle around the projected work set, if that beats the current
 * one. A minimum-area enclosing rectangle has a side on the convex hull (Freeman, Shapira,
 * CACM 18(7), 1975), so the hull edges are the only candidates. Returns 1 if f was rotated. */
static int fit_turn(frame_fit *f, const work_set *w, int k, double pad)
{
    int i = (k + 1) % 3, j = (k + 2) % 3;
    double wi = f->hi[i] - f->lo[i], wj = f->hi[j] - f->lo[j];
    /* A width within the pad is round-off: turning in that plane would trade noise for noise
     * (and shuffle the axes of flat sets), never gain anything real. */
    if (wi <= 2 * pad || wj <= 2 * pad)
        return 0;
    double xy[OBB_CAP][2], hull[2 * OBB_CAP][2];
    for (int m = 0; m < w->n; m++) {
        xy[m][0] = cb_vec3_dot(w->p[m], f->a[i]);
        xy[m][1] = cb_vec3_dot(w->p[m], f->a[j]);
    }
    sort_xy(xy, w->n);
    int h = hull2(hull, (const double(*)[2])xy, w->n);

    double best = (wi + 2 * pad) * (wj + 2 * pad), best_u[2] = {1.0, 0.0};
    int improved = 0;
    for (int e = 0; e < h; e++) {
        const double *p = hull[e], *q = hull[(e + 1) % h];
        double u[2] = {q[0] - p[0], q[1] - p[1]}, len = sqrt(u[0] * u[0] + u[1] * u[1]);
        if (len == 0)
            continue;
        u[0] /= len;
        u[1] /= len;
        double slo = INFINITY, shi = -INFINITY, tlo = INFINITY, thi = -INFINITY;
        for (int m = 0; m < h; m++) {
            double sv = u[0] * hull[m][0] + u[1] * hull[m][1];
            double tv = u[0] * hull[m][1] - u[1] * hull[m][0];
            slo = sv < slo ? sv : slo;
            shi = sv > shi ? sv : shi;
            tlo = tv < tlo ? tv : tlo;
            thi = tv > thi ? tv : thi;
        }
        double area = (shi - slo + 2 * pad) * (thi - tlo + 2 * pad);
        if (area < best) {
            best = area;
            best_u[0] = u[0];
            best_u[1] = u[1];
            improved = 1;
        }
    }
    if (!improved)
        return 0;
    /* A rotation about a[k] by the angle of best_u: the frame stays right-handed. */
    for (int c = 0; c < 3; c++) {
        double ai = f->a[i][c], aj = f->a[j][c];
        f->a[i][c] = best_u[0] * ai + best_u[1] * aj;
        f->a[j][c] = best_u[0] * aj - best_u[1] * ai;
    }
    fit_extents(f, w);
    return 1;
}

/* Principal axes of the set about its centroid o. */
static void frame_principal(double a[3][3], const point_set *s, const double o[3])
{
    double m[3][3] = {{0}};
    for (size_t i = 0; i < s->n; i++) {
        double q[3];
        point_get(q, s, i);
        for (int k = 0; k < 3; k++)
            q[k] -= o[k];
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++)
                m[r][c] += q[r] * q[c];
    }
    cb_sym3_eigen(a, m);
    frame_orthonormalize(a);
}

/* A frame from the set's extreme points (as in the DiTO method of Larsson, Kallberg, "Fast
 * computation of tight-fitting oriented bounding boxes", Game Engine Gems 2, 2011): a[0]
 * along the farthest pair among the extremes in 13 fixed directions, a[1] towards the point
 * farthest from their line. Returns 0 when all points coincide. */
static int frame_extremal(double a[3][3], const point_set *s)
{
    static const double dirs[13][3] = {
        {1, 0, 0},  {0, 1, 0},  {0, 0, 1},  {1, 1, 1},  {1, 1, -1}, {1, -1, 1}, {1, -1, -1},
        {1, 1, 0},  {1, -1, 0}, {1, 0, 1},  {1, 0, -1}, {0, 1, 1},  {0, 1, -1}};
    double lo_v[13], hi_v[13], lo_p[13][3], hi_p[13][3];
    for (size_t i = 0; i < s->n; i++) {
        double q[3];
        point_get(q, s, i);
        for (int d = 0; d < 13; d++) {
            double t = cb_vec3_dot(q, dirs[d]);
            if (i == 0 || t < lo_v[d]) {
                lo_v[d] = t;
                memcpy(lo_p[d], q, sizeof q);
            }
            if (i == 0 || t > hi_v[d]) {
                hi_v[d] = t;
                memcpy(hi_p[d], q, sizeof q);
            }
        }
    }
    int best = 0;
    double span = -1.0;
    for (int d = 0; d < 13; d++) {
        double len = cb_vec3_dist(hi_p[d], lo_p[d]);
        if (len > span) {
            span = len;
            best = d;
        }
    }
    if (span == 0.0)
        return 0;
    const double *p0 = lo_p[best];
    for (int k = 0; k < 3; k++)
        a[0][k] = hi_p[best][k] - p0[k];
    cb_vec3_normalize(a[0]);

    double far_d = 0.0;
    for (size_t i = 0; i < s->n; i++) {
        double q[3];
        point_get(q, s, i);
        for (int k = 0; k < 3; k++)
            q[k] -= p0[k];
        double t = cb_vec3_dot(q, a[0]);
        for (int k = 0; k < 3; k++)
            q[k] -= t * a[0][k];
        double d = cb_vec3_norm(q);
        if (d > far_d) {
            far_d = d;
            memcpy(a[1], q, sizeof q);
        }
    }
    /* An offset below sqrt(eps) of the span has no reliable direction after the cancellation
     * above; any perpendicular serves then. */
    if (far_d <= sqrt(DBL_EPSILON) * span) {
        frame_from_axis(a, a[0]);
        return 1;
    }
    cb_vec3_normalize(a[1]);
    frame_orthonormalize(a);
    return 1;
}

static int cmp_size(const void *a, const void *b)
{
    size_t x = *(const size_t *)a, y = *(const size_t *)b;
    return (x > y) - (x < y);
}

/* The work set: the whole set when it has at most OBB_WORK points, else its extreme points
 * in OBB_WORK / 2 directions spread over the sphere. Those form a kernel whose width in every
 * direction is that of the set up to a factor 1 - O(theta^2), theta the spacing of the
 * directions (Agarwal, Har-Peled, Varadarajan, "Approximating extent measures of points",
 * J. ACM 51(4), 2004). */
static void work_select(work_set *w, const point_set *s, const double o[3])
{
    size_t n = s->n;
    if (n > OBB_WORK) {
        enum { ND = OBB_WORK / 2 };
        double dirs[ND][3], lo[ND], hi[ND];
        for (int g = 0; g < ND; g++) {
            fibonacci_dir(dirs[g], g, ND);
            lo[g] = INFINITY;
            hi[g] = -INFINITY;
            w->idx[2 * g] = w->idx[2 * g + 1] = 0;
        }
        for (size_t i = 0; i < s->n; i++) {
            double q[3];
            point_get(q, s, i);
            for (int g = 0; g < ND; g++) {
                double t = cb_vec3_dot(q, dirs[g]);
                if (t < lo[g]) {
                    lo[g] = t;
                    w->idx[2 * g] = i;
                }
                if (t > hi[g]) {
                    hi[g] = t;
                    w->idx[2 * g + 1] = i;
                }
            }
        }
        qsort(w->idx, OBB_WORK, sizeof w->idx[0], cmp_size);
        n = 0;
        for (int m = 0; m < OBB_WORK; m++)
            if (m == 0 || w->idx[m] != w->idx[m - 1])
                w->idx[n++] = w->idx[m];
    } else {
        for (size_t i = 0; i < n; i++)
            w->idx[i] = i;
    }
    w->n = (int)n;
    for (int m = 0; m < w->n; m++) {
        point_get(w->p[m], s, w->idx[m]);
        for (int k = 0; k < 3; k++)
            w->p[m][k] -= o[k];
    }
}

/* Adds to the work set the points of the whole set extreme along the rows of a that it
 * lacks — a box fitted to a kernel tends to settle where the kernel has gaps — and returns
 * how many it added. Needs room for 6 more points. */
static int work_add_extremes(work_set *w, const point_set *s, const double o[3],
                             const double a[3][3])
{
    size_t arg[6] = {0};
    double ext[6];
    for (int e = 0; e < 6; e++)
        ext[e] = e % 2 ? -INFINITY : INFINITY;
    for (size_t i = 0; i < s->n; i++) {
        double q[3];
        point_get(q, s, i);
        for (int k = 0; k < 3; k++) {
            double t = coord(q, o, a[k]);
            if (t < ext[2 * k]) {
                ext[2 * k] = t;
                arg[2 * k] = i;
            }
            if (t > ext[2 * k + 1]) {
                ext[2 * k + 1] = t;
                arg[2 * k + 1] = i;
            }
        }
    }
    int added = 0;
    for (int e = 0; e < 6; e++) {
        int known = 0;
        for (int m = 0; m < w->n && !known; m++)
            known = w->idx[m] == arg[e];
        if (known)
            continue;
        w->idx[w->n] = arg[e];
        point_get(w->p[w->n], s, arg[e]);
        for (int k = 0; k < 3; k++)
            w->p[w->n][k] -= o[k];
        w->n++;
        added++;
    }
    return added;
}

/* Coordinate descent over rotations about the box axes; each step is exact and never grows
 * the box. Stops after a sweep without a turn, or after 8 sweeps (zigzag on a narrow valley). */
static void fit_descend(frame_fit *f, const work_set *w, double pad)
{
    for (int sweep = 0; sweep < 8; sweep++) {
        int turned = 0;
        for (int k = 0; k < 3; k++)
            turned |= fit_turn(f, w, k, pad);
        if (!turned)
            return;
    }
}

static void obb_set_empty(cb_obb *b)
{
    for (int k = 0; k < 3; k++) {
        b->center[k] = 0.0;
        b->half[k] = -1.0;
        for (int c = 0; c < 3; c++)
            b->axis[k][c] = k == c;
    }
}

/* Extents of the whole set along the rows of a, measured from o. */
static void set_extents(double lo[3], double hi[3], const point_set *s, const double o[3],
                        const double a[3][3])
{
    for (int k = 0; k < 3; k++) {
        lo[k] = INFINITY;
        hi[k] = -INFINITY;
    }
    for (size_t i = 0; i < s->n; i++) {
        double q[3];
        point_get(q, s, i);
        for (int k = 0; k < 3; k++) {
            double t = coord(q, o, a[k]);
            lo[k] = fmin(lo[k], t);
            hi[k] = fmax(hi[k], t);
        }
    }
}

static void obb_fit(cb_obb *b, const point_set *s)
{
    if (s->n == 0) {
        obb_set_empty(b);
        return;
    }
    /* Round-off guard: 32 ulps of the largest coordinate magnitude bounds the error of a
     * coordinate computed by coord() for any point of the set or a few-ulp perturbation. */
    cb_aabb box;
    aabb_fit(&box, s);
    double mag = 0.0;
    for (int k = 0; k < 3; k++)
        mag = fmax(mag, fmax(fabs(box.lo[k]), fabs(box.hi[k])));
    double pad = 32 * DBL_EPSILON * mag;

    double o[3] = {0, 0, 0};
    for (size_t i = 0; i < s->n; i++) {
        double q[3];
        point_get(q, s, i);
        for (int k = 0; k < 3; k++)
            o[k] += q[k];
    }
    for (int k = 0; k < 3; k++)
        o[k] /= (double)s->n;
    work_set w;
    work_select(&w, s, o);

    /* Trial axes: the world axes, the principal axes, the extremal frame and a grid in the
     * principal frame. Each gives the box with that axis and the least rectangle across it. */
    double dirs[9 + OBB_GRID][3], pca[3][3], ext[3][3];
    int n_dirs = 0;
    frame_principal(pca, s, o);
    int has_ext = frame_extremal(ext, s);
    for (int r = 0; r < 3; r++) {
        for (int c = 0; c < 3; c++) {
            dirs[n_dirs][c] = r == c;
            dirs[n_dirs + 1][c] = pca[r][c];
            dirs[n_dirs + 2][c] = has_ext ? ext[r][c] : pca[r][c];
        }
        n_dirs += 3;
    }
    for (int g = 0; g < OBB_GRID; g++, n_dirs++) {
        double l[3];
        fibonacci_dir(l, g, OBB_GRID);
        for (int c = 0; c < 3; c++)
            dirs[n_dirs][c] = l[0] * pca[0][c] + l[1] * pca[1][c] + l[2] * pca[2][c];
    }

    /* The OBB_KEEP best, sorted; ties keep the earlier (world first). */
    frame_fit cand[OBB_KEEP];
    double cand_v[OBB_KEEP];
    int n_cand = 0;
    for (int d = 0; d < n_dirs; d++) {
        frame_fit f;
        frame_from_axis(f.a, dirs[d]);
        fit_extents(&f, &w);
        fit_turn(&f, &w, 0, pad);
        double v = fit_measure(&f, pad);
        int at = n_cand;
        while (at > 0 && v < cand_v[at - 1])
            at--;
        if (at == OBB_KEEP)
            continue;
        if (n_cand < OBB_KEEP)
            n_cand++;
        for (int m = n_cand - 1; m > at; m--) {
            cand[m] = cand[m - 1];
            cand_v[m] = cand_v[m - 1];
        }
        cand[at] = f;
        cand_v[at] = v;
    }

    int best = 0;
    for (int c = 0; c < n_cand; c++) {
        fit_descend(&cand[c], &w, pad);
        cand_v[c] = fit_measure(&cand[c], pad);
        if (cand_v[c] < cand_v[best])
            best = c;
    }
    for (int r = 0; r < OBB_ROUNDS && work_add_extremes(&w, s, o, cand[best].a); r++) {
        fit_extents(&cand[best], &w);
        fit_descend(&cand[best], &w, pad);
    }

    /* Final extents over every point; a kernel-fitted frame is checked against the AABB. */
    double (*a)[3] = cand[best].a, lo[3], hi[3];
    frame_orthonormalize(a);
    set_extents(lo, hi, s, o, (const double(*)[3])a);
    double v = 1.0, v_aabb = 1.0;
    for (int k = 0; k < 3; k++) {
        v *= hi[k] - lo[k] + 2 * pad;
        v_aabb *= box.hi[k] - box.lo[k] + 2 * pad;
    }
    if (v_aabb < v) {
        frame_from_axis(a, (const double[3]){1, 0, 0});
        set_extents(lo, hi, s, o, (const double(*)[3])a);
    }
    for (int c = 0; c < 3; c++) {
        b->center[c] = o[c];
        for (int k = 0; k < 3; k++)
            b->center[c] += 0.5 * (lo[k] + hi[k]) * a[k][c];
    }
    for (int k = 0; k < 3; k++) {
        memcpy(b->axis[k], a[k], sizeof b->axis[k]);
        b->half[k] = 0.0;
    }
    for (size_t i = 0; i < s->n; i++) {
        double q[3];
        point_get(q, s, i);
        for (int k = 0; k < 3; k++)
            b->half[k] = fmax(b->half[k], fabs(coord(q, b->center, b->axis[k])));
    }
    for (int k = 0; k < 3; k++)
        b->half[k] += pad;
}

void cb_obb_of_points(cb_obb *b, const double *pts, size_t n, size_t stride)
{
    point_set s = {pts, n, stride, 0};
    obb_fit(b, &s);
}

/* ---------------------------------------------------------------- OBB queries -------------- */

static int obb_empty(const cb_obb *b) { return b->half[0] < 0 || b->half[1] < 0 || b->half[2] < 0; }

double cb_obb_volume(const cb_obb *b)
{
    if (obb_empty(b))
        return 0.0;
    return 8 * b->half[0] * b->half[1] * b->half[2];
}

int cb_obb_contains(const cb_obb *b, const double p[3], double tol)
{
    if (obb_empty(b))
        return 0;
    for (int k = 0; k < 3; k++)
        if (!(fabs(coord(p, b->center, b->axis[k])) <= b->half[k] + tol))
            return 0;
    return 1;
}

/* Gap between the projections of the boxes on the direction L (any length): the distance
 * between their shadows on the line, or a negative overlap. */
static double axis_gap(const cb_obb *a, const cb_obb *b, const double t[3], const double L[3])
{
    double len = cb_vec3_norm(L);
    double l[3] = {L[0] / len, L[1] / len, L[2] / len};
    double r = 0.0;
    for (int k = 0; k < 3; k++)
        r += a->half[k] * fabs(cb_vec3_dot(l, a->axis[k])) +
             b->half[k] * fabs(cb_vec3_dot(l, b->axis[k]));
    return fabs(cb_vec3_dot(t, l)) - r;
}

int cb_obb_separated(const cb_obb *a, const cb_obb *b, double tol)
{
    if (obb_empty(a) || obb_empty(b))
        return 1;
    double t[3], scale = 0.0;
    for (int k = 0; k < 3; k++) {
        t[k] = b->center[k] - a->center[k];
        scale += fabs(a->center[k]) + fabs(b->center[k]) + a->half[k] + b->half[k];
    }
    /* Error bound of axis_gap: differences, dot products and the non-orthonormality of the
     * axes each cost a few ulps of these magnitudes. */
    double limit = tol + 32 * DBL_EPSILON * scale;
    for (int k = 0; k < 3; k++)
        if (axis_gap(a, b, t, a->axis[k]) > limit || axis_gap(a, b, t, b->axis[k]) > limit)
            return 1;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double L[3];
            cb_vec3_cross(L, a->axis[i], b->axis[j]);
            if (cb_vec3_norm(L) > DBL_EPSILON && axis_gap(a, b, t, L) > limit)
                return 1;
        }
    return 0;
}

void cb_obb_corners(double c[8][3], const cb_obb *b)
{
    for (int n = 0; n < 8; n++)
        for (int k = 0; k < 3; k++) {
            c[n][k] = b->center[k];
            for (int i = 0; i < 3; i++)
                c[n][k] += ((n >> i) & 1 ? b->half[i] : -b->half[i]) * b->axis[i][k];
        }
}

/* ---------------------------------------------------------------- control nets ------------- */

void cb_nurbs_curve_aabb(cb_aabb *b, const cb_nurbs_curve_t c)
{
    point_set s = {c->cw, (size_t)c->n, 4, 1};
    aabb_fit(b, &s);
}

void cb_nurbs_curve_obb(cb_obb *b, const cb_nurbs_curve_t c)
{
    point_set s = {c->cw, (size_t)c->n, 4, 1};
    obb_fit(b, &s);
}

void cb_nurbs_surface_aabb(cb_aabb *b, const cb_nurbs_surface_t sf)
{
    point_set s = {sf->cw, (size_t)sf->n_u * (size_t)sf->n_v, 4, 1};
    aabb_fit(b, &s);
}

void cb_nurbs_surface_obb(cb_obb *b, const cb_nurbs_surface_t sf)
{
    point_set s = {sf->cw, (size_t)sf->n_u * (size_t)sf->n_v, 4, 1};
    obb_fit(b, &s);
}
