/* geom.h — small 3D vector helpers and rigid transforms. */
#ifndef CB_GEOM_H
#define CB_GEOM_H

#include <math.h>

/* pi to double precision (M_PI is not C11). */
#define CB_PI 3.14159265358979323846

static inline double cb_vec3_dot(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static inline void cb_vec3_cross(double r[3], const double a[3], const double b[3])
{
    double x = a[1] * b[2] - a[2] * b[1];
    double y = a[2] * b[0] - a[0] * b[2];
    double z = a[0] * b[1] - a[1] * b[0];
    r[0] = x;
    r[1] = y;
    r[2] = z;
}

static inline double cb_vec3_norm(const double a[3]) { return sqrt(cb_vec3_dot(a, a)); }

static inline double cb_vec3_dist(const double a[3], const double b[3])
{
    double d[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
    return cb_vec3_norm(d);
}

/* Scales a to unit length; returns its former length (0 leaves a unchanged). */
static inline double cb_vec3_normalize(double a[3])
{
    double n = cb_vec3_norm(a);
    if (n > 0) {
        a[0] /= n;
        a[1] /= n;
        a[2] /= n;
    }
    return n;
}

/* Distance from p to the segment a-b, and *lambda in [0, 1]: the nearest point's position
 * a + lambda (b - a). */
static inline double cb_seg3_nearest(double *lambda, const double a[3], const double b[3],
                                     const double p[3])
{
    double ab[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double ap[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
    double den = cb_vec3_dot(ab, ab), l = den > 0 ? cb_vec3_dot(ap, ab) / den : 0;
    l = l < 0 ? 0 : l > 1 ? 1 : l;
    double q[3] = {a[0] + l * ab[0], a[1] + l * ab[1], a[2] + l * ab[2]};
    *lambda = l;
    return cb_vec3_dist(q, p);
}

/* 1 when the segment a-b meets the axis-aligned box [lo, hi] grown by slack (the segment
 * clipped slab by slab). */
static inline int cb_seg3_meets_box(const double a[3], const double b[3], const double lo[3],
                                    const double hi[3], double slack)
{
    double t0 = 0, t1 = 1;
    for (int q = 0; q < 3; q++) {
        double l = lo[q] - slack, h = hi[q] + slack, d = b[q] - a[q];
        if (d == 0) {
            if (a[q] < l || a[q] > h)
                return 0;
            continue;
        }
        double ta = (l - a[q]) / d, tb = (h - a[q]) / d;
        if (ta > tb) {
            double w = ta;
            ta = tb;
            tb = w;
        }
        t0 = ta > t0 ? ta : t0;
        t1 = tb < t1 ? tb : t1;
        if (t0 > t1)
            return 0;
    }
    return 1;
}

/* Barycentric coordinates (b1, b2) of the foot of x on the plane of the triangle a b c: the foot
 * is a + b1 (b - a) + b2 (c - a), inside the triangle when b1 >= 0, b2 >= 0, b1 + b2 <= 1.
 * Returns the distance from x to that plane, or -1 for a degenerate triangle (b1, b2 unset). */
static inline double cb_tri3_foot(double *b1, double *b2, const double a[3], const double b[3],
                                  const double c[3], const double x[3])
{
    double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    double w[3] = {x[0] - a[0], x[1] - a[1], x[2] - a[2]}, n[3], t1[3], t2[3];
    cb_vec3_cross(n, e1, e2);
    double nn = cb_vec3_dot(n, n);
    if (!(nn > 0))
        return -1;
    cb_vec3_cross(t1, w, e2);
    cb_vec3_cross(t2, e1, w);
    *b1 = cb_vec3_dot(t1, n) / nn;
    *b2 = cb_vec3_dot(t2, n) / nn;
    return fabs(cb_vec3_dot(w, n)) / sqrt(nn);
}

/* A rigid motion x -> R x + t (R orthonormal, det +1). */
typedef struct {
    double r[3][3];
    double t[3];
} cb_xform;

void cb_xform_identity(cb_xform *x);
/* Rotation by angle (radians) about the line through `point` with direction `axis`. */
void cb_xform_rotation(cb_xform *x, const double point[3], const double axis[3], double angle);
void cb_xform_translation(cb_xform *x, const double t[3]);
/* out = a ∘ b (apply b first, then a); out may alias a or b. */
void cb_xform_compose(cb_xform *out, const cb_xform *a, const cb_xform *b);
void cb_xform_apply_point(double out[3], const cb_xform *x, const double p[3]);
void cb_xform_apply_vector(double out[3], const cb_xform *x, const double v[3]);

/* Eigenvectors of the symmetric 3 x 3 matrix m as the rows of v; m is overwritten by the
 * diagonalised matrix, whose diagonal m[i][i] is the eigenvalue of row i of v. Cyclic Jacobi
 * rotations to DBL_EPSILON of the norm of m (at most 32 sweeps); the zero matrix gives the
 * identity. */
void cb_sym3_eigen(double v[3][3], double m[3][3]);

/* Solves the n x n system A x = b in place (A row-major, overwritten; x returned in b) by
 * Gaussian elimination with partial pivoting. 0, with A and b in an undefined state, when a
 * pivot is not above rel times the largest |A| entry (rel 0: when one is zero). */
int cb_linsolve(double *A, double *b, int n, double rel);

#endif
