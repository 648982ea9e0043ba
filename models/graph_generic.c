/* graph_generic.c — the SSI corpus's graph cases (cb_graph_case_make, models.h): two whole
 * B-spline surfaces, the graphs of f and f + h over the design square, whose intersection is
 * the designed curve h = 0, in an exact pose (cb_model_graph_pair) and in generic ones (random
 * knots, degrees, parametrisations and rigid motion). Every case is a function of (class, pose,
 * index) alone. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "models/models.h"

#define DEG CB_MODEL_POLY_DEG
#define PI 3.14159265358979323846

/* ---------------------------------------------------------------- names -------------------- */

static const char *const CLASS_NAME[CB_GRAPH_CLASS_COUNT] = {
    "loop",           "two_loops",        "close_loops",     "crossing_loops",
    "node",           "cusp",             "contact_branches", "boundary",
    "tangent_sides",  "loops_touching",   "tangential_loop", "tangential_line",
    "contacts",       "small_loop",       "multi"};
static const char *const CLASS_FIG[CB_GRAPH_CLASS_COUNT] = {
    "-", "-", "-", "1a", "1a", "-", "1b", "1c", "1d", "1e", "1f", "1f", "1g", "-", "-"};
static const char *const POSE_NAME[CB_GRAPH_POSE_COUNT] = {"exact", "param", "generic"};

const char *cb_graph_class_name(int cls)
{
    return cls >= 0 && cls < CB_GRAPH_CLASS_COUNT ? CLASS_NAME[cls] : "?";
}

const char *cb_graph_class_fig(int cls)
{
    return cls >= 0 && cls < CB_GRAPH_CLASS_COUNT ? CLASS_FIG[cls] : "?";
}

const char *cb_graph_pose_name(int pose)
{
    return pose >= 0 && pose < CB_GRAPH_POSE_COUNT ? POSE_NAME[pose] : "?";
}

/* ---------------------------------------------------------------- random numbers ----------- */

typedef struct {
    uint64_t s;
} rng_t;

/* splitmix64: the same sequence on every machine. */
static uint64_t rng_next(rng_t *r)
{
    uint64_t z = (r->s += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

static double uniform(rng_t *r, double lo, double hi)
{
    return lo + (hi - lo) * ((double)(rng_next(r) >> 11) * 0x1.0p-53);
}

static int rand_int(rng_t *r, int lo, int hi)
{
    return lo + (int)(rng_next(r) % (uint64_t)(hi - lo + 1));
}

/* Standard normal (Box-Muller). */
static double normal(rng_t *r)
{
    double a = uniform(r, 1e-300, 1), b = uniform(r, 0, 2 * PI);
    return sqrt(-2 * log(a)) * cos(b);
}

/* ---------------------------------------------------------------- polynomials in x, y ------ */

typedef struct {
    double c[DEG + 1][DEG + 1]; /* sum c[i][j] x^i y^j */
    int overflow;               /* a term above DEG was dropped */
} dpoly;

static dpoly dp_lin(double a, double b, double c)
{
    dpoly p;
    memset(&p, 0, sizeof p);
    p.c[1][0] = a;
    p.c[0][1] = b;
    p.c[0][0] = c;
    return p;
}

static dpoly dp_mul(dpoly a, dpoly b)
{
    dpoly p;
    memset(&p, 0, sizeof p);
    p.overflow = a.overflow || b.overflow;
    for (int i = 0; i <= DEG; i++)
        for (int j = 0; j <= DEG; j++)
            if (a.c[i][j] != 0)
                for (int k = 0; k <= DEG; k++)
                    for (int l = 0; l <= DEG; l++)
                        if (b.c[k][l] != 0) {
                            if (i + k > DEG || j + l > DEG)
                                p.overflow = 1;
                            else
                                p.c[i + k][j + l] += a.c[i][j] * b.c[k][l];
                        }
    return p;
}

/* a + k b */
static dpoly dp_add(dpoly a, dpoly b, double k)
{
    for (int i = 0; i <= DEG; i++)
        for (int j = 0; j <= DEG; j++)
            a.c[i][j] += k * b.c[i][j];
    a.overflow |= b.overflow;
    return a;
}

static double dp_eval(const double c[DEG + 1][DEG + 1], double x, double y)
{
    double s = 0;
    for (int i = DEG; i >= 0; i--) {
        double r = 0;
        for (int j = DEG; j >= 0; j--)
            r = r * y + c[i][j];
        s = s * x + r;
    }
    return s;
}

static void dp_degrees(int *dx, int *dy, const dpoly *p)
{
    *dx = *dy = 0;
    for (int i = 0; i <= DEG; i++)
        for (int j = 0; j <= DEG; j++)
            if (p->c[i][j] != 0) {
                *dx = i > *dx ? i : *dx;
                *dy = j > *dy ? j : *dy;
            }
}

/* The factors of the designs, scaled by den so that in the exact pose (parameters on the grid
 * 1/den) every coefficient is an integer:
 *   circle: (den x - den cx)^2 + (den y - den cy)^2 - den^2 rr (rr = r^2; 0: a point);
 *   line:   nx den (x - px) + ny den (y - py);
 *   cusp:   den (den y')^2 - k (den x')^3, (x', y') = the frame at p turned by (c, s). */
static dpoly f_circle(double den, double cx, double cy, double rr)
{
    dpoly x = dp_lin(den, 0, -den * cx), y = dp_lin(0, den, -den * cy), one = dp_lin(0, 0, 1);
    return dp_add(dp_add(dp_mul(x, x), dp_mul(y, y), 1), one, -den * den * rr);
}

static dpoly f_line(double den, double px, double py, double nx, double ny)
{
    return dp_lin(nx * den, ny * den, -den * (nx * px + ny * py));
}

static dpoly f_cusp(double den, double px, double py, double c, double s, double k)
{
    dpoly xp = f_line(den, px, py, c, s), yp = f_line(den, px, py, -s, c);
    dpoly y2 = dp_mul(yp, yp), x3 = dp_mul(dp_mul(xp, xp), xp);
    return dp_add(dp_add(dp_lin(0, 0, 0), y2, den), x3, -k);
}

/* ---------------------------------------------------------------- designs ------------------ */

/* A design under construction: h (integer coefficients in the exact pose), the truth. */
typedef struct {
    dpoly h;
    int exact;
    double den; /* grid of the exact pose's parameters */
    int same_rect; /* Q must span exactly P's square (boundary classes) */
    cb_graph_case *c;
} design;

/* A parameter in [lo, hi]: on the grid 1/den in the exact pose, uniform otherwise. */
static double pick(rng_t *r, const design *d, double lo, double hi)
{
    if (!d->exact)
        return uniform(r, lo, hi);
    int a = (int)ceil(lo * d->den), b = (int)floor(hi * d->den);
    if (b < a)
        b = a;
    return rand_int(r, a, b) / d->den;
}

/* A direction: any angle, or in the exact pose one of the four axis directions. */
static double pick_angle(rng_t *r, const design *d)
{
    return d->exact ? rand_int(r, 0, 3) * (PI / 2) : uniform(r, 0, 2 * PI);
}

/* cos and sin, exact for the axis angles of the exact pose. */
static void cos_sin(double *c, double *s, double th, const design *d)
{
    if (d->exact) {
        int q = (int)lround(th / (PI / 2)) & 3;
        static const int C[4] = {1, 0, -1, 0}, S[4] = {0, 1, 0, -1};
        *c = C[q];
        *s = S[q];
    } else {
        *c = cos(th);
        *s = sin(th);
    }
}

static void add_prim(design *d, cb_graph_prim_kind kind, double a0, double a1, double a2,
                     double a3, int tangential)
{
    cb_graph_case *c = d->c;
    if (c->n_prims >= CB_GRAPH_MAX_PRIMS)
        return;
    cb_graph_prim *p = c->prim + c->n_prims++;
    p->kind = kind;
    p->a[0] = a0;
    p->a[1] = a1;
    p->a[2] = a2;
    p->a[3] = a3;
    p->tangential = tangential;
}

static void add_singular(design *d, double x, double y)
{
    cb_graph_case *c = d->c;
    if (c->n_singular < CB_GRAPH_MAX_SINGULAR) {
        c->singular[c->n_singular][0] = x;
        c->singular[c->n_singular][1] = y;
        c->n_singular++;
    }
}

static void add_circle(design *d, dpoly *h, double cx, double cy, double r, int squared)
{
    dpoly g = f_circle(d->den, cx, cy, r * r);
    *h = dp_mul(*h, squared ? dp_mul(g, g) : g);
    add_prim(d, CB_GRAPH_CIRCLE, cx, cy, r, 0, squared);
}

/* The line through (px, py) with unit normal (nx, ny) (integers in the exact pose). */
static void add_line(design *d, dpoly *h, double px, double py, double nx, double ny,
                     int squared)
{
    dpoly g = f_line(d->den, px, py, nx, ny);
    *h = dp_mul(*h, squared ? dp_mul(g, g) : g);
    add_prim(d, CB_GRAPH_LINE, px, py, atan2(nx, -ny), 0, squared);
}

static void add_point(design *d, dpoly *h, double px, double py)
{
    *h = dp_mul(*h, f_circle(d->den, px, py, 0));
    add_prim(d, CB_GRAPH_POINT, px, py, 0, 0, 1);
}

/* The two crossing points of two circles that cross. */
static void circle_nodes(design *d, double x1, double y1, double r1, double x2, double y2,
                         double r2)
{
    double dx = x2 - x1, dy = y2 - y1, D = hypot(dx, dy);
    double a = (r1 * r1 - r2 * r2 + D * D) / (2 * D), b = sqrt(fmax(r1 * r1 - a * a, 0));
    double mx = x1 + a * dx / D, my = y1 + a * dy / D;
    add_singular(d, mx - b * dy / D, my + b * dx / D);
    add_singular(d, mx + b * dy / D, my - b * dx / D);
}

static void design_class(design *d, rng_t *r, int cls)
{
    cb_graph_case *c = d->c;
    dpoly h = dp_lin(0, 0, 1);
    double th, co, si;
    switch (cls) {
    case CB_GRAPH_CLASS_LOOP:
        add_circle(d, &h, pick(r, d, 0.35, 0.65), pick(r, d, 0.35, 0.65), pick(r, d, 0.15, 0.28),
                   0);
        c->closed = 1;
        snprintf(c->truth, sizeof c->truth, "1 loop");
        break;
    case CB_GRAPH_CLASS_TWO_LOOPS: {
        th = pick_angle(r, d);
        cos_sin(&co, &si, th, d);
        double e = pick(r, d, 0.19, 0.26), r1 = pick(r, d, 0.08, 0.17),
               r2 = pick(r, d, 0.08, 0.17);
        add_circle(d, &h, 0.5 - e * co, 0.5 - e * si, r1, 0);
        add_circle(d, &h, 0.5 + e * co, 0.5 + e * si, r2, 0);
        c->closed = 2;
        snprintf(c->truth, sizeof c->truth, "2 loops");
        break;
    }
    case CB_GRAPH_CLASS_CLOSE_LOOPS: {
        th = pick_angle(r, d);
        cos_sin(&co, &si, th, d);
        double px = pick(r, d, 0.45, 0.55), py = pick(r, d, 0.45, 0.55);
        double r1 = pick(r, d, 0.12, 0.2), r2 = pick(r, d, 0.12, 0.2),
               gap = pick(r, d, 0.01, 0.035);
        /* p is the point of the first loop nearest the second. */
        add_circle(d, &h, px - r1 * co, py - r1 * si, r1, 0);
        add_circle(d, &h, px + (gap + r2) * co, py + (gap + r2) * si, r2, 0);
        c->closed = 2;
        snprintf(c->truth, sizeof c->truth, "2 loops, gap %.3f", gap);
        break;
    }
    case CB_GRAPH_CLASS_CROSSING_LOOPS: {
        th = pick_angle(r, d);
        cos_sin(&co, &si, th, d);
        double px = pick(r, d, 0.47, 0.53), py = pick(r, d, 0.47, 0.53);
        double half = pick(r, d, 0.06, 0.11), r1 = pick(r, d, 0.2, 0.28),
               r2 = pick(r, d, 0.2, 0.28);
        double x1 = px - half * co, y1 = py - half * si, x2 = px + half * co, y2 = py + half * si;
        add_circle(d, &h, x1, y1, r1, 0);
        add_circle(d, &h, x2, y2, r2, 0);
        circle_nodes(d, x1, y1, r1, x2, y2, r2);
        c->closed = 1;
        snprintf(c->truth, sizeof c->truth, "2 loops crossing at 2 nodes");
        break;
    }
    case CB_GRAPH_CLASS_NODE: {
        double px = pick(r, d, 0.4, 0.6), py = pick(r, d, 0.4, 0.6);
        if (d->exact) {
            static const int N[4][4] = {{1, 0, 0, 1}, {1, 1, 1, -1}, {1, 0, 1, 1}, {0, 1, 1, -1}};
            const int *n = N[rand_int(r, 0, 3)];
            add_line(d, &h, px, py, n[0], n[1], 0);
            add_line(d, &h, px, py, n[2], n[3], 0);
        } else {
            double t1 = uniform(r, 0, PI), t2 = t1 + uniform(r, 0.5, PI - 0.5);
            add_line(d, &h, px, py, cos(t1), sin(t1), 0);
            add_line(d, &h, px, py, cos(t2), sin(t2), 0);
        }
        add_singular(d, px, py);
        c->open = 1;
        snprintf(c->truth, sizeof c->truth, "2 lines, 1 node");
        break;
    }
    case CB_GRAPH_CLASS_CUSP: {
        th = pick_angle(r, d);
        cos_sin(&co, &si, th, d);
        /* The cusp opens along (co, si) from a point set back from the centre. */
        double back = pick(r, d, 0.12, 0.22);
        double px = 0.5 - back * co + (d->exact ? 0 : uniform(r, -0.04, 0.04));
        double py = 0.5 - back * si + (d->exact ? 0 : uniform(r, -0.04, 0.04));
        double k = d->exact ? rand_int(r, 1, 3) : uniform(r, 1, 4);
        h = f_cusp(d->den, px, py, co, si, k);
        add_prim(d, CB_GRAPH_CUSP, px, py, atan2(si, co), k, 0);
        add_singular(d, px, py);
        c->open = 1;
        snprintf(c->truth, sizeof c->truth, "1 branch with a cusp");
        break;
    }
    case CB_GRAPH_CLASS_CONTACT_BRANCHES: {
        th = pick_angle(r, d);
        cos_sin(&co, &si, th, d);
        double px = pick(r, d, 0.4, 0.6), py = pick(r, d, 0.4, 0.6);
        double d1 = pick(r, d, 0.15, 0.3), d2 = pick(r, d, 0.15, 0.3);
        /* Two branches parallel to (co, si), one on each side of the contact. */
        add_point(d, &h, px, py);
        add_line(d, &h, px + d1 * si, py - d1 * co, -si, co, 0);
        add_line(d, &h, px - d2 * si, py + d2 * co, -si, co, 0);
        c->open = 2;
        c->points = 1;
        snprintf(c->truth, sizeof c->truth, "2 branches + 1 contact point");
        break;
    }
    case CB_GRAPH_CLASS_BOUNDARY: {
        int k = rand_int(r, 0, 3);
        double cx = k & 1, cy = k >> 1, rad = pick(r, d, 0.4, 0.7);
        add_line(d, &h, cx, cy, 1, 0, 0);
        add_line(d, &h, cx, cy, 0, 1, 0);
        add_circle(d, &h, cx, cy, rad, 0);
        add_singular(d, cx, cy);
        add_singular(d, cx + (cx ? -rad : rad), cy);
        add_singular(d, cx, cy + (cy ? -rad : rad));
        d->same_rect = 1;
        c->open = 1;
        snprintf(c->truth, sizeof c->truth, "2 sides + 1 arc");
        break;
    }
    case CB_GRAPH_CLASS_TANGENT_SIDES: {
        double a = pick(r, d, 0.35, 0.65);
        double tilt = d->exact ? 0 : uniform(r, -0.3, 0.3);
        add_line(d, &h, 0, 0, 1, 0, 0);
        add_line(d, &h, 1, 1, 1, 0, 0);
        add_line(d, &h, 0, 0, 0, 1, 0);
        add_line(d, &h, 1, 1, 0, 1, 0);
        /* The tangential line through (a, 1/2), turned by tilt from the vertical. */
        add_line(d, &h, a, 0.5, d->exact ? 1 : cos(tilt), d->exact ? 0 : sin(tilt), 1);
        if (rng_next(r) & 1)
            h = dp_add(dp_lin(0, 0, 0), h, -1);
        for (int k = 0; k < 4; k++)
            add_singular(d, k & 1, k >> 1);
        add_singular(d, a + 0.5 * tan(tilt), 0);
        add_singular(d, a - 0.5 * tan(tilt), 1);
        d->same_rect = 1;
        c->open = 1;
        snprintf(c->truth, sizeof c->truth, "4 sides + 1 tangential line");
        break;
    }
    case CB_GRAPH_CLASS_LOOPS_TOUCHING: {
        th = pick_angle(r, d);
        cos_sin(&co, &si, th, d);
        double qx = pick(r, d, 0.45, 0.55), qy = pick(r, d, 0.45, 0.55);
        double r1 = pick(r, d, 0.12, 0.2), r2 = pick(r, d, 0.12, 0.2);
        add_circle(d, &h, qx - r1 * co, qy - r1 * si, r1, 0);
        add_circle(d, &h, qx + r2 * co, qy + r2 * si, r2, 0);
        add_singular(d, qx, qy);
        c->closed = 1;
        snprintf(c->truth, sizeof c->truth, "2 loops touching at 1 point");
        break;
    }
    case CB_GRAPH_CLASS_TANGENTIAL_LOOP:
        add_circle(d, &h, pick(r, d, 0.35, 0.65), pick(r, d, 0.35, 0.65), pick(r, d, 0.15, 0.28),
                   1);
        if (rng_next(r) & 1)
            h = dp_add(dp_lin(0, 0, 0), h, -1);
        c->closed = 1;
        snprintf(c->truth, sizeof c->truth, "1 tangential loop");
        break;
    case CB_GRAPH_CLASS_TANGENTIAL_LINE: {
        double px = pick(r, d, 0.35, 0.65), py = pick(r, d, 0.35, 0.65);
        if (d->exact) {
            static const int N[4][2] = {{1, 0}, {0, 1}, {1, 1}, {1, -1}};
            const int *n = N[rand_int(r, 0, 3)];
            add_line(d, &h, px, py, n[0], n[1], 1);
        } else {
            th = uniform(r, 0, PI);
            add_line(d, &h, px, py, cos(th), sin(th), 1);
        }
        if (rng_next(r) & 1)
            h = dp_add(dp_lin(0, 0, 0), h, -1);
        c->open = 1;
        snprintf(c->truth, sizeof c->truth, "1 tangential line");
        break;
    }
    case CB_GRAPH_CLASS_CONTACTS: {
        int n = rand_int(r, 2, 3);
        if (d->exact) {
            static const int G[4][2] = {{8, 8}, {16, 24}, {24, 12}, {10, 20}};
            int skip = rand_int(r, 0, 3);
            for (int k = 0, m = 0; k < 4 && m < n; k++)
                if (k != skip || n == 4) {
                    add_point(d, &h, G[k][0] / 32.0, G[k][1] / 32.0);
                    m++;
                }
        } else {
            double ph = uniform(r, 0, 2 * PI), rad = uniform(r, 0.2, 0.3);
            for (int k = 0; k < n; k++) {
                double a = ph + 2 * PI * k / n + uniform(r, -0.3, 0.3);
                add_point(d, &h, 0.5 + rad * cos(a), 0.5 + rad * sin(a));
            }
        }
        c->points = n;
        snprintf(c->truth, sizeof c->truth, "%d contact points", n);
        break;
    }
    case CB_GRAPH_CLASS_SMALL_LOOP:
        if (d->exact) {
            /* (1024 x - a)^2 + (1024 y - b)^2 - r2: radius sqrt(r2) / 1024. */
            static const int R2[4] = {1, 2, 4, 9};
            double den = d->den;
            d->den = 1024;
            add_circle(d, &h, rand_int(r, 400, 620) / 1024.0, rand_int(r, 400, 620) / 1024.0,
                       sqrt(R2[rand_int(r, 0, 3)]) / 1024, 0);
            /* rr = r^2 rounded: recompute the factor from the integer r2. */
            cb_graph_prim *p = c->prim + c->n_prims - 1;
            double r2 = round(p->a[2] * p->a[2] * 1024 * 1024);
            h = f_circle(1024, p->a[0], p->a[1], r2 / (1024.0 * 1024.0));
            d->den = den;
        } else {
            add_circle(d, &h, uniform(r, 0.3, 0.7), uniform(r, 0.3, 0.7), uniform(r, 1e-3, 4e-3),
                       0);
        }
        c->closed = 1;
        snprintf(c->truth, sizeof c->truth, "1 loop, radius %.1e", c->prim[0].a[2]);
        break;
    case CB_GRAPH_CLASS_MULTI: {
        th = pick_angle(r, d);
        cos_sin(&co, &si, th, d);
        double j[6] = {0};
        if (!d->exact)
            for (int k = 0; k < 6; k++)
                j[k] = uniform(r, -0.02, 0.02);
        /* In the frame turned by th about the centre: a loop at (-7, 3) / 32, a branch
         * x' = 7 / 32, a contact at (-3, -10) / 32. */
        double lx = -7 / 32.0 + j[0], ly = 3 / 32.0 + j[1], bx = 7 / 32.0 + j[2],
               cx = -3 / 32.0 + j[3], cy = -10 / 32.0 + j[4];
        double rad = d->exact ? 4 / 32.0 : 0.125 + j[5];
        add_circle(d, &h, 0.5 + co * lx - si * ly, 0.5 + si * lx + co * ly, rad, 0);
        add_line(d, &h, 0.5 + co * bx, 0.5 + si * bx, co, si, 0);
        add_point(d, &h, 0.5 + co * cx - si * cy, 0.5 + si * cx + co * cy);
        c->closed = 1;
        c->open = 1;
        c->points = 1;
        snprintf(c->truth, sizeof c->truth, "1 loop + 1 branch + 1 contact point");
        break;
    }
    default:
        break;
    }
    d->h = h;
}

/* ---------------------------------------------------------------- prims -------------------- */

void cb_graph_prim_point(double xy[2], const cb_graph_prim *p, double s)
{
    switch (p->kind) {
    case CB_GRAPH_CIRCLE:
        xy[0] = p->a[0] + p->a[2] * cos(s);
        xy[1] = p->a[1] + p->a[2] * sin(s);
        break;
    case CB_GRAPH_LINE:
        xy[0] = p->a[0] + s * cos(p->a[2]);
        xy[1] = p->a[1] + s * sin(p->a[2]);
        break;
    case CB_GRAPH_CUSP: {
        double xp = s * s, yp = sqrt(p->a[3]) * s * s * s, c = cos(p->a[2]), sn = sin(p->a[2]);
        xy[0] = p->a[0] + xp * c - yp * sn;
        xy[1] = p->a[1] + xp * sn + yp * c;
        break;
    }
    default:
        xy[0] = p->a[0];
        xy[1] = p->a[1];
        break;
    }
}

void cb_graph_prim_range(double *s0, double *s1, const cb_graph_prim *p)
{
    switch (p->kind) {
    case CB_GRAPH_CIRCLE:
        *s0 = 0;
        *s1 = 2 * PI;
        break;
    case CB_GRAPH_LINE:
        *s0 = -1.5;
        *s1 = 1.5;
        break;
    case CB_GRAPH_CUSP:
        *s0 = -1.25;
        *s1 = 1.25;
        break;
    default:
        *s0 = *s1 = 0;
        break;
    }
}

/* ---------------------------------------------------------------- the case ---------------- */

void cb_graph_case_init(cb_graph_case *c)
{
    memset(c, 0, sizeof *c);
    cb_nurbs_surface_init(c->P);
    cb_nurbs_surface_init(c->Q);
    cb_nurbs_surface_init(c->F);
}

void cb_graph_case_clear(cb_graph_case *c)
{
    cb_nurbs_surface_clear(c->P);
    cb_nurbs_surface_clear(c->Q);
    cb_nurbs_surface_clear(c->F);
    cb_graph_case_init(c);
}

static void to_world(double X[3], const cb_graph_case *c, const double p[3])
{
    double q[3] = {c->L[0] * p[0], c->L[1] * p[1], c->L[2] * p[2]};
    for (int i = 0; i < 3; i++)
        X[i] = c->R[i][0] * q[0] + c->R[i][1] * q[1] + c->R[i][2] * q[2] + c->T[i];
}

void cb_graph_case_design(double p[3], const cb_graph_case *c, const double X[3])
{
    double d[3] = {X[0] - c->T[0], X[1] - c->T[1], X[2] - c->T[2]};
    for (int i = 0; i < 3; i++)
        p[i] = (c->R[0][i] * d[0] + c->R[1][i] * d[1] + c->R[2][i] * d[2]) / c->L[i];
}

/* f at (x, y) clamped to the square (F's parameters are the design coordinates). */
static double height(const cb_graph_case *c, double x, double y)
{
    double F[3];
    x = fmin(fmax(x, 0), 1);
    y = fmin(fmax(y, 0), 1);
    cb_nurbs_surface_eval(F, c->F, x, y);
    return F[2];
}

void cb_graph_case_lift(double X[3], const cb_graph_case *c, double x, double y)
{
    double p[3] = {x, y, height(c, x, y)};
    to_world(X, c, p);
}

void cb_graph_case_residual(double *dp, double *dq, const cb_graph_case *c, const double X[3])
{
    double p[3];
    cb_graph_case_design(p, c, X);
    double x = fmin(fmax(p[0], 0), 1), y = fmin(fmax(p[1], 0), 1), f = height(c, x, y);
    *dp = fabs(p[2] - f) * c->L[2];
    *dq = fabs(p[2] - f - dp_eval(c->h, x, y)) * c->L[2];
}

/* Moves every control point of s into the world. */
static void move_surface(cb_nurbs_surface_t s, const cb_graph_case *c)
{
    for (long k = 0; k < (long)s->n_u * s->n_v; k++) {
        double *w = s->cw + 4 * k, p[3] = {w[0] / w[3], w[1] / w[3], w[2] / w[3]}, X[3];
        to_world(X, c, p);
        for (int i = 0; i < 3; i++)
            w[i] = X[i] * w[3];
    }
}

static void net_size(cb_graph_case *c)
{
    double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    const cb_nurbs_surface_struct *s[2] = {c->P, c->Q};
    for (int m = 0; m < 2; m++)
        for (long k = 0; k < (long)s[m]->n_u * s[m]->n_v; k++)
            for (int i = 0; i < 3; i++) {
                double v = s[m]->cw[4 * k + i] / s[m]->cw[4 * k + 3];
                lo[i] = fmin(lo[i], v);
                hi[i] = fmax(hi[i], v);
            }
    c->size = sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                   (hi[2] - lo[2]) * (hi[2] - lo[2]));
}

/* ---------------------------------------------------------------- exact pose --------------- */

static cb_status make_exact(cb_graph_case *c, const design *d, cb_error *err)
{
    cb_model_poly hp;
    memset(&hp, 0, sizeof hp);
    hp.overflow = d->h.overflow;
    for (int i = 0; i <= DEG; i++)
        for (int j = 0; j <= DEG; j++) {
            double v = d->h.c[i][j];
            if (v != floor(v) || fabs(v) >= 0x1p62)
                return cb_error_set(err, CB_ERR_INVALID,
                                    "graph case %s: h's coefficient of x^%d y^%d (%g) is not a "
                                    "64-bit integer", c->id, i, j, v);
            hp.c[i][j] = (long long)v;
        }
    cb_model_graph g;
    cb_status st = cb_model_graph_pair(c->P, c->Q, &g, &hp, err);
    if (st)
        return cb_error_prefix(err, "graph case %s: ", c->id);
    /* cb_model_graph_pair (models.h): P(u, v) is the graph of S f over (x, y) = (u, v), moved by
     * (x, y, z) -> (z, x, y) and a translation; f(1/2, 1/2) = 0 gives the translation. */
    double S = g.scale, X[3];
    static const double R[3][3] = {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}};
    memcpy(c->R, R, sizeof R);
    c->L[0] = c->L[1] = c->L[2] = S;
    cb_model_graph_point(X, &g, 0.5, 0.5);
    c->T[0] = X[0];
    c->T[1] = X[1] - S / 2;
    c->T[2] = X[2] - S / 2;
    for (int i = 0; i <= DEG; i++)
        for (int j = 0; j <= DEG; j++)
            c->h[i][j] = ldexp(d->h.c[i][j], -g.height_shift);
    /* F: P brought back into the design space (its parameters are already x and y). */
    if ((st = cb_nurbs_surface_set(c->F, c->P, err)))
        return st;
    for (long k = 0; k < (long)c->F->n_u * c->F->n_v; k++) {
        double *w = c->F->cw + 4 * k, p[3];
        cb_graph_case_design(p, c, w);
        memcpy(w, p, sizeof p);
    }
    return CB_OK;
}

/* ---------------------------------------------------------------- generic poses ------------ */

/* n sorted random knots in (a, b), at least gap apart and from the ends. */
static int random_knots(double *k, rng_t *r, int n, double a, double b, double gap)
{
    for (int tries = 0; tries < 100; tries++) {
        for (int i = 0; i < n; i++)
            k[i] = uniform(r, a + gap, b - gap);
        for (int i = 1; i < n; i++)
            for (int j = i; j > 0 && k[j] < k[j - 1]; j--) {
                double t = k[j];
                k[j] = k[j - 1];
                k[j - 1] = t;
            }
        int ok = 1;
        for (int i = 1; i < n; i++)
            ok &= k[i] - k[i - 1] >= gap;
        if (ok)
            return n;
    }
    return 0;
}

/* Clamped knot vector of degree p on [a, b] with the n interior knots ki. */
static int knot_vector(double *out, int p, double a, double b, const double *ki, int n)
{
    int m = 0;
    for (int i = 0; i <= p; i++)
        out[m++] = a;
    for (int i = 0; i < n; i++)
        out[m++] = ki[i];
    for (int i = 0; i <= p; i++)
        out[m++] = b;
    return m;
}

static double greville(const double *knots, int i, int p)
{
    double s = 0;
    for (int k = 1; k <= p; k++)
        s += knots[i + k];
    return s / p;
}

/* The interior knots of s along dir (with multiplicity); returns their number. */
static int interior_knots(double *out, const cb_nurbs_surface_t s, cb_dir dir)
{
    int p = dir == CB_DIR_U ? s->deg_u : s->deg_v, n = dir == CB_DIR_U ? s->n_u : s->n_v;
    const double *k = dir == CB_DIR_U ? s->knots_u : s->knots_v;
    for (int i = p + 1; i < n; i++)
        out[i - p - 1] = k[i];
    return n - p - 1;
}

/* Replaces s by op(s). */
static cb_status elevate(cb_nurbs_surface_t s, cb_dir dir, int times, cb_error *err)
{
    if (times <= 0)
        return CB_OK;
    cb_nurbs_surface_t t;
    cb_nurbs_surface_init(t);
    cb_status st = cb_nurbs_surface_elevate_degree(t, s, dir, times, err);
    if (!st)
        cb_nurbs_surface_swap(s, t);
    cb_nurbs_surface_clear(t);
    return st;
}

static cb_status refine(cb_nurbs_surface_t s, cb_dir dir, const double *x, int n, cb_error *err)
{
    if (n <= 0)
        return CB_OK;
    cb_nurbs_surface_t t;
    cb_nurbs_surface_init(t);
    cb_status st = cb_nurbs_surface_refine_knots(t, s, dir, x, n, err);
    if (!st)
        cb_nurbs_surface_swap(s, t);
    cb_nurbs_surface_clear(t);
    return st;
}

/* Restricts s to [a, b] along dir (a, b inside its domain or on its ends). */
static cb_status restrict_to(cb_nurbs_surface_t s, cb_dir dir, double a, double b,
                             cb_error *err)
{
    double box[4];
    cb_nurbs_surface_domain(s, box);
    double lo = box[2 * dir], hi = box[2 * dir + 1];
    cb_nurbs_surface_t x, y;
    cb_nurbs_surface_init(x);
    cb_nurbs_surface_init(y);
    cb_status st = CB_OK;
    if (a > lo && (st = cb_nurbs_surface_split(x, y, s, dir, a, err)) == CB_OK)
        cb_nurbs_surface_swap(s, y);
    if (!st && b < hi && (st = cb_nurbs_surface_split(x, y, s, dir, b, err)) == CB_OK)
        cb_nurbs_surface_swap(s, x);
    cb_nurbs_surface_clear(x);
    cb_nurbs_surface_clear(y);
    return st;
}

/* The parameter along dir becomes alpha w + beta (w the old one); alpha < 0 reverses it. */
static void reparam(cb_nurbs_surface_t s, cb_dir dir, double alpha, double beta)
{
    int p = dir == CB_DIR_U ? s->deg_u : s->deg_v, n = dir == CB_DIR_U ? s->n_u : s->n_v;
    double *k = dir == CB_DIR_U ? s->knots_u : s->knots_v;
    int m = n + p + 1;
    if (alpha < 0) {
        for (int i = 0; i < m / 2; i++) {
            double t = k[i];
            k[i] = k[m - 1 - i];
            k[m - 1 - i] = t;
        }
        for (int i = 0; i < n / 2; i++)
            for (int j = 0; j < (dir == CB_DIR_U ? s->n_v : s->n_u); j++) {
                double *a = dir == CB_DIR_U ? cb_nurbs_surface_cw(s, i, j)
                                            : cb_nurbs_surface_cw(s, j, i);
                double *b = dir == CB_DIR_U ? cb_nurbs_surface_cw(s, n - 1 - i, j)
                                            : cb_nurbs_surface_cw(s, j, n - 1 - i);
                double t[4];
                memcpy(t, a, sizeof t);
                memcpy(a, b, sizeof t);
                memcpy(b, t, sizeof t);
            }
    }
    for (int i = 0; i < m; i++)
        k[i] = alpha * k[i] + beta;
}

/* A random affine parametrisation of both directions of s, and a transposition half the
 * time. */
static cb_status random_param(cb_nurbs_surface_t s, rng_t *r, cb_error *err)
{
    for (int dir = 0; dir < 2; dir++) {
        double alpha = uniform(r, 0.4, 2.5) * ((rng_next(r) & 1) ? -1 : 1);
        reparam(s, (cb_dir)dir, alpha, uniform(r, -1.5, 1.5));
    }
    if (rng_next(r) & 1) {
        cb_nurbs_surface_t t;
        cb_nurbs_surface_init(t);
        cb_status st = cb_nurbs_surface_transpose(t, s, err);
        if (!st)
            cb_nurbs_surface_swap(s, t);
        cb_nurbs_surface_clear(t);
        return st;
    }
    return CB_OK;
}

static void random_rotation(double R[3][3], rng_t *r)
{
    double q[4], n = 0;
    for (int i = 0; i < 4; i++) {
        q[i] = normal(r);
        n += q[i] * q[i];
    }
    n = sqrt(n);
    double w = q[0] / n, x = q[1] / n, y = q[2] / n, z = q[3] / n;
    double M[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
                      {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
                      {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}};
    memcpy(R, M, sizeof M);
}

/* One of the 24 rotations that map the axes onto axes. */
static void axis_rotation(double R[3][3], rng_t *r)
{
    static const int PERM[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1},
                                   {0, 2, 1}, {2, 1, 0}, {1, 0, 2}};
    int p = rand_int(r, 0, 5), sg[3];
    for (int i = 0; i < 3; i++)
        sg[i] = (rng_next(r) & 1) ? -1 : 1;
    /* det = parity * product of signs: fix the last sign to make it +1. */
    int det = (p < 3 ? 1 : -1) * sg[0] * sg[1];
    sg[2] = det;
    memset(R, 0, 9 * sizeof(double));
    for (int i = 0; i < 3; i++)
        R[i][PERM[p][i]] = sg[i];
}

static cb_status make_generic(cb_graph_case *c, design *d, rng_t *r, cb_error *err)
{
    cb_status st;
    /* Q's rectangle: the square, or (half the time, where the design allows) a larger one. */
    double rect[4] = {0, 1, 0, 1};
    if (!d->same_rect && (rng_next(r) & 1)) {
        c->q_larger = 1;
        rect[0] = -uniform(r, 0.02, 0.15);
        rect[1] = 1 + uniform(r, 0.02, 0.15);
        rect[2] = -uniform(r, 0.02, 0.15);
        rect[3] = 1 + uniform(r, 0.02, 0.15);
    }
    /* h scaled to a largest value in [0.1, 0.2] over the square. */
    double hmax = 0;
    for (int i = 0; i <= 64; i++)
        for (int j = 0; j <= 64; j++)
            hmax = fmax(hmax, fabs(dp_eval(d->h.c, i / 64.0, j / 64.0)));
    if (!(hmax > 0))
        return cb_error_set(err, CB_ERR_INVALID, "graph case %s: h vanishes", c->id);
    double hs = uniform(r, 0.1, 0.2) / hmax;
    for (int i = 0; i <= DEG; i++)
        for (int j = 0; j <= DEG; j++)
            c->h[i][j] = hs * d->h.c[i][j];
    int hdx, hdy;
    dp_degrees(&hdx, &hdy, &d->h);

    /* f: a random spline over Q's rectangle, near a random smooth function. */
    static const int DEGS[5][2] = {{3, 3}, {3, 3}, {4, 4}, {5, 3}, {3, 5}};
    int di = rng_next(r) % 10 < 6 ? 0 : rand_int(r, 1, 4);
    int p = DEGS[di][0], q = DEGS[di][1];
    double kx[4], ky[4], KX[16], KY[16];
    int nkx = random_knots(kx, r, rand_int(r, 0, 3), rect[0], rect[1], 0.08);
    int nky = random_knots(ky, r, rand_int(r, 0, 3), rect[2], rect[3], 0.08);
    /* Half the cases (drawn from a stream of their own, so that the other draws stay): f one
     * polynomial, and P and Q refined at knots of their own, so that no knot line of one is a
     * knot line of the other; otherwise f's breaks are knot lines of both. */
    rng_t r2 = {r->s ^ 0x6a09e667f3bcc908ULL};
    int independent = rng_next(&r2) & 1;
    if (independent)
        nkx = nky = 0;
    for (int i = 0; i < nkx; i++)
        c->shared_knots += kx[i] > 0 && kx[i] < 1;
    for (int i = 0; i < nky; i++)
        c->shared_knots += ky[i] > 0 && ky[i] < 1;
    int mx = knot_vector(KX, p, rect[0], rect[1], kx, nkx),
        my = knot_vector(KY, q, rect[2], rect[3], ky, nky);
    int nx = mx - p - 1, ny = my - q - 1;
    double g[6];
    for (int i = 0; i < 6; i++)
        g[i] = uniform(r, -0.35, 0.35);
    double fr = uniform(r, 2, 5), ph = uniform(r, 0, 2 * PI), noise = uniform(r, 0, 0.03);
    double *pts = malloc((size_t)nx * ny * 3 * sizeof(double));
    if (!pts)
        return cb_error_set(err, CB_ERR_NOMEM, "graph case: out of memory");
    for (int i = 0; i < nx; i++)
        for (int j = 0; j < ny; j++) {
            double x = greville(KX, i, p), y = greville(KY, j, q), *P = pts + 3 * (i * ny + j);
            P[0] = x;
            P[1] = y;
            P[2] = g[0] * x + g[1] * y + g[2] * (x - 0.5) * (x - 0.5) +
                   g[3] * (x - 0.5) * (y - 0.5) + g[4] * (y - 0.5) * (y - 0.5) +
                   0.05 * g[5] * sin(fr * x + ph) * cos(fr * y) + uniform(r, -noise, noise);
        }
    st = cb_nurbs_surface_make(c->F, p, q, KX, mx, KY, my, pts, NULL, nx, ny, err);
    free(pts);
    if (st)
        return st;

    /* Q = f + h: f elevated to Q's degrees, knots of its own, then h's coefficients on the
     * same knots added. */
    int qp = p > hdx ? p : hdx, qq = q > hdy ? q : hdy;
    double extra[2][2];
    int n_extra[2] = {0, 0};
    if (rng_next(r) % 10 < 6)
        for (int dir = 0; dir < 2; dir++)
            n_extra[dir] = random_knots(extra[dir], r, rand_int(r, 0, 2), rect[2 * dir],
                                        rect[2 * dir + 1], 0.03);
    cb_nurbs_surface_t H;
    cb_nurbs_surface_init(H);
    st = cb_nurbs_surface_set(c->Q, c->F, err);
    if (!st)
        st = elevate(c->Q, CB_DIR_U, qp - p, err);
    if (!st)
        st = elevate(c->Q, CB_DIR_V, qq - q, err);
    for (int dir = 0; dir < 2 && !st; dir++)
        st = refine(c->Q, (cb_dir)dir, extra[dir], n_extra[dir], err);
    for (int dir = 0; dir < 2 && !st && independent; dir++) {
        double k[2];
        int n = random_knots(k, &r2, rand_int(&r2, 1, 2), rect[2 * dir], rect[2 * dir + 1], 0.05);
        st = refine(c->Q, (cb_dir)dir, k, n, err);
    }
    if (!st) {
        /* h as one Bezier patch of degree (qp, qq) over the rectangle. */
        double pow[(DEG + 1) * (DEG + 1)], bern[(DEG + 1) * (DEG + 1)];
        double hp[(DEG + 1) * (DEG + 1) * 3], bu[2 * (DEG + 1)], bv[2 * (DEG + 1)];
        memset(pow, 0, sizeof pow);
        for (int i = 0; i <= qp; i++)
            for (int j = 0; j <= qq; j++)
                pow[i * (qq + 1) + j] = i <= DEG && j <= DEG ? c->h[i][j] : 0;
        cb_power_to_bernstein_2d(bern, pow, qp, qq, rect[0], rect[1], rect[2], rect[3]);
        for (int i = 0; i <= qp; i++)
            for (int j = 0; j <= qq; j++) {
                double *P = hp + 3 * (i * (qq + 1) + j);
                P[0] = rect[0] + (rect[1] - rect[0]) * i / qp;
                P[1] = rect[2] + (rect[3] - rect[2]) * j / qq;
                P[2] = bern[i * (qq + 1) + j];
            }
        knot_vector(bu, qp, rect[0], rect[1], NULL, 0);
        knot_vector(bv, qq, rect[2], rect[3], NULL, 0);
        st = cb_nurbs_surface_make(H, qp, qq, bu, 2 * qp + 2, bv, 2 * qq + 2, hp, NULL, qp + 1,
                                   qq + 1, err);
    }
    for (int dir = 0; dir < 2 && !st; dir++) {
        double ik[64];
        int n = interior_knots(ik, c->Q, (cb_dir)dir);
        st = n > 64 ? cb_error_set(err, CB_ERR_INVALID, "graph case: too many knots")
                    : refine(H, (cb_dir)dir, ik, n, err);
    }
    if (!st && (H->n_u != c->Q->n_u || H->n_v != c->Q->n_v ||
                memcmp(H->knots_u, c->Q->knots_u, (size_t)(H->n_u + H->deg_u + 1) *
                                                      sizeof(double)) ||
                memcmp(H->knots_v, c->Q->knots_v,
                       (size_t)(H->n_v + H->deg_v + 1) * sizeof(double))))
        st = cb_error_set(err, CB_ERR_INVALID, "graph case %s: h and f on different knots",
                          c->id);
    if (!st)
        for (long k = 0; k < (long)H->n_u * H->n_v; k++)
            c->Q->cw[4 * k + 2] += H->cw[4 * k + 2];
    cb_nurbs_surface_clear(H);

    /* P: f over the square, sometimes elevated or given one more knot. */
    if (!st)
        st = cb_nurbs_surface_set(c->P, c->F, err);
    for (int dir = 0; dir < 2 && !st; dir++)
        st = restrict_to(c->P, (cb_dir)dir, 0, 1, err);
    for (int dir = 0; dir < 2 && !st && independent; dir++) {
        double k[3];
        int n = random_knots(k, &r2, rand_int(&r2, 1, 3), 0, 1, 0.05);
        st = refine(c->P, (cb_dir)dir, k, n, err);
    }
    if (!st && rng_next(r) % 10 < 3)
        st = elevate(c->P, (cb_dir)(rng_next(r) & 1), 1, err);
    if (!st && rng_next(r) % 10 < 4) {
        double t = uniform(r, 0.05, 0.95);
        st = refine(c->P, (cb_dir)(rng_next(r) & 1), &t, 1, err);
    }
    /* Each its own parametrisation, then one motion for both. */
    if (!st)
        st = random_param(c->P, r, err);
    if (!st)
        st = random_param(c->Q, r, err);
    if (st)
        return st;
    if (c->pose == CB_GRAPH_POSE_GENERIC) {
        random_rotation(c->R, r);
        for (int i = 0; i < 3; i++) {
            c->T[i] = uniform(r, -2, 2);
            c->L[i] = uniform(r, 0.75, 1.35);
        }
    } else {
        axis_rotation(c->R, r);
        for (int i = 0; i < 3; i++) {
            c->T[i] = rand_int(r, -16, 16) / 8.0;
            c->L[i] = 1;
        }
    }
    move_surface(c->P, c);
    move_surface(c->Q, c);
    return CB_OK;
}

/* ---------------------------------------------------------------- entry -------------------- */

cb_status cb_graph_case_make(cb_graph_case *c, int cls, int pose, int index, cb_error *err)
{
    cb_graph_case_clear(c);
    if (cls < 0 || cls >= CB_GRAPH_CLASS_COUNT || pose < 0 || pose >= CB_GRAPH_POSE_COUNT ||
        index < 0)
        return cb_error_set(err, CB_ERR_INVALID, "graph case: class %d, pose %d, index %d",
                            cls, pose, index);
    c->cls = cls;
    c->pose = pose;
    c->index = index;
    snprintf(c->id, sizeof c->id, "%s/%s/%d", CLASS_NAME[cls], POSE_NAME[pose], index);
    rng_t r = {0x5eed0000ULL ^ ((uint64_t)cls << 40) ^ ((uint64_t)pose << 32) ^ (uint64_t)index};
    for (int k = 0; k < 4; k++)
        rng_next(&r);
    design d;
    memset(&d, 0, sizeof d);
    d.c = c;
    d.exact = pose == CB_GRAPH_POSE_EXACT;
    d.den = d.exact ? 32 : 1;
    design_class(&d, &r, cls);
    if (d.h.overflow)
        return cb_error_set(err, CB_ERR_INVALID, "graph case %s: h above degree %d", c->id, DEG);
    cb_status st = d.exact ? make_exact(c, &d, err) : make_generic(c, &d, &r, err);
    if (st) {
        cb_graph_case_clear(c);
        return st;
    }
    net_size(c);
    return CB_OK;
}
