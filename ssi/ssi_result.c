/* ssi_result.c — the result container of the SSI (cb_ssi_result_t, ssi/ssi.h): every operation
 * that adds to it or moves it, so that its invariants (outcome counters, failure status, the
 * memory rules) live in one place. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brep/geom.h"
#include "ssi/ssi.h"

const char *cb_ssi_outcome_name(cb_ssi_outcome o)
{
    switch (o) {
    case CB_SSI_CERTIFIED:
        return "certified";
    case CB_SSI_WITHIN_TOL:
        return "within_tolerance";
    case CB_SSI_REFUSED:
        return "refused";
    }
    return "unknown";
}

const char *cb_ssi_region_kind_name(cb_ssi_region_kind k)
{
    switch (k) {
    case CB_SSI_REGION_COINCIDENCE:
        return "coincidence";
    case CB_SSI_REGION_NEAR_NODE:
        return "near_node";
    case CB_SSI_REGION_CONTACT_BAND:
        return "contact_band";
    case CB_SSI_REGION_SIDE:
        return "side";
    case CB_SSI_REGION_OUTSIDE_FACE:
        return "outside_face";
    }
    return "unknown";
}

void cb_ssi_result_init(cb_ssi_result_t r)
{
    memset(r, 0, sizeof(*r));
    r->status = CB_OK;
}

void cb_ssi_result_clear(cb_ssi_result_t r)
{
    for (slong i = 0; i < r->n_curves; i++)
        free(r->curve[i].pt);
    free(r->curve);
    free(r->point);
    free(r->failed);
    free(r->coincident);
    free(r->mark);
    free(r->region);
    cb_ssi_result_init(r);
}

/* Room for n more items in the array *a of *count items out of *alloc (size bytes each);
 * CB_ERR_NOMEM leaves it as it was. */
static cb_status grow(void **a, slong *alloc, slong count, slong n, size_t size)
{
    if (count + n <= *alloc)
        return CB_OK;
    slong na = FLINT_MAX(*alloc ? 2 * *alloc : 8, count + n);
    void *q = realloc(*a, (size_t)na * size);
    if (!q)
        return CB_ERR_NOMEM;
    *a = q;
    *alloc = na;
    return CB_OK;
}

cb_ssi_curve *_cb_ssi_add_curve(cb_ssi_result_t r, int fa, int fb)
{
    if (grow((void **)&r->curve, &r->alloc_curves, r->n_curves, 1, sizeof(cb_ssi_curve)))
        return NULL;
    cb_ssi_curve *c = r->curve + r->n_curves++;
    memset(c, 0, sizeof(*c));
    c->face_a = fa;
    c->face_b = fb;
    c->certified = 1;
    return c;
}

cb_ssi_isolated *_cb_ssi_add_point(cb_ssi_result_t r, int fa, int fb)
{
    if (grow((void **)&r->point, &r->alloc_points, r->n_points, 1, sizeof(cb_ssi_isolated)))
        return NULL;
    cb_ssi_isolated *p = r->point + r->n_points++;
    memset(p, 0, sizeof(*p));
    p->tangential = 1;
    p->certified = 1;
    p->face_a = fa;
    p->face_b = fb;
    return p;
}

cb_ssi_coincident *_cb_ssi_add_coincident(cb_ssi_result_t r, int fa, int fb, int pa, int pb,
                                          int same_normal, const double xyz[3], int exact,
                                          double width)
{
    if (grow((void **)&r->coincident, &r->alloc_coincident, r->n_coincident, 1,
             sizeof(cb_ssi_coincident)))
        return NULL;
    cb_ssi_coincident *c = r->coincident + r->n_coincident++;
    c->face_a = fa;
    c->face_b = fb;
    c->patch_a = pa;
    c->patch_b = pb;
    c->patch_pairs = 1;
    c->whole = 1;
    c->same_normal = c->same_face_normal = same_normal != 0;
    memcpy(c->xyz, xyz, sizeof c->xyz);
    c->exact = exact != 0;
    c->width = exact ? 0 : width;
    return c;
}

cb_ssi_region *_cb_ssi_add_region(cb_ssi_result_t r, cb_ssi_region_kind kind, int fa, int fb,
                                  int pa, int pb, double width)
{
    if (grow((void **)&r->region, &r->alloc_regions, r->n_regions, 1, sizeof(cb_ssi_region)))
        return NULL;
    cb_ssi_region *g = r->region + r->n_regions++;
    memset(g, 0, sizeof(*g));
    g->kind = kind;
    g->face_a = fa;
    g->face_b = fb;
    g->patch_a = pa;
    g->patch_b = pb;
    g->width = width;
    return g;
}

cb_status _cb_ssi_add_failure(cb_ssi_result_t r, int fa, int fb, int pa, int pb, cb_status st,
                              const char *msg)
{
    if (grow((void **)&r->failed, &r->alloc_failed, r->n_failed, 1, sizeof(cb_ssi_failure))) {
        /* The failure goes unlisted, but r must not read as certified. */
        if (r->status == CB_OK)
            r->status = CB_ERR_NOMEM;
        return CB_ERR_NOMEM;
    }
    cb_ssi_failure *f = r->failed + r->n_failed++;
    f->face_a = fa;
    f->face_b = fb;
    f->patch_a = pa;
    f->patch_b = pb;
    f->status = st;
    snprintf(f->msg, sizeof f->msg, "%s", msg);
    f->has_box = 0;
    memset(f->box_a, 0, sizeof f->box_a);
    memset(f->box_b, 0, sizeof f->box_b);
    if (r->status == CB_OK)
        r->status = st;
    return CB_OK;
}

cb_status _cb_ssi_add_marks(cb_ssi_result_t r, const cb_ssi_mark *m, slong n)
{
    if (grow((void **)&r->mark, &r->alloc_marks, r->n_marks, n, sizeof(cb_ssi_mark)))
        return CB_ERR_NOMEM;
    memcpy(r->mark + r->n_marks, m, (size_t)n * sizeof(*m));
    r->n_marks += n;
    return CB_OK;
}

cb_status _cb_ssi_result_move(cb_ssi_result_t r, cb_ssi_result_t s)
{
    if (s->n_curves) {
        if (grow((void **)&r->curve, &r->alloc_curves, r->n_curves, s->n_curves,
                 sizeof(cb_ssi_curve)))
            return CB_ERR_NOMEM;
        memcpy(r->curve + r->n_curves, s->curve, (size_t)s->n_curves * sizeof(*s->curve));
        r->n_curves += s->n_curves;
        s->n_curves = 0;
    }
    if (s->n_points) {
        if (grow((void **)&r->point, &r->alloc_points, r->n_points, s->n_points,
                 sizeof(cb_ssi_isolated)))
            return CB_ERR_NOMEM;
        memcpy(r->point + r->n_points, s->point, (size_t)s->n_points * sizeof(*s->point));
        r->n_points += s->n_points;
        s->n_points = 0;
    }
    for (slong k = 0; k < s->n_failed; k++) {
        const cb_ssi_failure *f = s->failed + k;
        if (_cb_ssi_add_failure(r, f->face_a, f->face_b, f->patch_a, f->patch_b, f->status,
                                f->msg) != CB_OK)
            return CB_ERR_NOMEM;
        cb_ssi_failure *g = r->failed + r->n_failed - 1;
        g->has_box = f->has_box;
        memcpy(g->box_a, f->box_a, sizeof g->box_a);
        memcpy(g->box_b, f->box_b, sizeof g->box_b);
    }
    s->n_failed = 0;
    if (s->n_coincident) {
        if (grow((void **)&r->coincident, &r->alloc_coincident, r->n_coincident,
                 s->n_coincident, sizeof(cb_ssi_coincident)))
            return CB_ERR_NOMEM;
        memcpy(r->coincident + r->n_coincident, s->coincident,
               (size_t)s->n_coincident * sizeof(*s->coincident));
        r->n_coincident += s->n_coincident;
        s->n_coincident = 0;
    }
    if (s->n_regions) {
        if (grow((void **)&r->region, &r->alloc_regions, r->n_regions, s->n_regions,
                 sizeof(cb_ssi_region)))
            return CB_ERR_NOMEM;
        memcpy(r->region + r->n_regions, s->region, (size_t)s->n_regions * sizeof(*s->region));
        r->n_regions += s->n_regions;
        s->n_regions = 0;
    }
    if (s->n_marks && _cb_ssi_add_marks(r, s->mark, s->n_marks) != CB_OK)
        return CB_ERR_NOMEM;
    s->n_marks = 0;
    r->pairs_total += s->pairs_total;
    r->pairs_culled += s->pairs_culled;
    r->pairs_empty += s->pairs_empty;
    r->pairs_certified += s->pairs_certified;
    r->pairs_within_tolerance += s->pairs_within_tolerance;
    r->pairs_outside_face += s->pairs_outside_face;
    r->pairs_subdivided += s->pairs_subdivided;
    r->pairs_coincident += s->pairs_coincident;
    r->pairs_closed_form += s->pairs_closed_form;
    r->subpairs += s->subpairs;
    r->regions_within_tol += s->regions_within_tol;
    r->nodes_within_tol += s->nodes_within_tol;
    r->width_within_tol = fmax(r->width_within_tol, s->width_within_tol);
    r->max_dist_a = fmax(r->max_dist_a, s->max_dist_a);
    r->max_dist_b = fmax(r->max_dist_b, s->max_dist_b);
    r->time_topo += s->time_topo;
    r->time_trace += s->time_trace;
    return CB_OK;
}

static double surface_dist(const cb_ssi_surface *S, const double uv[2], const double X[3])
{
    double p[3];
    if (S->kind == CB_SSI_ANALYTIC)
        cb_analytic_eval(p, &S->analytic, uv[0], uv[1]);
    else
        cb_nurbs_surface_eval(p, S->nurbs, uv[0], uv[1]);
    return sqrt((p[0] - X[0]) * (p[0] - X[0]) + (p[1] - X[1]) * (p[1] - X[1]) +
                (p[2] - X[2]) * (p[2] - X[2]));
}

void _cb_ssi_result_measure(cb_ssi_result_t r, const cb_ssi_surface *A, const cb_ssi_surface *B,
                            const cb_ssi_point *p)
{
    r->max_dist_a = fmax(r->max_dist_a, surface_dist(A, p->uv_a, p->xyz));
    r->max_dist_b = fmax(r->max_dist_b, surface_dist(B, p->uv_b, p->xyz));
}

/* ---------------------------------------------------------------- densification ---------- */

static void surface_derivs(double d[6][3], const cb_ssi_surface *S, double u, double v)
{
    if (S->kind == CB_SSI_ANALYTIC)
        cb_analytic_eval_derivs(d, &S->analytic, u, v);
    else
        cb_nurbs_surface_eval_derivs(d, S->nurbs, u, v);
}

/* Period of parameter k of S (0 when not periodic): the angle of every analytic surface but
 * the plane, and the torus' second angle. */
static double surface_period(const cb_ssi_surface *S, int k)
{
    if (S->kind != CB_SSI_ANALYTIC || S->analytic.kind == CB_ANALYTIC_PLANE)
        return 0;
    return k == 0 || S->analytic.kind == CB_ANALYTIC_TORUS ? 2 * CB_SSI_PI : 0;
}

/* The point of the curve between a and b: their parameters' midpoint (b's periodic ones taken
 * nearest a's), moved onto both surfaces and onto the plane through the chord's midpoint normal
 * to it by Newton's method. 1 with m filled when it converged to within tol / 16 of both
 * surfaces and of the plane, no farther from the chord's midpoint than half the chord (the
 * same branch). */
static int curve_midpoint(cb_ssi_point *m, const cb_ssi_point *a, const cb_ssi_point *b,
                          const cb_ssi_surface *A, const cb_ssi_surface *B, double tol)
{
    double M[3], n[3], len = 0;
    for (int k = 0; k < 3; k++) {
        M[k] = 0.5 * (a->xyz[k] + b->xyz[k]);
        n[k] = b->xyz[k] - a->xyz[k];
        len += n[k] * n[k];
    }
    len = sqrt(len);
    if (!(len > 0))
        return 0;
    for (int k = 0; k < 3; k++)
        n[k] /= len;
    double x[4];
    const double *pa[2] = {a->uv_a, a->uv_b}, *pb[2] = {b->uv_a, b->uv_b};
    const cb_ssi_surface *S[2] = {A, B};
    for (int s = 0; s < 2; s++)
        for (int k = 0; k < 2; k++) {
            double P = surface_period(S[s], k), vb = pb[s][k];
            if (P > 0)
                vb += P * nearbyint((pa[s][k] - vb) / P);
            x[2 * s + k] = 0.5 * (pa[s][k] + vb);
        }
    double X[3] = {0, 0, 0}, res = HUGE_VAL;
    for (int it = 0; it < 12; it++) {
        double da[6][3], db[6][3];
        surface_derivs(da, A, x[0], x[1]);
        surface_derivs(db, B, x[2], x[3]);
        double F[4], J[4][4], dx[4];
        for (int k = 0; k < 3; k++) {
            F[k] = da[0][k] - db[0][k];
            X[k] = 0.5 * (da[0][k] + db[0][k]);
        }
        F[3] = n[0] * (X[0] - M[0]) + n[1] * (X[1] - M[1]) + n[2] * (X[2] - M[2]);
        res = fmax(sqrt(F[0] * F[0] + F[1] * F[1] + F[2] * F[2]), fabs(F[3]));
        if (res <= 1e-3 * tol)
            break;
        for (int k = 0; k < 3; k++) {
            J[k][0] = da[1][k];
            J[k][1] = da[2][k];
            J[k][2] = -db[1][k];
            J[k][3] = -db[2][k];
            dx[k] = -F[k];
        }
        for (int c = 0; c < 2; c++) {
            J[3][c] = 0.5 * (n[0] * da[1 + c][0] + n[1] * da[1 + c][1] + n[2] * da[1 + c][2]);
            J[3][2 + c] = 0.5 * (n[0] * db[1 + c][0] + n[1] * db[1 + c][1] + n[2] * db[1 + c][2]);
        }
        dx[3] = -F[3];
        /* A (nearly) singular system (the surfaces tangent along the curve) gives no
         * point. */
        if (!cb_linsolve(&J[0][0], dx, 4, 1e-10))
            return 0;
        for (int c = 0; c < 4; c++)
            x[c] += dx[c];
        if (!isfinite(x[0] + x[1] + x[2] + x[3]))
            return 0;
        /* B-spline parameters stay in their domains. */
        for (int s = 0; s < 2; s++)
            if (S[s]->kind == CB_SSI_NURBS) {
                const cb_nurbs_surface_struct *N = S[s]->nurbs;
                double lo[2] = {N->knots_u[N->deg_u], N->knots_v[N->deg_v]};
                double hi[2] = {N->knots_u[N->n_u], N->knots_v[N->n_v]};
                for (int k = 0; k < 2; k++)
                    x[2 * s + k] = fmin(fmax(x[2 * s + k], lo[k]), hi[k]);
            }
    }
    if (!(res <= tol / 16))
        return 0;
    double off = sqrt((X[0] - M[0]) * (X[0] - M[0]) + (X[1] - M[1]) * (X[1] - M[1]) +
                      (X[2] - M[2]) * (X[2] - M[2]));
    if (!(off <= 0.5 * len))
        return 0;
    memcpy(m->xyz, X, sizeof X);
    m->uv_a[0] = x[0];
    m->uv_a[1] = x[1];
    m->uv_b[0] = x[2];
    m->uv_b[1] = x[3];
    return 1;
}

/* Appends to *out (capacity *cap) the points strictly between a and b that bring every chord's
 * midpoint within chord of the curve (depth <= 16); -1 when out of memory. */
static int densify(cb_ssi_point **out, slong *n, slong *cap, const cb_ssi_point *a,
                   const cb_ssi_point *b, const cb_ssi_surface *A, const cb_ssi_surface *B,
                   double chord, double tol, int depth)
{
    cb_ssi_point m;
    if (depth >= 16 || !curve_midpoint(&m, a, b, A, B, tol))
        return 0;
    double sag = 0;
    for (int k = 0; k < 3; k++)
        sag += (m.xyz[k] - 0.5 * (a->xyz[k] + b->xyz[k])) * (m.xyz[k] - 0.5 * (a->xyz[k] + b->xyz[k]));
    if (!(sqrt(sag) > chord))
        return 0;
    if (densify(out, n, cap, a, &m, A, B, chord, tol, depth + 1))
        return -1;
    if (*n == *cap) {
        slong c = 2 * *cap;
        cb_ssi_point *q = realloc(*out, (size_t)c * sizeof *q);
        if (!q)
            return -1;
        *out = q;
        *cap = c;
    }
    (*out)[(*n)++] = m;
    return densify(out, n, cap, &m, b, A, B, chord, tol, depth + 1);
}

int _cb_ssi_result_densify(cb_ssi_result_t r, slong c0, const cb_ssi_surface *A,
                           const cb_ssi_surface *B, double chord, double tol)
{
    for (slong c = c0; c < r->n_curves; c++) {
        cb_ssi_curve *cv = r->curve + c;
        if (cv->tangential || cv->n < 2)
            continue;
        slong n = 0, cap = 2 * cv->n;
        cb_ssi_point *out = malloc((size_t)cap * sizeof *out);
        if (!out)
            return -1;
        int added = 0;
        for (slong i = 0; i < cv->n; i++) {
            if (i > 0) {
                slong before = n;
                if (densify(&out, &n, &cap, cv->pt + i - 1, cv->pt + i, A, B, chord, tol, 0)) {
                    free(out);
                    return -1;
                }
                added |= n > before;
            }
            if (n == cap) {
                cb_ssi_point *q = realloc(out, (size_t)(2 * cap) * sizeof *q);
                if (!q) {
                    free(out);
                    return -1;
                }
                out = q;
                cap *= 2;
            }
            out[n++] = cv->pt[i];
        }
        if (added) {
            free(cv->pt);
            cv->pt = out;
            cv->n = n;
        } else {
            free(out);
        }
    }
    return 0;
}
