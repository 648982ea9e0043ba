/* Planar predicates of the parameter-domain triangulation. The orientation test must be exact:
 * the walk that locates points, the flips and the constraint recovery all branch on its sign,
 * and a wrong sign on near-collinear boundary samples (a dense edge on a flat face) would tear
 * the triangulation. Method: J. R. Shewchuk, "Adaptive precision floating-point arithmetic and
 * fast robust geometric predicates" (1997): a filter, then exact expansions. */
#include <math.h>

#include "brep/tess_internal.h"

/* a + b = s + e exactly. */
static void two_sum(double a, double b, double *s, double *e)
{
    double x = a + b, bv = x - a, av = x - bv;
    *s = x;
    *e = (a - av) + (b - bv);
}

/* a * b = p + e exactly (fma gives the rounding error of the product). */
static void two_product(double a, double b, double *p, double *e)
{
    double x = a * b;
    *p = x;
    *e = fma(a, b, -x);
}

/* Adds b to the non-overlapping expansion e[0..n) (increasing magnitude); returns the new
 * length, at most n + 1 (Shewchuk's Grow-Expansion with zero elimination). */
static int grow_expansion(double *e, int n, double b)
{
    double q = b;
    int m = 0;
    for (int i = 0; i < n; i++) {
        double s, err;
        two_sum(q, e[i], &s, &err);
        q = s;
        if (err != 0)
            e[m++] = err;
    }
    if (q != 0)
        e[m++] = q;
    return m;
}

static int orient2d_exact(const double a[2], const double b[2], const double c[2])
{
    double acx[2], acy[2], bcx[2], bcy[2];
    two_sum(a[0], -c[0], &acx[1], &acx[0]);
    two_sum(a[1], -c[1], &acy[1], &acy[0]);
    two_sum(b[0], -c[0], &bcx[1], &bcx[0]);
    two_sum(b[1], -c[1], &bcy[1], &bcy[0]);
    double e[17];
    int n = 0;
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2; j++) {
            double p, q;
            two_product(acx[i], bcy[j], &p, &q);
            n = grow_expansion(e, n, q);
            n = grow_expansion(e, n, p);
            two_product(acy[i], bcx[j], &p, &q);
            n = grow_expansion(e, n, -q);
            n = grow_expansion(e, n, -p);
        }
    return n == 0 ? 0 : e[n - 1] > 0 ? 1 : -1;
}

int cb_tess_orient2d(const double a[2], const double b[2], const double c[2])
{
    double l = (a[0] - c[0]) * (b[1] - c[1]), r = (a[1] - c[1]) * (b[0] - c[0]);
    double det = l - r;
    /* Shewchuk's ccwerrboundA = (3 + 16 eps) eps. */
    double bound = (3.0 + 16.0 * 0x1p-53) * 0x1p-53 * (fabs(l) + fabs(r));
    if (det > bound)
        return 1;
    if (-det > bound)
        return -1;
    return orient2d_exact(a, b, c);
}

double cb_tess_incircle(const double a[2], const double b[2], const double c[2],
                        const double d[2])
{
    double adx = a[0] - d[0], ady = a[1] - d[1];
    double bdx = b[0] - d[0], bdy = b[1] - d[1];
    double cdx = c[0] - d[0], cdy = c[1] - d[1];
    double al = adx * adx + ady * ady, bl = bdx * bdx + bdy * bdy, cl = cdx * cdx + cdy * cdy;
    double bc = bdx * cdy - cdx * bdy, ca = cdx * ady - adx * cdy, ab = adx * bdy - bdx * ady;
    double det = al * bc + bl * ca + cl * ab;
    double perm = al * (fabs(bdx * cdy) + fabs(cdx * bdy)) +
                  bl * (fabs(cdx * ady) + fabs(adx * cdy)) +
                  cl * (fabs(adx * bdy) + fabs(bdx * ady));
    /* Shewchuk's iccerrboundA = (10 + 96 eps) eps: below it the sign is not known. */
    double bound = (10.0 + 96.0 * 0x1p-53) * 0x1p-53 * perm;
    return fabs(det) > bound ? det : 0;
}
