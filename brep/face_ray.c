/* Ray / trimmed face intersection: closed forms for the analytic surfaces, sample cells and
 * Newton steps for the others, then the trimming test of each point found. */
#include <stdlib.h>
#include <string.h>

#include "brep/face.h"

enum { MAX_RAW = 128 /* raw surface intersections considered per face */ };

typedef struct {
    double s, u, v; /* s: distance along the unit direction */
    int tangent;    /* found as a double root or with a singular Newton system */
} raw_hit;

typedef struct {
    raw_hit h[MAX_RAW];
    int n;
} raw_list;

static void add_raw(raw_list *l, double s, double u, double v, int tangent)
{
    if (l->n < MAX_RAW)
        l->h[l->n++] = (raw_hit){s, u, v, tangent};
}

/* ---------------------------------------------------------------- polynomial roots --------- */

static double poly_eval(const double *c, int n, double x)
{
    double y = c[n];
    for (int k = n - 1; k >= 0; k--)
        y = y * x + c[k];
    return y;
}

/* Sum |c_k| |x|^k: the scale of the rounding of poly_eval at x. */
static double poly_mag(const double *c, int n, double x)
{
    double y = fabs(c[n]), ax = fabs(x);
    for (int k = n - 1; k >= 0; k--)
        y = y * ax + fabs(c[k]);
    return y;
}

/* The root of c in [lo, hi], where c changes sign, by bisection. */
static double bisect(const double *c, int n, double lo, double hi)
{
    double flo = poly_eval(c, n, lo);
    for (int it = 0; it < 200 && hi - lo > 1e-15 * (fabs(lo) + fabs(hi)); it++) {
        double m = 0.5 * (lo + hi), fm = poly_eval(c, n, m);
        if ((fm < 0) == (flo < 0)) {
            lo = m;
            flo = fm;
        } else {
            hi = m;
        }
    }
    return 0.5 * (lo + hi);
}

/* Real roots of sum c[k] x^k (degree n <= 4, c[n] != 0) in increasing order; tangent[k] set
 * for a root found as a touching extremum (a double root up to rounding). Method: the roots of
 * the derivative split the line into monotone pieces, each holding at most one root. */
static int poly_roots(double *roots, int *tangent, const double *c, int n)
{
    if (n == 1) {
        roots[0] = -c[0] / c[1];
        tangent[0] = 0;
        return 1;
    }
    double dc[4] = {0, 0, 0, 0};
    for (int k = 1; k <= n; k++)
        dc[k - 1] = k * c[k];
    double crit[4];
    int ct[4], m = poly_roots(crit, ct, dc, n - 1);
    double bound = 0;
    for (int k = 0; k < n; k++)
        bound = fmax(bound, fabs(c[k] / c[n]));
    bound += 1;
    double pts[6];
    int np = 0;
    pts[np++] = -bound;
    for (int k = 0; k < m; k++)
        if (crit[k] > -bound && crit[k] < bound)
            pts[np++] = crit[k];
    pts[np++] = bound;
    int nr = 0;
    for (int k = 0; k + 1 < np; k++) {
        double fa = poly_eval(c, n, pts[k]), fb = poly_eval(c, n, pts[k + 1]);
        if (k > 0 && fabs(fa) <= 1e-12 * poly_mag(c, n, pts[k])) {
            roots[nr] = pts[k];
            tangent[nr++] = 1;
            continue;
        }
        if ((fa < 0) != (fb < 0) && fb != 0) {
            roots[nr] = bisect(c, n, pts[k], pts[k + 1]);
            tangent[nr++] = 0;
        }
    }
    return nr;
}

/* ---------------------------------------------------------------- analytic ----------------- */

static void quadratic(double A, double B, double C, double out[2][2], int *n, int *tang)
{
    *n = 0;
    *tang = 0;
    double scale = fmax(fabs(A), fmax(fabs(B), fabs(C)));
    if (scale == 0)
        return;
    if (fabs(A) <= 1e-14 * scale) {
        if (B != 0) {
            out[0][0] = -C / B;
            *n = 1;
        }
        return;
    }
    double disc = B * B - 4 * A * C;
    if (disc < 0) {
        if (disc < -1e-12 * (B * B + fabs(4 * A * C)))
            return;
        out[0][0] = -B / (2 * A);
        *n = 1;
        *tang = 1;
        return;
    }
    double q = -0.5 * (B + copysign(sqrt(disc), B));
    out[0][0] = q / A;
    out[1][0] = q != 0 ? C / q : q / A;
    *n = 2;
    if (disc <= 1e-12 * (B * B + fabs(4 * A * C)))
        *tang = 1;
}

static void analytic_hits(raw_list *l, const cb_analytic_surface *a, const double o[3],
                          const double e[3])
{
    double q[3], w[3], pt[3];
    cb_frame_to_local(q, &a->frame, o);
    const cb_frame *fr = &a->frame;
    w[0] = cb_vec3_dot(e, fr->x);
    w[1] = cb_vec3_dot(e, fr->y);
    w[2] = cb_vec3_dot(e, fr->z);
    double ss[4];
    int ts[4], n = 0;
    if (a->kind == CB_ANALYTIC_PLANE) {
        if (w[2] == 0)
            return;
        ss[n] = -q[2] / w[2];
        ts[n++] = 0;
    } else if (a->kind == CB_ANALYTIC_TORUS) {
        double sc = -cb_vec3_dot(q, w), c[5], R = a->r1, r = a->r2;
        double p0[3] = {q[0] + sc * w[0], q[1] + sc * w[1], q[2] + sc * w[2]};
        double b = cb_vec3_dot(p0, w), c0 = cb_vec3_dot(p0, p0) + R * R - r * r;
        double A2 = w[0] * w[0] + w[1] * w[1], B2 = 2 * (p0[0] * w[0] + p0[1] * w[1]);
        double C2 = p0[0] * p0[0] + p0[1] * p0[1];
        c[4] = 1;
        c[3] = 4 * b;
        c[2] = 4 * b * b + 2 * c0 - 4 * R * R * A2;
        c[1] = 4 * b * c0 - 4 * R * R * B2;
        c[0] = c0 * c0 - 4 * R * R * C2;
        double roots[4];
        n = poly_roots(roots, ts, c, 4);
        for (int k = 0; k < n; k++) {
            double x = roots[k];
            for (int it = 0; it < 3; it++) { /* Newton polish */
                double f = poly_eval(c, 4, x), df = 4 * c[4];
                df = ((df * x + 3 * c[3]) * x + 2 * c[2]) * x + c[1];
                if (df == 0)
                    break;
                x -= f / df;
            }
            ss[k] = sc + x;
        }
    } else {
        double A, B, C;
        if (a->kind == CB_ANALYTIC_CYLINDER) {
            A = w[0] * w[0] + w[1] * w[1];
            B = 2 * (q[0] * w[0] + q[1] * w[1]);
            C = q[0] * q[0] + q[1] * q[1] - a->r1 * a->r1;
        } else if (a->kind == CB_ANALYTIC_CONE) {
            double ta = tan(a->angle), rq = a->r1 + q[2] * ta;
            A = w[0] * w[0] + w[1] * w[1] - ta * ta * w[2] * w[2];
            B = 2 * (q[0] * w[0] + q[1] * w[1] - rq * ta * w[2]);
            C = q[0] * q[0] + q[1] * q[1] - rq * rq;
        } else {
            double sx = a->r1, sy = a->r1, sz = a->r1;
            if (a->kind == CB_ANALYTIC_ELLIPSOID) {
                sy = a->r2;
                sz = a->r3;
            }
            double qq[3] = {q[0] / sx, q[1] / sy, q[2] / sz}, ww[3] = {w[0] / sx, w[1] / sy,
                                                                      w[2] / sz};
            A = cb_vec3_dot(ww, ww);
            B = 2 * cb_vec3_dot(qq, ww);
            C = cb_vec3_dot(qq, qq) - 1;
        }
        double out[2][2];
        int tang;
        quadratic(A, B, C, out, &n, &tang);
        for (int k = 0; k < n; k++) {
            ss[k] = out[k][0];
            ts[k] = tang;
        }
    }
    for (int k = 0; k < n; k++) {
        double s = ss[k], u, v;
        for (int i = 0; i < 3; i++)
            pt[i] = q[i] + s * w[i];
        switch (a->kind) {
        case CB_ANALYTIC_PLANE:
            u = pt[0];
            v = pt[1];
            break;
        case CB_ANALYTIC_CYLINDER:
            u = atan2(pt[1], pt[0]);
            v = pt[2];
            break;
        case CB_ANALYTIC_CONE:
            if (a->r1 + pt[2] * tan(a->angle) < 0)
                continue; /* the other nappe */
            u = atan2(pt[1], pt[0]);
            v = pt[2];
            break;
        case CB_ANALYTIC_SPHERE:
            u = atan2(pt[1], pt[0]);
            v = asin(fmax(-1, fmin(1, pt[2] / a->r1)));
            break;
        case CB_ANALYTIC_ELLIPSOID:
            u = atan2(pt[1] / a->r2, pt[0] / a->r1);
            v = asin(fmax(-1, fmin(1, pt[2] / a->r3)));
            break;
        default:
            u = atan2(pt[1], pt[0]);
            v = atan2(pt[2], hypot(pt[0], pt[1]) - a->r1);
            break;
        }
        add_raw(l, s, u, v, ts[k]);
    }
}

/* ---------------------------------------------------------------- sampled surfaces --------- */

/* Entry and exit distances of the ray in box b, or 0 when it misses [s0, s1]. */
static int slab(const cb_aabb *b, const double o[3], const double e[3], double s0, double s1)
{
    for (int i = 0; i < 3; i++) {
        if (e[i] == 0) {
            if (o[i] < b->lo[i] || o[i] > b->hi[i])
                return 0;
            continue;
        }
        double a = (b->lo[i] - o[i]) / e[i], c = (b->hi[i] - o[i]) / e[i];
        s0 = fmax(s0, fmin(a, c));
        s1 = fmin(s1, fmax(a, c));
        if (s0 > s1)
            return 0;
    }
    return 1;
}

/* Newton steps on S(u, v) - (o + s e) = 0 from (u, v, s); 1 when it converges. */
static int newton(double x[3], int *tangent, const cb_face *f, const double o[3],
                  const double e[3], double scale)
{
    const cb_topo_inverter *inv = &f->inv;
    for (int it = 0; it < 40; it++) {
        double d[6][3], F[3], n[3];
        cb_topo_inverter_eval_derivs(d, inv, x[0], x[1]);
        for (int i = 0; i < 3; i++)
            F[i] = d[0][i] - o[i] - x[2] * e[i];
        double res = cb_vec3_norm(F);
        cb_vec3_cross(n, d[1], d[2]);
        double det = -cb_vec3_dot(n, e), jn = cb_vec3_norm(n);
        if (res <= 1e-12 * scale) {
            *tangent = fabs(det) <= 1e-9 * jn;
            return 1;
        }
        if (det == 0)
            return 0;
        /* Cramer's rule on [S_u S_v -e] dx = -F. */
        double m1[3], m2[3], mF[3] = {-F[0], -F[1], -F[2]}, me[3] = {-e[0], -e[1], -e[2]};
        cb_vec3_cross(m1, mF, d[2]);
        cb_vec3_cross(m2, d[1], mF);
        double du = cb_vec3_dot(m1, me) / det, dv = cb_vec3_dot(m2, me) / det;
        double ds = cb_vec3_dot(n, mF) / det;
        x[0] += du;
        x[1] += dv;
        x[2] += ds;
        for (int i = 0; i < 2; i++)
            if (inv->period[i] <= 0)
                x[i] = fmin(fmax(x[i], inv->box[2 * i]), inv->box[2 * i + 1]);
        if (!isfinite(x[0] + x[1] + x[2]))
            return 0;
    }
    return 0;
}

enum { MAX_CELL_DEPTH = 6 };

/* A cell is flat enough for a Newton start when its bilinear deviation is below this fraction
 * of its extent: the ray then meets it at most about once. */
static const double CELL_FLAT = 0.02;

static void add_root(raw_list *l, const cb_face *f, const double x[3], int tangent, double scale)
{
    for (int k = 0; k < l->n; k++) {
        double pa[3], pb[3];
        if (fabs(l->h[k].s - x[2]) > 1e-9 * scale)
            continue;
        cb_topo_inverter_eval(pa, &f->inv, l->h[k].u, l->h[k].v);
        cb_topo_inverter_eval(pb, &f->inv, x[0], x[1]);
        if (cb_vec3_dist(pa, pb) <= 1e-9 * scale)
            return;
    }
    add_raw(l, x[2], x[0], x[1], tangent);
}

/* Searches the parameter rectangle uv: its box from 3 x 3 samples grown by twice their
 * bilinear deviation; quartered while the ray meets the box and the rectangle is not flat,
 * then Newton steps from its centre. */
static void search(raw_list *l, const cb_face *f, const double uv[4], const double o[3],
                   const double e[3], double s0, double s1, double scale, int depth)
{
    double pts[9][3], dev = 0;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            cb_topo_inverter_eval(pts[3 * i + j], &f->inv, uv[0] + (uv[1] - uv[0]) * i / 2,
                                  uv[2] + (uv[3] - uv[2]) * j / 2);
    for (int k = 0; k < 3; k++) {
        dev = fmax(dev, fabs(pts[1][k] - 0.5 * (pts[0][k] + pts[2][k])));
        dev = fmax(dev, fabs(pts[7][k] - 0.5 * (pts[6][k] + pts[8][k])));
        dev = fmax(dev, fabs(pts[3][k] - 0.5 * (pts[0][k] + pts[6][k])));
        dev = fmax(dev, fabs(pts[5][k] - 0.5 * (pts[2][k] + pts[8][k])));
        dev = fmax(dev, fabs(pts[4][k] - 0.25 * (pts[0][k] + pts[2][k] + pts[6][k] + pts[8][k])));
    }
    cb_aabb bx;
    cb_aabb_of_points(&bx, &pts[0][0], 9, 3);
    double ext = 0;
    for (int k = 0; k < 3; k++) {
        ext = fmax(ext, bx.hi[k] - bx.lo[k]);
        bx.lo[k] -= 2 * dev + f->tol;
        bx.hi[k] += 2 * dev + f->tol;
    }
    if (!slab(&bx, o, e, s0 - f->tol, s1 + f->tol))
        return;
    if (depth < MAX_CELL_DEPTH && dev > CELL_FLAT * ext) {
        double um = 0.5 * (uv[0] + uv[1]), vm = 0.5 * (uv[2] + uv[3]);
        double q[4][4] = {{uv[0], um, uv[2], vm}, {um, uv[1], uv[2], vm},
                          {uv[0], um, vm, uv[3]}, {um, uv[1], vm, uv[3]}};
        for (int k = 0; k < 4; k++)
            search(l, f, q[k], o, e, s0, s1, scale, depth + 1);
        return;
    }
    double x[3] = {0.5 * (uv[0] + uv[1]), 0.5 * (uv[2] + uv[3]), 0}, pc[3];
    for (int i = 0; i < 3; i++)
        pc[i] = pts[4][i] - o[i];
    x[2] = cb_vec3_dot(pc, e);
    int tangent;
    if (newton(x, &tangent, f, o, e, scale))
        add_root(l, f, x, tangent, scale);
}

static void cell_hits(raw_list *l, const cb_face *f, const double o[3], const double e[3],
                      double s0, double s1)
{
    double scale = f->size + cb_vec3_norm(o) + 1e-300;
    for (int c = 0; c < f->n_cells; c++)
        if (slab(&f->cells[c].box, o, e, s0 - f->tol, s1 + f->tol))
            search(l, f, f->cells[c].uv, o, e, s0, s1, scale, 0);
}

/* ---------------------------------------------------------------- driver ------------------- */

static int hit_cmp(const void *x, const void *y)
{
    double a = ((const cb_face_hit *)x)->t, b = ((const cb_face_hit *)y)->t;
    return (a > b) - (a < b);
}

int cb_face_ray(cb_face_hit *hits, int max, const cb_face *f, const double o[3], const double d[3],
                double t0, double t1, double tol, double graze)
{
    double len = cb_vec3_norm(d);
    if (!(len > 0))
        return 0;
    double e[3] = {d[0] / len, d[1] / len, d[2] / len};
    double s0 = t0 * len, s1 = t1 * len;
    if (!slab(&f->box, o, e, s0 - tol, s1 + tol))
        return 0;
    raw_list raw, *l = &raw;
    l->n = 0;
    const cb_topo_surface *s = &f->b->surfaces[f->b->faces[f->face].surface];
    if (s->kind == CB_SURFACE_ANALYTIC)
        analytic_hits(l, &s->analytic, o, e);
    else
        cell_hits(l, f, o, e, s0, s1);
    int n = 0;
    cb_face_hit buf[MAX_RAW];
    for (int k = 0; k < l->n; k++) {
        const raw_hit *h = &l->h[k];
        if (h->s < s0 || h->s > s1)
            continue;
        cb_face_where w = cb_face_classify_uv(f, h->u, h->v, tol);
        if (w == CB_FACE_OUT)
            continue;
        double nrm[3], c = 0;
        if (cb_face_normal(nrm, f, h->u, h->v) > 0)
            c = cb_vec3_dot(nrm, e);
        cb_face_hit_kind kind = CB_FACE_HIT_CROSS;
        if (w == CB_FACE_ON)
            kind = CB_FACE_HIT_EDGE;
        else if (h->tangent || fabs(c) < graze)
            kind = CB_FACE_HIT_GRAZE;
        buf[n++] = (cb_face_hit){.t = h->s / len, .u = h->u, .v = h->v, .cos = c, .kind = kind};
    }
    qsort(buf, (size_t)n, sizeof *buf, hit_cmp);
    for (int k = 0; k < n && k < max; k++)
        hits[k] = buf[k];
    return n;
}
