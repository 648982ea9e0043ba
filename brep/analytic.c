/* Placement frames, analytic surface construction and evaluation, trivariate polynomials and
 * the implicit equations of the analytic surfaces. */
#include "brep/analytic.h"

#include <float.h>
#include <stdlib.h>
#include <string.h>

static const double pi = 3.14159265358979323846;

/* ---------------------------------------------------------------- placement frames --------- */

static int finite3(const double v[3]) { return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]); }

/* u = v / |v| for finite v; dividing by the largest component first keeps |v| from overflowing.
 * Returns 0 when v is zero. */
static int unit_vector(double u[3], const double v[3])
{
    double m = fmax(fabs(v[0]), fmax(fabs(v[1]), fabs(v[2])));
    if (!(m > 0))
        return 0;
    for (int i = 0; i < 3; i++)
        u[i] = v[i] / m;
    cb_vec3_normalize(u);
    return 1;
}

/* x = r - (r.z) z, in place. */
static void reject_from(double x[3], const double z[3])
{
    double d = cb_vec3_dot(x, z);
    for (int i = 0; i < 3; i++)
        x[i] -= d * z[i];
}

cb_status cb_frame_make(cb_frame *f, const double origin[3], const double axis[3],
                        const double ref_dir[3], cb_error *err)
{
    double z[3], x[3], ref[3];
    if (!finite3(origin))
        return cb_error_set(err, CB_ERR_INVALID, "frame: origin is not finite");
    if (!finite3(axis))
        return cb_error_set(err, CB_ERR_INVALID, "frame: axis is not finite");
    if (!unit_vector(z, axis))
        return cb_error_set(err, CB_ERR_INVALID, "frame: axis is the zero vector");
    if (ref_dir) {
        if (!finite3(ref_dir))
            return cb_error_set(err, CB_ERR_INVALID, "frame: reference direction is not finite");
        if (!unit_vector(x, ref_dir))
            return cb_error_set(err, CB_ERR_INVALID,
                                "frame: reference direction is the zero vector");
    } else {
        /* The world axis least aligned with z keeps at least sqrt(2/3) after projection. */
        int k = 0;
        for (int i = 1; i < 3; i++)
            if (fabs(z[i]) < fabs(z[k]))
                k = i;
        x[0] = x[1] = x[2] = 0.0;
        x[k] = 1.0;
    }
    memcpy(ref, x, sizeof ref);
    reject_from(x, z);
    /* x and z are unit vectors, so the projection is exact to a few ulps; a remainder at that
     * level is rounding noise with no direction: the reference is parallel to the axis. */
    double n = cb_vec3_normalize(x);
    if (!(n > 8 * DBL_EPSILON))
        return cb_error_set(err, CB_ERR_INVALID,
                            "frame: reference direction is parallel to the axis (normalised: "
                            "reference (%.17g, %.17g, %.17g), axis (%.17g, %.17g, %.17g))",
                            ref[0], ref[1], ref[2], z[0], z[1], z[2]);
    /* When the reference was nearly parallel, the rounding of the first pass is large relative
     * to the small remainder; a second pass restores orthogonality to round-off. */
    reject_from(x, z);
    cb_vec3_normalize(x);
    memcpy(f->o, origin, sizeof f->o);
    memcpy(f->z, z, sizeof f->z);
    memcpy(f->x, x, sizeof f->x);
    cb_vec3_cross(f->y, z, x);
    return CB_OK;
}

/* o (if given) + l[0] x + l[1] y + l[2] z. */
static void frame_combine(double p[3], const cb_frame *f, const double *o, const double l[3])
{
    double r[3];
    for (int i = 0; i < 3; i++)
        r[i] = (o ? o[i] : 0.0) + l[0] * f->x[i] + l[1] * f->y[i] + l[2] * f->z[i];
    memcpy(p, r, sizeof r);
}

void cb_frame_to_world(double p[3], const cb_frame *f, const double l[3])
{
    frame_combine(p, f, f->o, l);
}

void cb_frame_to_local(double l[3], const cb_frame *f, const double p[3])
{
    double d[3] = {p[0] - f->o[0], p[1] - f->o[1], p[2] - f->o[2]};
    l[0] = cb_vec3_dot(f->x, d);
    l[1] = cb_vec3_dot(f->y, d);
    l[2] = cb_vec3_dot(f->z, d);
}

/* ---------------------------------------------------------------- surfaces ----------------- */

const char *cb_analytic_kind_name(cb_analytic_kind kind)
{
    switch (kind) {
    case CB_ANALYTIC_PLANE: return "plane";
    case CB_ANALYTIC_CYLINDER: return "cylinder";
    case CB_ANALYTIC_CONE: return "cone";
    case CB_ANALYTIC_SPHERE: return "sphere";
    case CB_ANALYTIC_TORUS: return "torus";
    case CB_ANALYTIC_ELLIPSOID: return "ellipsoid";
    }
    return "unknown surface kind";
}

static void analytic_set(cb_analytic_surface *s, cb_analytic_kind kind, const cb_frame *f,
                         double r1, double r2, double r3, double angle)
{
    s->kind = kind;
    s->frame = *f;
    s->r1 = r1;
    s->r2 = r2;
    s->r3 = r3;
    s->angle = angle;
}

static cb_status check_positive(double v, const char *what, cb_error *err)
{
    if (!(isfinite(v) && v > 0))
        return cb_error_set(err, CB_ERR_INVALID, "%s %.17g must be finite and > 0", what, v);
    return CB_OK;
}

cb_status cb_analytic_plane(cb_analytic_surface *s, const cb_frame *f, cb_error *err)
{
    (void)err;
    analytic_set(s, CB_ANALYTIC_PLANE, f, 0, 0, 0, 0);
    return CB_OK;
}

cb_status cb_analytic_cylinder(cb_analytic_surface *s, const cb_frame *f, double radius,
                               cb_error *err)
{
    cb_status st = check_positive(radius, "cylinder: radius", err);
    if (!st)
        analytic_set(s, CB_ANALYTIC_CYLINDER, f, radius, 0, 0, 0);
    return st;
}

cb_status cb_analytic_cone(cb_analytic_surface *s, const cb_frame *f, double radius,
                           double semi_angle, cb_error *err)
{
    if (!(isfinite(radius) && radius >= 0))
        return cb_error_set(err, CB_ERR_INVALID, "cone: radius %.17g must be finite and >= 0",
                            radius);
    if (!(semi_angle > 0 && semi_angle < pi / 2))
        return cb_error_set(err, CB_ERR_INVALID,
                            "cone: semi-angle %.17g must be in the open interval (0, pi/2)",
                            semi_angle);
    analytic_set(s, CB_ANALYTIC_CONE, f, radius, 0, 0, semi_angle);
    return CB_OK;
}

cb_status cb_analytic_sphere(cb_analytic_surface *s, const cb_frame *f, double radius,
                             cb_error *err)
{
    cb_status st = check_positive(radius, "sphere: radius", err);
    if (!st)
        analytic_set(s, CB_ANALYTIC_SPHERE, f, radius, 0, 0, 0);
    return st;
}

cb_status cb_analytic_torus(cb_analytic_surface *s, const cb_frame *f, double major_radius,
                            double minor_radius, cb_error *err)
{
    cb_status st = check_positive(major_radius, "torus: major radius", err);
    if (!st)
        st = check_positive(minor_radius, "torus: minor radius", err);
    if (st)
        return st;
    if (major_radius == minor_radius)
        return cb_error_set(err, CB_ERR_INVALID,
                            "torus: major radius %.17g equals minor radius (a horn torus: its "
                            "tube touches the axis in a point where it meets itself; not "
                            "supported)",
                            major_radius);
    analytic_set(s, CB_ANALYTIC_TORUS, f, major_radius, minor_radius, 0, 0);
    return CB_OK;
}

cb_status cb_analytic_ellipsoid(cb_analytic_surface *s, const cb_frame *f, double a, double b,
                                double c, cb_error *err)
{
    cb_status st = check_positive(a, "ellipsoid: semi-axis a", err);
    if (!st)
        st = check_positive(b, "ellipsoid: semi-axis b", err);
    if (!st)
        st = check_positive(c, "ellipsoid: semi-axis c", err);
    if (!st)
        analytic_set(s, CB_ANALYTIC_ELLIPSOID, f, a, b, c, 0);
    return st;
}

/* The revolved form (sx rho(v) cos u, sy rho(v) sin u, h(v)) of every kind but the plane:
 * rho[k], h[k] are the k-th derivatives in v. */
typedef struct {
    double rho[3], h[3], sx, sy;
} profile;

static void profile_at(profile *q, const cb_analytic_surface *s, double v)
{
    double cv = cos(v), sv = sin(v);
    q->sx = q->sy = 1.0;
    switch (s->kind) {
    case CB_ANALYTIC_PLANE: break;
    case CB_ANALYTIC_CYLINDER:
    case CB_ANALYTIC_CONE: {
        double t = s->kind == CB_ANALYTIC_CONE ? tan(s->angle) : 0.0;
        q->rho[0] = s->r1 + v * t;
        q->rho[1] = t;
        q->rho[2] = 0.0;
        q->h[0] = v;
        q->h[1] = 1.0;
        q->h[2] = 0.0;
        return;
    }
    case CB_ANALYTIC_SPHERE:
    case CB_ANALYTIC_TORUS:
    case CB_ANALYTIC_ELLIPSOID: {
        /* rho = A + B cos v, h = C sin v. */
        double A = 0.0, B = s->r1, C = s->r1;
        if (s->kind == CB_ANALYTIC_TORUS) {
            A = s->r1;
            B = C = s->r2;
        } else if (s->kind == CB_ANALYTIC_ELLIPSOID) {
            B = 1.0;
            C = s->r3;
            q->sx = s->r1;
            q->sy = s->r2;
        }
        q->rho[0] = A + B * cv;
        q->rho[1] = -B * sv;
        q->rho[2] = -B * cv;
        q->h[0] = C * sv;
        q->h[1] = C * cv;
        q->h[2] = -C * sv;
        return;
    }
    }
}

void cb_analytic_eval(double p[3], const cb_analytic_surface *s, double u, double v)
{
    double l[3];
    if (s->kind == CB_ANALYTIC_PLANE) {
        l[0] = u;
        l[1] = v;
        l[2] = 0.0;
    } else {
        profile q;
        profile_at(&q, s, v);
        l[0] = q.sx * q.rho[0] * cos(u);
        l[1] = q.sy * q.rho[0] * sin(u);
        l[2] = q.h[0];
    }
    cb_frame_to_world(p, &s->frame, l);
}

void cb_analytic_eval_derivs(double d[6][3], const cb_analytic_surface *s, double u, double v)
{
    double l[6][3];
    memset(l, 0, sizeof l);
    if (s->kind == CB_ANALYTIC_PLANE) {
        l[0][0] = u;
        l[0][1] = v;
        l[1][0] = 1.0;
        l[2][1] = 1.0;
    } else {
        profile q;
        profile_at(&q, s, v);
        double cu = cos(u), su = sin(u);
        double ax = q.sx * cu, ay = q.sy * su;  /* the parallel circle at unit radius */
        double bx = -q.sx * su, by = q.sy * cu; /* its u derivative */
        l[0][0] = q.sx * q.rho[0] * cu;         /* as in cb_analytic_eval, for bitwise equality */
        l[0][1] = q.sy * q.rho[0] * su;
        l[0][2] = q.h[0];
        l[1][0] = q.rho[0] * bx;
        l[1][1] = q.rho[0] * by;
        l[2][0] = q.rho[1] * ax;
        l[2][1] = q.rho[1] * ay;
        l[2][2] = q.h[1];
        l[3][0] = -q.rho[0] * ax;
        l[3][1] = -q.rho[0] * ay;
        l[4][0] = q.rho[1] * bx;
        l[4][1] = q.rho[1] * by;
        l[5][0] = q.rho[2] * ax;
        l[5][1] = q.rho[2] * ay;
        l[5][2] = q.h[2];
    }
    cb_frame_to_world(d[0], &s->frame, l[0]);
    for (int k = 1; k < 6; k++)
        frame_combine(d[k], &s->frame, NULL, l[k]);
}

/* ---------------------------------------------------------------- trivariate polynomials --- */

void cb_poly3_init(cb_poly3_t p)
{
    p->deg = -1;
    p->c = NULL;
}

void cb_poly3_clear(cb_poly3_t p)
{
    free(p->c);
    cb_poly3_init(p);
}

void cb_poly3_swap(cb_poly3_t a, cb_poly3_t b)
{
    cb_poly3_struct t = *a;
    *a = *b;
    *b = t;
}

cb_status cb_poly3_alloc(cb_poly3_t p, int deg, cb_error *err)
{
    if (deg < 0 || deg > CB_POLY3_MAX_DEGREE)
        return cb_error_set(err, CB_ERR_INVALID, "polynomial degree %d out of range [0, %d]", deg,
                            CB_POLY3_MAX_DEGREE);
    double *c = calloc((size_t)cb_poly3_len(deg), sizeof *c);
    if (!c)
        return cb_error_set(err, CB_ERR_NOMEM, "no memory for a polynomial of degree %d", deg);
    free(p->c);
    p->deg = deg;
    p->c = c;
    return CB_OK;
}

cb_status cb_poly3_set(cb_poly3_t dst, const cb_poly3_t src, cb_error *err)
{
    if (dst == src)
        return CB_OK;
    if (src->deg < 0) {
        cb_poly3_clear(dst);
        return CB_OK;
    }
    cb_poly3_t t;
    cb_poly3_init(t);
    cb_status st = cb_poly3_alloc(t, src->deg, err);
    if (st)
        return st;
    memcpy(t->c, src->c, (size_t)cb_poly3_len(src->deg) * sizeof *t->c);
    cb_poly3_swap(dst, t);
    cb_poly3_clear(t);
    return CB_OK;
}

/* The loops below walk the layout in storage order: total degree t, then m = j + k, then k. */

double cb_poly3_eval(const cb_poly3_t p, const double x[3])
{
    double pw[3][CB_POLY3_MAX_DEGREE + 1];
    int d = p->deg;
    for (int a = 0; a < 3; a++) {
        pw[a][0] = 1.0;
        for (int e = 1; e <= d; e++)
            pw[a][e] = pw[a][e - 1] * x[a];
    }
    double f = 0.0;
    int idx = 0;
    for (int t = 0; t <= d; t++)
        for (int m = 0; m <= t; m++)
            for (int k = 0; k <= m; k++, idx++)
                f += p->c[idx] * pw[0][t - m] * pw[1][m - k] * pw[2][k];
    return f;
}

double cb_poly3_eval_grad(double grad[3], const cb_poly3_t p, const double x[3])
{
    double pw[3][CB_POLY3_MAX_DEGREE + 1];
    int d = p->deg;
    for (int a = 0; a < 3; a++) {
        pw[a][0] = 1.0;
        for (int e = 1; e <= d; e++)
            pw[a][e] = pw[a][e - 1] * x[a];
    }
    double f = 0.0, g[3] = {0.0, 0.0, 0.0};
    int idx = 0;
    for (int t = 0; t <= d; t++)
        for (int m = 0; m <= t; m++)
            for (int k = 0; k <= m; k++, idx++) {
                int i = t - m, j = m - k;
                double c = p->c[idx];
                f += c * pw[0][i] * pw[1][j] * pw[2][k];
                if (i)
                    g[0] += c * i * pw[0][i - 1] * pw[1][j] * pw[2][k];
                if (j)
                    g[1] += c * j * pw[0][i] * pw[1][j - 1] * pw[2][k];
                if (k)
                    g[2] += c * k * pw[0][i] * pw[1][j] * pw[2][k - 1];
            }
    memcpy(grad, g, sizeof g);
    return f;
}

cb_status cb_poly3_mul(cb_poly3_t out, const cb_poly3_t a, const cb_poly3_t b, cb_error *err)
{
    if (a->deg < 0 || b->deg < 0) {
        cb_poly3_clear(out);
        return CB_OK;
    }
    cb_poly3_t r;
    cb_poly3_init(r);
    cb_status st = cb_poly3_alloc(r, a->deg + b->deg, err);
    if (st)
        return st;
    int ia = 0;
    for (int ta = 0; ta <= a->deg; ta++)
        for (int ma = 0; ma <= ta; ma++)
            for (int ka = 0; ka <= ma; ka++, ia++) {
                double ca = a->c[ia];
                if (ca == 0.0)
                    continue;
                int ib = 0;
                for (int tb = 0; tb <= b->deg; tb++)
                    for (int mb = 0; mb <= tb; mb++)
                        for (int kb = 0; kb <= mb; kb++, ib++)
                            r->c[cb_poly3_index(ta - ma + tb - mb, ma - ka + mb - kb, ka + kb)] +=
                                ca * b->c[ib];
            }
    cb_poly3_swap(out, r);
    cb_poly3_clear(r);
    return CB_OK;
}

cb_status cb_poly3_compose_affine(cb_poly3_t out, const cb_poly3_t p, const double m[3][3],
                                  const double t[3], cb_error *err)
{
    int d = p->deg;
    if (d < 0) {
        cb_poly3_clear(out);
        return CB_OK;
    }
    /* pw[a * (d + 1) + e] = (m[a] . x + t[a])^e at storage degree e. */
    int npw = 3 * (d + 1);
    cb_poly3_struct *pw = malloc((size_t)npw * sizeof *pw);
    if (!pw)
        return cb_error_set(err, CB_ERR_NOMEM, "no memory to compose a polynomial");
    for (int q = 0; q < npw; q++)
        cb_poly3_init(&pw[q]);
    cb_poly3_t r, xy, term;
    cb_poly3_init(r);
    cb_poly3_init(xy);
    cb_poly3_init(term);
    cb_status st = cb_poly3_alloc(r, d, err);
    for (int a = 0; a < 3 && !st; a++) {
        cb_poly3_struct *row = pw + a * (d + 1);
        st = cb_poly3_alloc(&row[0], 0, err);
        if (st)
            break;
        row[0].c[0] = 1.0;
        if (d >= 1 && !(st = cb_poly3_alloc(&row[1], 1, err))) {
            row[1].c[0] = t[a];
            row[1].c[cb_poly3_index(1, 0, 0)] = m[a][0];
            row[1].c[cb_poly3_index(0, 1, 0)] = m[a][1];
            row[1].c[cb_poly3_index(0, 0, 1)] = m[a][2];
        }
        for (int e = 2; e <= d && !st; e++)
            st = cb_poly3_mul(&row[e], &row[e - 1], &row[1], err);
    }
    int idx = 0;
    for (int tt = 0; tt <= d && !st; tt++)
        for (int mm = 0; mm <= tt && !st; mm++)
            for (int k = 0; k <= mm && !st; k++, idx++) {
                double c = p->c[idx];
                if (c == 0.0)
                    continue;
                int i = tt - mm, j = mm - k;
                st = cb_poly3_mul(xy, &pw[i], &pw[(d + 1) + j], err);
                if (!st)
                    st = cb_poly3_mul(term, xy, &pw[2 * (d + 1) + k], err);
                /* term has storage degree tt <= d: by the graded layout it is a prefix of r. */
                for (int q = 0; !st && q < cb_poly3_len(tt); q++)
                    r->c[q] += c * term->c[q];
            }
    if (!st)
        cb_poly3_swap(out, r);
    cb_poly3_clear(r);
    cb_poly3_clear(xy);
    cb_poly3_clear(term);
    for (int q = 0; q < npw; q++)
        cb_poly3_clear(&pw[q]);
    free(pw);
    return st;
}

/* ---------------------------------------------------------------- implicit equations ------- */

/* The local-frame equation of s with the normalisation documented in analytic.h. */
static cb_status local_implicit(cb_poly3_t g, const cb_analytic_surface *s, cb_error *err)
{
    const int X2 = cb_poly3_index(2, 0, 0), Y2 = cb_poly3_index(0, 2, 0),
              Z2 = cb_poly3_index(0, 0, 2), Z1 = cb_poly3_index(0, 0, 1);
    cb_status st;
    switch (s->kind) {
    case CB_ANALYTIC_PLANE:
        if ((st = cb_poly3_alloc(g, 1, err)))
            return st;
        g->c[Z1] = 1.0;
        return CB_OK;
    case CB_ANALYTIC_CYLINDER:
    case CB_ANALYTIC_SPHERE: {
        if ((st = cb_poly3_alloc(g, 2, err)))
            return st;
        double r = s->r1, k = 1.0 / (2.0 * r);
        g->c[X2] = g->c[Y2] = k;
        g->c[Z2] = s->kind == CB_ANALYTIC_SPHERE ? k : 0.0;
        g->c[0] = -0.5 * r;
        return CB_OK;
    }
    case CB_ANALYTIC_ELLIPSOID: {
        if ((st = cb_poly3_alloc(g, 2, err)))
            return st;
        double a = s->r1, b = s->r2, c = s->r3;
        double h = 0.5 * fmin(a, fmin(b, c));
        g->c[X2] = h / (a * a);
        g->c[Y2] = h / (b * b);
        g->c[Z2] = h / (c * c);
        g->c[0] = -h;
        return CB_OK;
    }
    case CB_ANALYTIC_CONE: {
        /* (cos a / 2)(x^2 + y^2 - (r + z tan a)^2), expanded. */
        if ((st = cb_poly3_alloc(g, 2, err)))
            return st;
        double r = s->r1, ta = tan(s->angle), h = 0.5 * cos(s->angle);
        g->c[X2] = g->c[Y2] = h;
        g->c[Z2] = -h * ta * ta;
        g->c[Z1] = -2.0 * h * r * ta;
        g->c[0] = -h * r * r;
        return CB_OK;
    }
    case CB_ANALYTIC_TORUS: {
        double R = s->r1, r = s->r2;
        cb_poly3_t q;
        cb_poly3_init(q);
        if ((st = cb_poly3_alloc(q, 2, err)))
            return st;
        q->c[X2] = q->c[Y2] = q->c[Z2] = 1.0;
        q->c[0] = (R - r) * (R + r);
        st = cb_poly3_mul(g, q, q, err);
        cb_poly3_clear(q);
        if (st)
            return st;
        g->c[X2] -= 4.0 * R * R;
        g->c[Y2] -= 4.0 * R * R;
        double k = 1.0 / (8.0 * R * r);
        for (int i = 0; i < cb_poly3_len(g->deg); i++)
            g->c[i] *= k;
        return CB_OK;
    }
    }
    return cb_error_set(err, CB_ERR_INVALID, "analytic surface of unknown kind %d", (int)s->kind);
}

cb_status cb_analytic_implicit_about(cb_poly3_t F, const cb_analytic_surface *s,
                                     const double center[3], cb_error *err)
{
    if (!finite3(center))
        return cb_error_set(err, CB_ERR_INVALID, "implicit equation: center is not finite");
    cb_poly3_t g;
    cb_poly3_init(g);
    cb_status st = local_implicit(g, s, err);
    if (!st) {
        /* Local coordinates x' = M q + t with the frame axes as the rows of M and
         * t = -M (o - center), so that q = p - center. */
        const cb_frame *f = &s->frame;
        double m[3][3], t[3], d[3];
        for (int i = 0; i < 3; i++) {
            m[0][i] = f->x[i];
            m[1][i] = f->y[i];
            m[2][i] = f->z[i];
            d[i] = f->o[i] - center[i];
        }
        for (int a = 0; a < 3; a++)
            t[a] = -cb_vec3_dot(m[a], d);
        st = cb_poly3_compose_affine(F, g, m, t, err);
    }
    cb_poly3_clear(g);
    return st;
}

cb_status cb_analytic_implicit(cb_poly3_t F, const cb_analytic_surface *s, cb_error *err)
{
    const double origin[3] = {0.0, 0.0, 0.0};
    return cb_analytic_implicit_about(F, s, origin, err);
}
