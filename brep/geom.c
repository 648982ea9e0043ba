#include "brep/geom.h"

#include <float.h>
#include <string.h>

void cb_xform_identity(cb_xform *x)
{
    memset(x, 0, sizeof *x);
    x->r[0][0] = x->r[1][1] = x->r[2][2] = 1.0;
}

void cb_xform_rotation(cb_xform *x, const double point[3], const double axis[3], double angle)
{
    double k[3] = {axis[0], axis[1], axis[2]};
    cb_vec3_normalize(k);
    double c = cos(angle), s = sin(angle), C = 1.0 - c;
    /* Rodrigues' formula. */
    x->r[0][0] = c + k[0] * k[0] * C;
    x->r[0][1] = k[0] * k[1] * C - k[2] * s;
    x->r[0][2] = k[0] * k[2] * C + k[1] * s;
    x->r[1][0] = k[1] * k[0] * C + k[2] * s;
    x->r[1][1] = c + k[1] * k[1] * C;
    x->r[1][2] = k[1] * k[2] * C - k[0] * s;
    x->r[2][0] = k[2] * k[0] * C - k[1] * s;
    x->r[2][1] = k[2] * k[1] * C + k[0] * s;
    x->r[2][2] = c + k[2] * k[2] * C;
    /* Fix `point`: t = point - R point. */
    double rp[3];
    for (int i = 0; i < 3; i++)
        rp[i] = x->r[i][0] * point[0] + x->r[i][1] * point[1] + x->r[i][2] * point[2];
    for (int i = 0; i < 3; i++)
        x->t[i] = point[i] - rp[i];
}

void cb_xform_translation(cb_xform *x, const double t[3])
{
    cb_xform_identity(x);
    memcpy(x->t, t, sizeof x->t);
}

void cb_xform_compose(cb_xform *out, const cb_xform *a, const cb_xform *b)
{
    cb_xform r;
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++)
            r.r[i][j] = a->r[i][0] * b->r[0][j] + a->r[i][1] * b->r[1][j] + a->r[i][2] * b->r[2][j];
        r.t[i] = a->r[i][0] * b->t[0] + a->r[i][1] * b->t[1] + a->r[i][2] * b->t[2] + a->t[i];
    }
    *out = r;
}

void cb_xform_apply_vector(double out[3], const cb_xform *x, const double v[3])
{
    double r[3];
    for (int i = 0; i < 3; i++)
        r[i] = x->r[i][0] * v[0] + x->r[i][1] * v[1] + x->r[i][2] * v[2];
    memcpy(out, r, sizeof r);
}

void cb_xform_apply_point(double out[3], const cb_xform *x, const double p[3])
{
    double r[3];
    cb_xform_apply_vector(r, x, p);
    for (int i = 0; i < 3; i++)
        out[i] = r[i] + x->t[i];
}

/* Eigenvectors of the symmetric matrix m (overwritten) as the rows of v, by cyclic Jacobi
 * rotations (Golub, Van Loan, Matrix Computations, 4th ed., alg. 8.5.3). Stops when the
 * off-diagonal part is below DBL_EPSILON times the norm of m — beyond that the eigenvectors
 * are as accurate as the data — or after 32 sweeps (convergence is quadratic; a handful
 * suffice). The zero matrix gives the identity. */
void cb_sym3_eigen(double v[3][3], double m[3][3])
{
    static const int pairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};
    double norm2 = 0.0;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            norm2 += m[i][j] * m[i][j];
            v[i][j] = i == j;
        }
    for (int sweep = 0; sweep < 32; sweep++) {
        double off2 = 2 * (m[0][1] * m[0][1] + m[0][2] * m[0][2] + m[1][2] * m[1][2]);
        if (off2 <= DBL_EPSILON * DBL_EPSILON * norm2)
            break;
        for (int r = 0; r < 3; r++) {
            int p = pairs[r][0], q = pairs[r][1];
            if (m[p][q] == 0.0)
                continue;
            double tau = (m[q][q] - m[p][p]) / (2 * m[p][q]);
            double t = (tau >= 0 ? 1.0 : -1.0) / (fabs(tau) + sqrt(1.0 + tau * tau));
            double c = 1.0 / sqrt(1.0 + t * t), sn = t * c;
            /* m <- J^T m J and v <- J^T v, J the rotation by (c, sn) in the (p, q) plane. */
            for (int i = 0; i < 3; i++) {
                double mp = m[i][p], mq = m[i][q];
                m[i][p] = c * mp - sn * mq;
                m[i][q] = sn * mp + c * mq;
            }
            for (int j = 0; j < 3; j++) {
                double mp = m[p][j], mq = m[q][j];
                m[p][j] = c * mp - sn * mq;
                m[q][j] = sn * mp + c * mq;
            }
            for (int j = 0; j < 3; j++) {
                double vp = v[p][j], vq = v[q][j];
                v[p][j] = c * vp - sn * vq;
                v[q][j] = sn * vp + c * vq;
            }
        }
    }
}

int cb_linsolve(double *A, double *b, int n, double rel)
{
    double big = 0;
    for (int k = 0; k < n * n; k++)
        big = fmax(big, fabs(A[k]));
    for (int c = 0; c < n; c++) {
        int p = c;
        for (int r = c + 1; r < n; r++)
            if (fabs(A[r * n + c]) > fabs(A[p * n + c]))
                p = r;
        if (!(fabs(A[p * n + c]) > rel * big))
            return 0;
        if (p != c) {
            for (int k = 0; k < n; k++) {
                double t = A[c * n + k];
                A[c * n + k] = A[p * n + k];
                A[p * n + k] = t;
            }
            double t = b[c];
            b[c] = b[p];
            b[p] = t;
        }
        for (int r = c + 1; r < n; r++) {
            double f = A[r * n + c] / A[c * n + c];
            for (int k = c; k < n; k++)
                A[r * n + k] -= f * A[c * n + k];
            b[r] -= f * b[c];
        }
    }
    for (int c = n - 1; c >= 0; c--) {
        for (int k = c + 1; k < n; k++)
            b[c] -= A[c * n + k] * b[k];
        b[c] /= A[c * n + c];
    }
    return 1;
}
