/* Tests of brep/bbox: containment, tightness and frames of fitted boxes, the SAT test against
 * brute-force distances, AABB overlap against interval arithmetic, boxes of control nets. */
#include <float.h>
#include <math.h>
#include <stdlib.h>

#include "brep/bbox.h"
#include "check.h"

#define MAX_PTS 20000
#define PI 3.14159265358979323846

static double pts[MAX_PTS * 3];

/* ---------------------------------------------------------------- helpers ------------------ */

/* Uniformly random rotation, rows orthonormal, from a random unit quaternion. */
static void random_rotation(double r[3][3], check_rng *rng)
{
    double q[4], n2;
    do {
        n2 = 0;
        for (int k = 0; k < 4; k++) {
            q[k] = check_rng_uniform(rng, -1, 1);
            n2 += q[k] * q[k];
        }
    } while (n2 > 1 || n2 < 1e-3);
    double n = sqrt(n2), w = q[0] / n, x = q[1] / n, y = q[2] / n, z = q[3] / n;
    double m[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
                      {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
                      {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}};
    memcpy(r, m, sizeof m);
}

/* Rotation Rz(a) Ry(b) Rx(c): with all angles in [0.4, 1.1] no box edge is near a world axis. */
static void euler_rotation(double r[3][3], double a, double b, double c)
{
    double ca = cos(a), sa = sin(a), cb = cos(b), sb = sin(b), cc = cos(c), sc = sin(c);
    double m[3][3] = {{ca * cb, ca * sb * sc - sa * cc, ca * sb * cc + sa * sc},
                      {sa * cb, sa * sb * sc + ca * cc, sa * sb * cc - ca * sc},
                      {-sb, cb * sc, cb * cc}};
    memcpy(r, m, sizeof m);
}

/* out = c + R^T l: the point with local coordinates l in the frame whose rows are R. */
static void frame_point(double out[3], const double c[3], const double r[3][3], const double l[3])
{
    for (int k = 0; k < 3; k++)
        out[k] = c[k] + l[0] * r[0][k] + l[1] * r[1][k] + l[2] * r[2][k];
}

static double max_abs_coord(const double *p, size_t n)
{
    double m = 0;
    for (size_t i = 0; i < 3 * n; i++)
        m = fmax(m, fabs(p[i]));
    return m;
}

/* Frame facts that must hold for every fitted box. */
static void check_frame(const cb_obb *b, const char *what, int trial)
{
    int ok = 1;
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++) {
            double d = cb_vec3_dot(b->axis[i], b->axis[j]) - (i == j);
            ok &= fabs(d) <= 1e-14;
        }
        ok &= isfinite(b->center[i]) && isfinite(b->half[i]) && b->half[i] >= 0;
    }
    double c[3];
    cb_vec3_cross(c, b->axis[0], b->axis[1]);
    ok &= cb_vec3_dist(c, b->axis[2]) <= 1e-14;
    CHECK(ok, "%s trial %d: axes (%.17g %.17g %.17g) (%.17g %.17g %.17g) (%.17g %.17g %.17g) "
              "half %g %g %g",
          what, trial, b->axis[0][0], b->axis[0][1], b->axis[0][2], b->axis[1][0], b->axis[1][1],
          b->axis[1][2], b->axis[2][0], b->axis[2][1], b->axis[2][2], b->half[0], b->half[1],
          b->half[2]);
}

/* The half extents of b in increasing order. */
static void sorted_half(double h[3], const cb_obb *b)
{
    memcpy(h, b->half, 3 * sizeof h[0]);
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2 - i; j++)
            if (h[j] > h[j + 1]) {
                double t = h[j];
                h[j] = h[j + 1];
                h[j + 1] = t;
            }
}

/* Every point inside the box with tol 0; reports the first miss. */
static void check_contains_all(const cb_obb *b, const double *p, size_t n, const char *what,
                               int trial)
{
    size_t miss = n;
    for (size_t i = 0; i < n && miss == n; i++)
        if (!cb_obb_contains(b, p + 3 * i, 0.0))
            miss = i;
    CHECK(miss == n, "%s trial %d: point %zu (%.17g, %.17g, %.17g) of %zu outside the OBB",
          what, trial, miss, miss < n ? p[3 * miss] : 0, miss < n ? p[3 * miss + 1] : 0,
          miss < n ? p[3 * miss + 2] : 0, n);
}

/* OBB volume at most that of the AABB grown by 256 ulps of the data magnitude per side (the
 * OBB carries a 32-ulp round-off pad). Returns OBB / AABB volume (1 if both vanish). */
static double check_volume_vs_aabb(const cb_obb *b, const double *p, size_t n, const char *what,
                                   int trial)
{
    cb_aabb a;
    cb_aabb_of_points(&a, p, n, 3);
    double s = 256 * DBL_EPSILON * max_abs_coord(p, n), grown = 1, va = cb_aabb_volume(&a);
    for (int k = 0; k < 3; k++)
        grown *= a.hi[k] - a.lo[k] + 2 * s;
    double vo = cb_obb_volume(b);
    CHECK(vo <= grown, "%s trial %d: OBB volume %.17g > AABB volume %.17g (grown %.17g), n %zu",
          what, trial, vo, va, grown, n);
    return va > 0 ? vo / va : 1.0;
}

/* ---------------------------------------------------------------- AABB --------------------- */

static void test_aabb(check_rng *rng)
{
    /* Bounds are attained and hold every point. */
    for (int trial = 0; trial < 200; trial++) {
        size_t n = (size_t)check_rng_int(rng, 1, 50);
        for (size_t i = 0; i < 3 * n; i++)
            pts[i] = check_rng_uniform(rng, -5, 5);
        cb_aabb b;
        cb_aabb_of_points(&b, pts, n, 3);
        int inside = 1, hit_lo[3] = {0}, hit_hi[3] = {0};
        for (size_t i = 0; i < n; i++)
            for (int k = 0; k < 3; k++) {
                inside &= b.lo[k] <= pts[3 * i + k] && pts[3 * i + k] <= b.hi[k];
                hit_lo[k] |= b.lo[k] == pts[3 * i + k];
                hit_hi[k] |= b.hi[k] == pts[3 * i + k];
            }
        int tight = hit_lo[0] && hit_lo[1] && hit_lo[2] && hit_hi[0] && hit_hi[1] && hit_hi[2];
        CHECK(inside && tight, "trial %d: n %zu inside %d tight %d", trial, n, inside, tight);
    }

    /* Overlap agrees with per-axis intervals: [a] and [b] are within tol iff
     * max(lo) - min(hi) <= tol. Integer corners make touching exact and frequent. */
    int n_overlap = 0, n_apart = 0;
    for (int trial = 0; trial < 3000; trial++) {
        cb_aabb a, b;
        for (int k = 0; k < 3; k++) {
            int a0 = check_rng_int(rng, -4, 4), a1 = check_rng_int(rng, a0, 5);
            int b0 = check_rng_int(rng, -4, 4), b1 = check_rng_int(rng, b0, 5);
            a.lo[k] = a0;
            a.hi[k] = a1;
            b.lo[k] = b0;
            b.hi[k] = b1;
        }
        double tol = 0.5 * check_rng_int(rng, 0, 2);
        int expect = 1;
        for (int k = 0; k < 3; k++)
            expect &= fmax(a.lo[k], b.lo[k]) - fmin(a.hi[k], b.hi[k]) <= tol;
        int got = cb_aabb_overlap(&a, &b, tol);
        CHECK(got == expect && cb_aabb_overlap(&b, &a, tol) == got,
              "trial %d: a [%g %g]x[%g %g]x[%g %g] b [%g %g]x[%g %g]x[%g %g] tol %g: got %d, "
              "intervals say %d",
              trial, a.lo[0], a.hi[0], a.lo[1], a.hi[1], a.lo[2], a.hi[2], b.lo[0], b.hi[0],
              b.lo[1], b.hi[1], b.lo[2], b.hi[2], tol, got, expect);
        n_overlap += got;
        n_apart += !got;
    }
    CHECK(n_overlap > 300 && n_apart > 300, "overlap cases %d, apart %d", n_overlap, n_apart);

    cb_aabb e, u = {{0, 0, 0}, {1, 1, 1}};
    cb_aabb_of_points(&e, pts, 0, 3);
    CHECK(cb_aabb_volume(&e) == 0 && !cb_aabb_overlap(&e, &u, 10) && !cb_aabb_overlap(&u, &e, 10),
          "empty AABB: volume %g", cb_aabb_volume(&e));
}

/* ---------------------------------------------------------------- OBB fitting -------------- */

/* Random clouds of every shape, including degenerate ones: containment, frame, volume. */
static void test_obb_clouds(check_rng *rng)
{
    static const char *kinds[] = {"general", "coincident", "collinear", "coplanar",
                                  "world-plane", "world-line"};
    double ratio_sum = 0;
    int ratio_n = 0;
    for (int trial = 0; trial < 600; trial++) {
        int kind = trial % 6;
        size_t n = (size_t)check_rng_int(rng, 1, 120);
        double r[3][3], c[3], scale[3];
        random_rotation(r, rng);
        double far = (double[]){0, 1, 1e3}[check_rng_int(rng, 0, 2)];
        for (int k = 0; k < 3; k++) {
            c[k] = check_rng_uniform(rng, -far, far);
            scale[k] = exp(check_rng_uniform(rng, log(1e-3), log(10)));
        }
        for (size_t i = 0; i < n; i++) {
            double l[3] = {0, 0, 0};
            double *p = pts + 3 * i;
            switch (kind) {
            case 0:
                for (int k = 0; k < 3; k++)
                    l[k] = scale[k] * check_rng_uniform(rng, -1, 1);
                frame_point(p, c, r, l);
                break;
            case 1:
                frame_point(p, c, r, l);
                break;
            case 2:
                l[0] = scale[0] * check_rng_uniform(rng, -1, 1);
                frame_point(p, c, r, l);
                break;
            case 3:
                l[0] = scale[0] * check_rng_uniform(rng, -1, 1);
                l[1] = scale[1] * check_rng_uniform(rng, -1, 1);
                frame_point(p, c, r, l);
                break;
            case 4:
                p[0] = c[0] + scale[0] * check_rng_uniform(rng, -1, 1);
                p[1] = c[1] + scale[1] * check_rng_uniform(rng, -1, 1);
                p[2] = c[2];
                break;
            default:
                p[0] = c[0] + scale[0] * check_rng_uniform(rng, -1, 1);
                p[1] = c[1];
                p[2] = c[2];
                break;
            }
        }
        cb_obb b;
        cb_obb_of_points(&b, pts, n, 3);
        check_frame(&b, kinds[kind], trial);
        check_contains_all(&b, pts, n, kinds[kind], trial);
        double ratio = check_volume_vs_aabb(&b, pts, n, kinds[kind], trial);
        if (kind == 0 && n >= 4) {
            ratio_sum += ratio;
            ratio_n++;
        }
        /* Extents where the set has none stay at round-off level. */
        double h[3];
        sorted_half(h, &b);
        double ro = 1e-12 * (max_abs_coord(pts, n) + 1e-300);
        int flat_dims = kind == 1 ? 3 : kind == 2 || kind == 5 ? 2 : kind == 3 || kind == 4;
        int ok = 1;
        for (int k = 0; k < flat_dims; k++)
            ok &= h[k] <= ro;
        CHECK(ok, "%s trial %d: n %zu half extents %g %g %g, expected %d below %g", kinds[kind],
              trial, n, h[0], h[1], h[2], flat_dims, ro);
    }
    printf("bbox: random general clouds: mean OBB/AABB volume %.3f over %d clouds\n",
           ratio_sum / ratio_n, ratio_n);

    cb_obb e;
    cb_obb_of_points(&e, pts, 0, 3);
    double origin[3] = {0, 0, 0};
    CHECK(cb_obb_volume(&e) == 0 && !cb_obb_contains(&e, origin, 1e300) &&
              cb_obb_separated(&e, &e, 0),
          "empty OBB: volume %g", cb_obb_volume(&e));

    /* A stride other than 3: every fourth double is junk that must be ignored. */
    double strided[40 * 4];
    for (int i = 0; i < 40; i++) {
        for (int k = 0; k < 3; k++)
            strided[4 * i + k] = check_rng_uniform(rng, -1, 1);
        strided[4 * i + 3] = 1e30;
    }
    cb_obb sb;
    cb_obb_of_points(&sb, strided, 40, 4);
    int in = 1;
    for (int i = 0; i < 40; i++)
        in &= cb_obb_contains(&sb, strided + 4 * i, 0);
    CHECK(in && sb.half[0] < 2 && sb.half[1] < 2 && sb.half[2] < 2, "stride 4: half %g %g %g",
          sb.half[0], sb.half[1], sb.half[2]);
}

/* A rotated elongated box: the fitted box must be the box itself, far below the AABB. */
static void test_obb_elongated(check_rng *rng)
{
    const double half[3] = {5, 1, 0.25}, true_vol = 8 * 5 * 1 * 0.25;
    double worst_true = 0, worst_aabb = 0, sum_aabb = 0, worst_inner = 0, min_inner = INFINITY;
    for (int trial = 0; trial < 100; trial++) {
        double r[3][3], c[3];
        euler_rotation(r, check_rng_uniform(rng, 0.4, 1.1), check_rng_uniform(rng, 0.4, 1.1),
                       check_rng_uniform(rng, 0.4, 1.1));
        for (int k = 0; k < 3; k++)
            c[k] = check_rng_uniform(rng, -100, 100);
        /* Corners, points on faces and inside. */
        size_t n = 0;
        for (int m = 0; m < 8; m++) {
            double l[3];
            for (int k = 0; k < 3; k++)
                l[k] = (m >> k) & 1 ? half[k] : -half[k];
            frame_point(pts + 3 * n++, c, r, l);
        }
        for (int i = 0; i < 200; i++) {
            double l[3];
            for (int k = 0; k < 3; k++)
                l[k] = check_rng_uniform(rng, -half[k], half[k]);
            if (i % 2)
                l[i % 3] = i % 4 == 1 ? half[i % 3] : -half[i % 3];
            frame_point(pts + 3 * n++, c, r, l);
        }
        cb_obb b;
        cb_obb_of_points(&b, pts, n, 3);
        check_frame(&b, "elongated", trial);
        check_contains_all(&b, pts, n, "elongated", trial);
        double to_aabb = check_volume_vs_aabb(&b, pts, n, "elongated", trial);
        double to_true = cb_obb_volume(&b) / true_vol;
        CHECK(to_true >= 1 - 1e-9 && to_true <= 1.01 && to_aabb < 0.5,
              "elongated trial %d: OBB / true volume %.6f, OBB / AABB %.4f", trial, to_true,
              to_aabb);
        worst_true = fmax(worst_true, to_true);
        worst_aabb = fmax(worst_aabb, to_aabb);
        sum_aabb += to_aabb;

        /* 2000 points inside (no corners; fitted through a kernel): at most 2 % above the box. */
        n = 2000;
        for (size_t i = 0; i < n; i++) {
            double l[3];
            for (int k = 0; k < 3; k++)
                l[k] = check_rng_uniform(rng, -half[k], half[k]);
            frame_point(pts + 3 * i, c, r, l);
        }
        cb_obb_of_points(&b, pts, n, 3);
        check_contains_all(&b, pts, n, "elongated-inner", trial);
        double inner = cb_obb_volume(&b) / true_vol;
        CHECK(inner <= 1.02, "elongated-inner trial %d: OBB / true volume %.6f", trial, inner);
        worst_inner = fmax(worst_inner, inner);
        min_inner = fmin(min_inner, inner);
    }
    printf("bbox: elongated 10x2x0.5 box: OBB/true volume <= %.6f, OBB/AABB mean %.3f max %.3f; "
           "2000 inner points: OBB/true in [%.4f, %.4f]\n",
           worst_true, sum_aabb / 100, worst_aabb, min_inner, worst_inner);
}

/* A rectangle in a random plane: the box must find the rectangle, not only the plane. */
static void test_obb_flat_rectangle(check_rng *rng)
{
    for (int trial = 0; trial < 100; trial++) {
        double r[3][3], c[3], a = check_rng_uniform(rng, 0.5, 5);
        double bb = check_rng_uniform(rng, 0.1, a);
        random_rotation(r, rng);
        for (int k = 0; k < 3; k++)
            c[k] = check_rng_uniform(rng, -10, 10);
        size_t n = 0;
        for (int m = 0; m < 4; m++) {
            double l[3] = {m & 1 ? a : -a, m & 2 ? bb : -bb, 0};
            frame_point(pts + 3 * n++, c, r, l);
        }
        for (int i = 0; i < 60; i++) {
            double l[3] = {check_rng_uniform(rng, -a, a), check_rng_uniform(rng, -bb, bb), 0};
            frame_point(pts + 3 * n++, c, r, l);
        }
        cb_obb b;
        cb_obb_of_points(&b, pts, n, 3);
        check_contains_all(&b, pts, n, "flat-rectangle", trial);
        double h[3];
        sorted_half(h, &b);
        CHECK(h[0] <= 1e-12 && fabs(h[1] - bb) <= 1e-9 && fabs(h[2] - a) <= 1e-9,
              "flat-rectangle trial %d: %g x %g rectangle, half extents %.17g %.17g %.17g", trial,
              a, bb, h[0], h[1], h[2]);
    }
}

/* Against the best of 3000 random orientations: the search must not be stuck far above what
 * blind sampling finds (6 %), and must beat it on average. */
static void test_obb_vs_search(check_rng *rng)
{
    double worst = 0, sum = 0;
    const int trials = 150;
    for (int trial = 0; trial < trials; trial++) {
        size_t n = (size_t)check_rng_int(rng, 8, 40);
        double r[3][3], c[3] = {0, 0, 0}, scale[3];
        random_rotation(r, rng);
        for (int k = 0; k < 3; k++)
            scale[k] = check_rng_uniform(rng, 0.2, 3);
        for (size_t i = 0; i < n; i++) {
            double l[3];
            for (int k = 0; k < 3; k++)
                l[k] = scale[k] * check_rng_uniform(rng, -1, 1);
            frame_point(pts + 3 * i, c, r, l);
        }
        cb_obb b;
        cb_obb_of_points(&b, pts, n, 3);
        double best = INFINITY;
        for (int s = 0; s < 3000; s++) {
            double q[3][3], v = 1;
            random_rotation(q, rng);
            for (int k = 0; k < 3; k++) {
                double lo = INFINITY, hi = -INFINITY;
                for (size_t i = 0; i < n; i++) {
                    double d = cb_vec3_dot(pts + 3 * i, q[k]);
                    lo = fmin(lo, d);
                    hi = fmax(hi, d);
                }
                v *= hi - lo;
            }
            best = fmin(best, v);
        }
        double ratio = cb_obb_volume(&b) / best;
        CHECK(ratio <= 1.06, "search trial %d: n %zu, OBB volume %.6g, random search found %.6g",
              trial, n, cb_obb_volume(&b), best);
        worst = fmax(worst, ratio);
        sum += ratio;
    }
    CHECK(sum / trials < 0.97, "OBB / random search volume: mean %.4f", sum / trials);
    printf("bbox: OBB / best of 3000 random orientations: mean %.4f, worst %.4f\n", sum / trials,
           worst);
}

/* Large sets, fitted through a kernel: a 20000-point cloud and 3000 points on a circle (every
 * point a hull vertex). */
static void test_obb_large(check_rng *rng)
{
    double r[3][3], c[3] = {3, -2, 7};
    random_rotation(r, rng);
    size_t n = MAX_PTS;
    for (size_t i = 0; i < n; i++) {
        double l[3] = {check_rng_uniform(rng, -4, 4), check_rng_uniform(rng, -1, 1),
                       check_rng_uniform(rng, -0.5, 0.5)};
        frame_point(pts + 3 * i, c, r, l);
    }
    cb_obb b;
    cb_obb_of_points(&b, pts, n, 3);
    check_frame(&b, "large", 0);
    check_contains_all(&b, pts, n, "large", 0);
    double large = cb_obb_volume(&b) / 16;
    CHECK(large <= 1.02, "large: OBB / box volume %g", large);

    n = 3000;
    for (size_t i = 0; i < n; i++) {
        double t = 2 * PI * (double)i / (double)n, l[3] = {2 * cos(t), 2 * sin(t), 0};
        frame_point(pts + 3 * i, c, r, l);
    }
    cb_obb_of_points(&b, pts, n, 3);
    check_frame(&b, "circle", 0);
    check_contains_all(&b, pts, n, "circle", 0);
    CHECK(cb_obb_volume(&b) <= 1e-10 && b.half[0] + b.half[1] + b.half[2] <= 4 + 1e-9,
          "circle: half %g %g %g", b.half[0], b.half[1], b.half[2]);
    printf("bbox: 20000-point 8x2x1 box cloud: OBB / box volume %.5f\n", large);
}

/* ---------------------------------------------------------------- SAT ---------------------- */

static void random_obb(cb_obb *b, check_rng *rng, double spread, double hmin, double hmax)
{
    random_rotation(b->axis, rng);
    for (int k = 0; k < 3; k++) {
        b->center[k] = check_rng_uniform(rng, -spread, spread);
        b->half[k] = check_rng_uniform(rng, hmin, hmax);
    }
}

/* Exact distance from p to the solid box b. */
static double point_box_dist(const double p[3], const cb_obb *b)
{
    double d2 = 0, d[3] = {p[0] - b->center[0], p[1] - b->center[1], p[2] - b->center[2]};
    for (int k = 0; k < 3; k++) {
        double e = fabs(cb_vec3_dot(d, b->axis[k])) - b->half[k];
        if (e > 0)
            d2 += e * e;
    }
    return sqrt(d2);
}

/* Upper bound of the distance between the boxes: least distance from a sample of either
 * box's surface (a 7 x 7 grid on each face: corners, edges, faces) to the other box. */
static double dist_upper(const cb_obb *a, const cb_obb *b)
{
    double best = INFINITY;
    for (int pass = 0; pass < 2; pass++) {
        const cb_obb *s = pass ? b : a, *o = pass ? a : b;
        for (int f = 0; f < 6; f++) {
            int ax = f / 2, u = (ax + 1) % 3, v = (ax + 2) % 3;
            for (int i = 0; i < 7; i++)
                for (int j = 0; j < 7; j++) {
                    double l[3];
                    l[ax] = f % 2 ? s->half[ax] : -s->half[ax];
                    l[u] = s->half[u] * (i / 3.0 - 1);
                    l[v] = s->half[v] * (j / 3.0 - 1);
                    double p[3];
                    frame_point(p, s->center, s->axis, l);
                    best = fmin(best, point_box_dist(p, o));
                }
        }
    }
    return best;
}

/* Lower bound of the distance (0 if not shown apart): the widest gap between the shadows of
 * the corner sets on 600 random directions. */
static double dist_lower(const cb_obb *a, const cb_obb *b, check_rng *rng)
{
    double ca[8][3], cb[8][3], best = 0;
    cb_obb_corners(ca, a);
    cb_obb_corners(cb, b);
    for (int s = 0; s < 600; s++) {
        double l[3], r[3][3];
        random_rotation(r, rng);
        memcpy(l, r[0], sizeof l);
        double alo = INFINITY, ahi = -INFINITY, blo = INFINITY, bhi = -INFINITY;
        for (int m = 0; m < 8; m++) {
            double x = cb_vec3_dot(ca[m], l), y = cb_vec3_dot(cb[m], l);
            alo = fmin(alo, x);
            ahi = fmax(ahi, x);
            blo = fmin(blo, y);
            bhi = fmax(bhi, y);
        }
        best = fmax(best, fmax(blo - ahi, alo - bhi));
    }
    return best;
}

static void test_sat_random(check_rng *rng)
{
    int n_sep = 0, n_not = 0;
    for (int trial = 0; trial < 2000; trial++) {
        cb_obb a, b;
        random_obb(&a, rng, 2, 0.05, 1.5);
        random_obb(&b, rng, 2, 0.05, 1.5);
        double tol = (double[]){0, 0, 0.01, 0.2}[trial % 4];
        int sep = cb_obb_separated(&a, &b, tol);
        double up = dist_upper(&a, &b), low = dist_lower(&a, &b, rng);
        /* Corners: on the boundary of their box, at the documented signs. */
        double cor[8][3], corner_err = 0;
        cb_obb_corners(cor, &a);
        for (int m = 0; m < 8; m++)
            for (int k = 0; k < 3; k++) {
                double d[3] = {cor[m][0] - a.center[0], cor[m][1] - a.center[1],
                               cor[m][2] - a.center[2]};
                double want = (m >> k) & 1 ? a.half[k] : -a.half[k];
                corner_err = fmax(corner_err, fabs(cb_vec3_dot(d, a.axis[k]) - want));
            }
        CHECK(corner_err <= 1e-14, "sat trial %d: corner off by %g", trial, corner_err);
        CHECK(!(sep && up <= tol),
              "sat trial %d: separated with tol %g but sample points are %.17g apart", trial,
              tol, up);
        CHECK(!(tol == 0 && low > 1e-9 && !sep),
              "sat trial %d: boxes at least %.17g apart but not separated", trial, low);
        CHECK(cb_obb_separated(&b, &a, tol) == sep, "sat trial %d: not symmetric", trial);
        CHECK(!sep || cb_obb_separated(&a, &b, 0.5 * tol) == 1,
              "sat trial %d: separated with tol %g but not with %g", trial, tol, 0.5 * tol);
        n_sep += sep;
        n_not += !sep;
    }
    CHECK(n_sep > 300 && n_not > 300, "sat: separated %d, not %d", n_sep, n_not);

    /* A point shared on purpose: never separated, whatever the tolerance. */
    for (int trial = 0; trial < 1000; trial++) {
        cb_obb a, b;
        random_obb(&a, rng, 50, 1e-3, 3);
        random_obb(&b, rng, 0, 1e-3, 3);
        double la[3], lb[3], x[3], y[3];
        for (int k = 0; k < 3; k++) {
            /* Often on a face, edge or corner of both boxes. */
            la[k] = check_rng_int(rng, 0, 1) ? a.half[k] * (check_rng_int(rng, 0, 1) ? 1 : -1)
                                             : check_rng_uniform(rng, -a.half[k], a.half[k]);
            lb[k] = check_rng_int(rng, 0, 1) ? b.half[k] * (check_rng_int(rng, 0, 1) ? 1 : -1)
                                             : check_rng_uniform(rng, -b.half[k], b.half[k]);
        }
        frame_point(x, a.center, a.axis, la);
        double zero[3] = {0, 0, 0};
        frame_point(y, zero, b.axis, lb);
        for (int k = 0; k < 3; k++)
            b.center[k] = x[k] - y[k];
        double tol = (double[]){0, 1e-9, 0.1}[trial % 3];
        CHECK(!cb_obb_separated(&a, &b, tol),
              "shared-point trial %d: point (%.17g %.17g %.17g) in both, tol %g, said separated",
              trial, x[0], x[1], x[2], tol);
    }
}

/* Face-to-face boxes at a known gap g along A's axis 0, with B's axis 0 parallel to it
 * (a0 x b0 vanishes exactly, the other four crosses of the remaining axes all lie along a0) or
 * tilted by 1e-17 .. 1e-9 rad: separated iff g > tol. */
static void test_sat_parallel(check_rng *rng)
{
    int n_sep = 0, n_not = 0;
    for (int trial = 0; trial < 1200; trial++) {
        cb_obb a, b;
        random_obb(&a, rng, 10, 0.1, 2);
        double th = check_rng_uniform(rng, 0, 2 * PI), c = cos(th), s = sin(th);
        int exact = trial % 2 == 0;
        for (int k = 0; k < 3; k++) {
            b.axis[0][k] = a.axis[0][k];
            b.axis[1][k] = c * a.axis[1][k] + s * a.axis[2][k];
            b.axis[2][k] = c * a.axis[2][k] - s * a.axis[1][k];
            b.half[k] = check_rng_uniform(rng, 0.1, 2);
        }
        double tilt = 0;
        if (!exact) {
            /* Tilt B about its axis 1 by 1e-17 .. 1e-9 rad. */
            tilt = pow(10, check_rng_uniform(rng, -17, -9));
            double ct = cos(tilt), st = sin(tilt), b0[3], b2[3];
            for (int k = 0; k < 3; k++) {
                b0[k] = ct * b.axis[0][k] + st * b.axis[2][k];
                b2[k] = ct * b.axis[2][k] - st * b.axis[0][k];
            }
            memcpy(b.axis[0], b0, sizeof b0);
            memcpy(b.axis[2], b2, sizeof b2);
        }
        double tol = (double[]){0, 1e-3, 0.1}[trial % 3];
        static const double fac[6] = {-1, 0, 0.99, 1.01, 2, 10};
        double g = trial % 3 == 0 ? (double[]){-1e-3, 0, 1e-6, 1e-3, 0.1, 1}[(trial / 3) % 6]
                                  : tol * fac[(trial / 3) % 6];
        /* Lateral offset within the smaller face so the faces overlap in projection. */
        double lat1 = check_rng_uniform(rng, -0.05, 0.05);
        double lat2 = check_rng_uniform(rng, -0.05, 0.05);
        double side = trial % 4 < 2 ? 1 : -1;
        double reach = a.half[0] + b.half[0] * cos(tilt) + b.half[2] * sin(tilt);
        for (int k = 0; k < 3; k++)
            b.center[k] = a.center[k] + side * (reach + g) * a.axis[0][k] + lat1 * a.axis[1][k] +
                          lat2 * a.axis[2][k];
        int sep = cb_obb_separated(&a, &b, tol);
        /* The distance is g when B's axis 0 is exactly parallel, else within 2 h sin(tilt)
         * <= 4e-9 of g; the margin also covers the round-off guard of the test. */
        double margin = 1e-8;
        int decided = exact ? !(g > tol && g <= tol + margin) : fabs(g - tol) > margin;
        if (decided) {
            CHECK(sep == (g > tol),
                  "parallel trial %d (%s, tilt %g): gap %.17g tol %g: separated %d", trial,
                  exact ? "exact" : "tilted", tilt, g, tol, sep);
            n_sep += sep;
            n_not += !sep;
        }
        double up = dist_upper(&a, &b);
        CHECK(!(sep && up <= tol), "parallel trial %d: separated but samples %.17g apart", trial,
              up);
    }
    CHECK(n_sep > 300 && n_not > 300, "parallel: separated %d, not %d", n_sep, n_not);
}

/* ---------------------------------------------------------------- control nets ------------- */

static void random_knots(double *U, int n, int deg, check_rng *rng)
{
    int m = n + deg + 1;
    for (int i = 0; i <= deg; i++) {
        U[i] = 0;
        U[m - 1 - i] = 1;
    }
    for (int i = deg + 1; i < n; i++)
        U[i] = check_rng_uniform(rng, 0.01, 0.99);
    /* Insertion sort of the interior knots. */
    for (int i = deg + 2; i < n; i++)
        for (int j = i; j > deg + 1 && U[j - 1] > U[j]; j--) {
            double t = U[j];
            U[j] = U[j - 1];
            U[j - 1] = t;
        }
}

static void test_nurbs_nets(check_rng *rng)
{
    double ratio_sum = 0, ratio_max = 0;
    int n_ratio = 0;
    for (int trial = 0; trial < 300; trial++) {
        int du = check_rng_int(rng, 1, 4), dv = check_rng_int(rng, 1, 4);
        int nu = check_rng_int(rng, du + 1, 9), nv = check_rng_int(rng, dv + 1, 9);
        double U[20], V[20], W[81], r[3][3], c[3];
        random_knots(U, nu, du, rng);
        random_knots(V, nv, dv, rng);
        random_rotation(r, rng);
        double far = trial % 3 == 0 ? 1e3 : 1;
        for (int k = 0; k < 3; k++)
            c[k] = check_rng_uniform(rng, -far, far);
        /* A wavy sheet: a surface-like net rather than a cloud. */
        double bend = check_rng_uniform(rng, 0, 1), rough = check_rng_uniform(rng, 0, 0.3);
        for (int i = 0; i < nu; i++)
            for (int j = 0; j < nv; j++) {
                double x = (double)i / (nu - 1), y = (double)j / (nv - 1);
                double l[3] = {3 * x, y, bend * (x - 0.5) * (x - 0.5)};
                for (int k = 0; k < 3; k++)
                    l[k] += rough * check_rng_uniform(rng, -1, 1);
                frame_point(pts + 3 * (i * nv + j), c, r, l);
                W[i * nv + j] = check_rng_uniform(rng, 0.2, 5);
            }
        int rational = trial % 4 != 0;
        cb_nurbs_surface_t s;
        cb_nurbs_surface_init(s);
        cb_error err;
        cb_status st = cb_nurbs_surface_make(s, du, dv, U, nu + du + 1, V, nv + dv + 1, pts,
                                             rational ? W : NULL, nu, nv, &err);
        CHECK(st == CB_OK, "net trial %d: make failed: %s", trial, err.msg);
        if (st != CB_OK)
            continue;
        cb_aabb ab, ref;
        cb_obb ob;
        cb_nurbs_surface_aabb(&ab, s);
        cb_nurbs_surface_obb(&ob, s);

        /* The AABB is exactly that of cw / w. */
        double eu[81 * 3];
        for (int i = 0; i < nu * nv; i++)
            for (int k = 0; k < 3; k++)
                eu[3 * i + k] = s->cw[4 * i + k] / s->cw[4 * i + 3];
        cb_aabb_of_points(&ref, eu, (size_t)(nu * nv), 3);
        CHECK(memcmp(&ab, &ref, sizeof ab) == 0, "net trial %d: surface AABB differs from that of "
                                                 "cw / w",
              trial);
        check_frame(&ob, "net", trial);
        /* The control points as given, which cw / w reproduces only to an ulp. */
        check_contains_all(&ob, pts, (size_t)(nu * nv), "net", trial);
        double ratio = check_volume_vs_aabb(&ob, eu, (size_t)(nu * nv), "net", trial);
        ratio_sum += ratio;
        ratio_max = fmax(ratio_max, ratio);
        n_ratio++;

        /* Points of the surface: inside both boxes up to evaluation round-off. */
        double tol = 1024 * DBL_EPSILON * max_abs_coord(eu, (size_t)(nu * nv));
        int out_o = 0, out_a = 0;
        double bad[3] = {0, 0, 0}, bad_uv[2] = {0, 0};
        for (int i = 0; i < 12; i++)
            for (int j = 0; j < 12; j++) {
                double u = i < 11 ? i / 11.0 : check_rng_uniform(rng, 0, 1);
                double v = j < 11 ? j / 11.0 : check_rng_uniform(rng, 0, 1);
                double p[3];
                cb_nurbs_surface_eval(p, s, u, v);
                int in_a = 1;
                for (int k = 0; k < 3; k++)
                    in_a &= ab.lo[k] - tol <= p[k] && p[k] <= ab.hi[k] + tol;
                if (!cb_obb_contains(&ob, p, tol) || !in_a) {
                    out_o += !cb_obb_contains(&ob, p, tol);
                    out_a += !in_a;
                    memcpy(bad, p, sizeof bad);
                    bad_uv[0] = u;
                    bad_uv[1] = v;
                }
            }
        CHECK(out_o == 0 && out_a == 0,
              "net trial %d: degrees %d %d, %d x %d points: %d surface points outside the OBB, "
              "%d outside the AABB (tol %g), e.g. S(%g, %g) = (%.17g %.17g %.17g)",
              trial, du, dv, nu, nv, out_o, out_a, tol, bad_uv[0], bad_uv[1], bad[0], bad[1],
              bad[2]);
        cb_nurbs_surface_clear(s);

        /* A curve through the first row of the same net. */
        cb_nurbs_curve_t cv;
        cb_nurbs_curve_init(cv);
        st = cb_nurbs_curve_make(cv, dv, V, nv + dv + 1, pts, rational ? W : NULL, nv, &err);
        CHECK(st == CB_OK, "curve trial %d: make failed: %s", trial, err.msg);
        if (st == CB_OK) {
            cb_obb oc;
            cb_aabb ac;
            cb_nurbs_curve_obb(&oc, cv);
            cb_nurbs_curve_aabb(&ac, cv);
            check_frame(&oc, "curve", trial);
            check_contains_all(&oc, pts, (size_t)nv, "curve", trial);
            int out = 0;
            for (int i = 0; i <= 40; i++) {
                double p[3];
                cb_nurbs_curve_eval(p, cv, i / 40.0);
                int in_a = 1;
                for (int k = 0; k < 3; k++)
                    in_a &= ac.lo[k] - tol <= p[k] && p[k] <= ac.hi[k] + tol;
                out += !cb_obb_contains(&oc, p, tol) || !in_a;
            }
            CHECK(out == 0, "curve trial %d: degree %d, %d points: %d curve points outside",
                  trial, dv, nv, out);
        }
        cb_nurbs_curve_clear(cv);
    }
    printf("bbox: random control nets: OBB/AABB volume mean %.3f max %.3f over %d nets\n",
           ratio_sum / n_ratio, ratio_max, n_ratio);
}

int main(void)
{
    check_rng rng = {20230601};
    test_aabb(&rng);
    test_obb_clouds(&rng);
    test_obb_elongated(&rng);
    test_obb_flat_rectangle(&rng);
    test_obb_vs_search(&rng);
    test_obb_large(&rng);
    test_sat_random(&rng);
    test_sat_parallel(&rng);
    test_nurbs_nets(&rng);
    return check_report("bbox");
}
