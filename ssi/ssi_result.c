/* ssi_result.c — the result container of the SSI (cb_ssi_result_t, ssi/ssi.h): every operation
 * that adds to it or moves it, so that its invariants (outcome counters, failure status, the
 * memory rules) live in one place. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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
