/* ssi_stitch.c — the result type, and stitching pieces of patch pairs into maximal curves. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "ssi/ssi.h"

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
    cb_ssi_result_init(r);
}

cb_status _cb_ssi_add_marks(cb_ssi_result_t r, const cb_ssi_mark *m, slong n)
{
    if (r->n_marks + n > r->alloc_marks) {
        slong alloc = FLINT_MAX(2 * r->alloc_marks, r->n_marks + n);
        cb_ssi_mark *q = realloc(r->mark, (size_t)alloc * sizeof(*q));
        if (!q)
            return CB_ERR_NOMEM;
        r->mark = q;
        r->alloc_marks = alloc;
    }
    memcpy(r->mark + r->n_marks, m, (size_t)n * sizeof(*m));
    r->n_marks += n;
    return CB_OK;
}

cb_status _cb_ssi_result_move(cb_ssi_result_t r, cb_ssi_result_t s)
{
    if (s->n_curves) {
        if (r->n_curves + s->n_curves > r->alloc_curves) {
            slong alloc = FLINT_MAX(2 * r->alloc_curves, r->n_curves + s->n_curves);
            cb_ssi_curve *q = realloc(r->curve, (size_t)alloc * sizeof(*q));
            if (!q)
                return CB_ERR_NOMEM;
            r->curve = q;
            r->alloc_curves = alloc;
        }
        memcpy(r->curve + r->n_curves, s->curve, (size_t)s->n_curves * sizeof(*s->curve));
        r->n_curves += s->n_curves;
        s->n_curves = 0;
    }
    if (s->n_points) {
        if (r->n_points + s->n_points > r->alloc_points) {
            slong alloc = FLINT_MAX(2 * r->alloc_points, r->n_points + s->n_points);
            cb_ssi_isolated *q = realloc(r->point, (size_t)alloc * sizeof(*q));
            if (!q)
                return CB_ERR_NOMEM;
            r->point = q;
            r->alloc_points = alloc;
        }
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
    for (slong k = 0; k < s->n_coincident; k++) {
        const cb_ssi_coincident *c = s->coincident + k;
        cb_ssi_coincident *d = _cb_ssi_add_coincident(r, c->face_a, c->face_b, c->patch_a,
                                                      c->patch_b, c->same_normal, c->xyz);
        if (!d)
            return CB_ERR_NOMEM;
        *d = *c;
    }
    s->n_coincident = 0;
    if (s->n_marks && _cb_ssi_add_marks(r, s->mark, s->n_marks) != CB_OK)
        return CB_ERR_NOMEM;
    s->n_marks = 0;
    r->pairs_total += s->pairs_total;
    r->pairs_culled += s->pairs_culled;
    r->pairs_empty += s->pairs_empty;
    r->pairs_certified += s->pairs_certified;
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

static double d3(const double *a, const double *b)
{
    return sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                (a[2] - b[2]) * (a[2] - b[2]));
}

/* Distance from p to the polyline of n points x. */
static double polyline_dist(const double *p, const double *x, slong n)
{
    double best = d3(p, x);
    for (slong i = 0; i + 1 < n; i++) {
        const double *a = x + 3 * i, *b = x + 3 * i + 3;
        double ab[3], ap[3], l2 = 0, dot = 0;
        for (int k = 0; k < 3; k++) {
            ab[k] = b[k] - a[k];
            ap[k] = p[k] - a[k];
            l2 += ab[k] * ab[k];
            dot += ab[k] * ap[k];
        }
        double f = l2 > 0 ? fmin(1, fmax(0, dot / l2)) : 0, q[3];
        for (int k = 0; k < 3; k++)
            q[k] = a[k] + f * ab[k];
        best = fmin(best, d3(p, q));
    }
    return best;
}

typedef struct {
    const _cb_ssi_piece *p;
    slong node[2];
    int dropped, used;
} item;

typedef struct {
    double X[3];
    _cb_ssi_pq pq;
    slong deg;
} node;

static void out_point(cb_ssi_point *o, const double X[3], const _cb_ssi_pq *q, int swapped)
{
    memcpy(o->xyz, X, 3 * sizeof(double));
    const double *uv = q->uv, *st = q->st;
    memcpy(o->uv_a, swapped ? st : uv, 2 * sizeof(double));
    memcpy(o->uv_b, swapped ? uv : st, 2 * sizeof(double));
}

/* A new empty curve; NULL when out of memory (r is left as it was). */
static cb_ssi_curve *add_curve(cb_ssi_result_t r)
{
    if (r->n_curves == r->alloc_curves) {
        slong alloc = r->alloc_curves ? 2 * r->alloc_curves : 8;
        cb_ssi_curve *q = realloc(r->curve, (size_t)alloc * sizeof(*q));
        if (!q)
            return NULL;
        r->curve = q;
        r->alloc_curves = alloc;
    }
    cb_ssi_curve *c = r->curve + r->n_curves++;
    memset(c, 0, sizeof(*c));
    return c;
}

static cb_status curve_append(cb_ssi_curve *c, slong *alloc, const double X[3],
                              const _cb_ssi_pq *q, int swapped)
{
    if (c->n == *alloc) {
        slong a = *alloc ? 2 * *alloc : 64;
        cb_ssi_point *pt = realloc(c->pt, (size_t)a * sizeof(cb_ssi_point));
        if (!pt)
            return CB_ERR_NOMEM;
        c->pt = pt;
        *alloc = a;
    }
    out_point(c->pt + c->n++, X, q, swapped);
    return CB_OK;
}

/* Appends piece it in direction rev (0: as stored), skipping its first point when the curve
 * already ends there, with its end points snapped to their nodes. */
static cb_status append_piece(cb_ssi_curve *c, slong *alloc, const item *it, int rev,
                              const node *nodes, int swapped)
{
    const _cb_ssi_piece *p = it->p;
    cb_status st = CB_OK;
    for (slong k = 0; k < p->n && st == CB_OK; k++) {
        slong i = rev ? p->n - 1 - k : k;
        if (k == 0 && c->n > 0)
            continue;
        if (i == 0 && it->node[0] >= 0)
            st = curve_append(c, alloc, nodes[it->node[0]].X, &nodes[it->node[0]].pq, swapped);
        else if (i == p->n - 1 && it->node[1] >= 0)
            st = curve_append(c, alloc, nodes[it->node[1]].X, &nodes[it->node[1]].pq, swapped);
        else
            st = curve_append(c, alloc, p->xyz + 3 * i, p->pt + i, swapped);
    }
    return st;
}

cb_status _cb_ssi_stitch(cb_ssi_result_t r, const _cb_ssi_piece_set *sets, slong nsets,
                         int swapped, int face_a, int face_b, double merge_tol, double chord)
{
    slong ni = 0, nn = 0;
    for (slong s = 0; s < nsets; s++)
        ni += sets[s].n;
    item *it = calloc((size_t)ni + 1, sizeof(item));
    node *nodes = malloc((size_t)(2 * ni + 1) * sizeof(node));
    if (!it || !nodes) {
        free(it);
        free(nodes);
        return CB_ERR_NOMEM;
    }
    cb_status st = CB_OK;
    slong m = 0;
    for (slong s = 0; s < nsets; s++)
        for (slong k = 0; k < sets[s].n; k++) {
            it[m].p = sets[s].p + k;
            it[m].node[0] = it[m].node[1] = -1;
            m++;
        }
    /* Nodes: end points of open pieces, clustered in piece order. */
    for (slong i = 0; i < ni; i++) {
        const _cb_ssi_piece *p = it[i].p;
        if (p->isolated || p->closed)
            continue;
        for (int e = 0; e < 2; e++) {
            slong idx = e ? p->n - 1 : 0;
            const double *X = p->xyz + 3 * idx;
            slong f = -1;
            for (slong q = 0; q < nn && f < 0; q++)
                if (d3(nodes[q].X, X) <= merge_tol)
                    f = q;
            if (f < 0) {
                f = nn++;
                memcpy(nodes[f].X, X, 3 * sizeof(double));
                nodes[f].pq = p->pt[idx];
                nodes[f].deg = 0;
            }
            it[i].node[e] = f;
        }
        /* A piece that never leaves its start node (a touch at a patch side) adds nothing. */
        int moves = 0;
        for (slong k = 0; k < p->n && !moves; k++)
            moves = d3(p->xyz + 3 * k, nodes[it[i].node[0]].X) > merge_tol;
        if (!moves && it[i].node[0] == it[i].node[1])
            it[i].dropped = 1;
    }
    /* Duplicates: a curve on a patch side shared by two pairs is found by both. */
    for (slong i = 0; i < ni; i++) {
        if (it[i].dropped || it[i].p->isolated || it[i].p->closed)
            continue;
        const _cb_ssi_piece *p = it[i].p;
        const double *mid = p->xyz + 3 * (p->n / 2);
        for (slong j = 0; j < i; j++) {
            if (it[j].dropped || it[j].p->isolated || it[j].p->closed)
                continue;
            int same = (it[j].node[0] == it[i].node[0] && it[j].node[1] == it[i].node[1]) ||
                       (it[j].node[0] == it[i].node[1] && it[j].node[1] == it[i].node[0]);
            if (same && polyline_dist(mid, it[j].p->xyz, it[j].p->n) <= chord + merge_tol) {
                it[i].dropped = 1;
                break;
            }
        }
    }
    for (slong i = 0; i < ni; i++)
        if (!it[i].dropped && it[i].node[0] >= 0) {
            nodes[it[i].node[0]].deg++;
            nodes[it[i].node[1]].deg++;
        }
    /* Chains through nodes of degree 2. */
    for (slong i = 0; i < ni && st == CB_OK; i++) {
        if (it[i].dropped || it[i].used || it[i].p->isolated)
            continue;
        slong alloc = 0;
        cb_ssi_curve *c = add_curve(r);
        if (!c) {
            st = CB_ERR_NOMEM;
            break;
        }
        c->face_a = face_a;
        c->face_b = face_b;
        if (it[i].p->closed) {
            it[i].used = 1;
            st = append_piece(c, &alloc, it + i, 0, nodes, swapped);
            c->closed = 1;
            c->tangential = it[i].p->tangential;
            continue;
        }
        /* Walk backwards from piece i to the chain's start (a node of degree != 2) or around
         * the loop back to i. */
        slong cur = i;
        int rev = 0;
        for (;;) {
            slong nd = it[cur].node[rev ? 1 : 0];
            if (nodes[nd].deg != 2)
                break;
            slong nxt = -1;
            int nrev = 0;
            for (slong j = 0; j < ni && nxt < 0; j++) {
                if (j == cur || it[j].dropped || it[j].p->isolated || it[j].p->closed)
                    continue;
                if (it[j].node[1] == nd) {
                    nxt = j;
                    nrev = 0;
                } else if (it[j].node[0] == nd) {
                    nxt = j;
                    nrev = 1;
                }
            }
            if (nxt < 0 || nxt == i)
                break;
            cur = nxt;
            rev = nrev;
        }
        slong first = cur;
        c->tangential = 1;
        for (;;) {
            it[cur].used = 1;
            c->tangential &= it[cur].p->tangential != 0;
            st = append_piece(c, &alloc, it + cur, rev, nodes, swapped);
            if (st != CB_OK)
                break;
            slong nd = it[cur].node[rev ? 0 : 1];
            if (nodes[nd].deg != 2)
                break;
            slong nxt = -1;
            int nrev = 0;
            for (slong j = 0; j < ni && nxt < 0; j++) {
                if (j == cur || it[j].dropped || it[j].p->isolated || it[j].p->closed)
                    continue;
                if (it[j].node[0] == nd) {
                    nxt = j;
                    nrev = 0;
                } else if (it[j].node[1] == nd) {
                    nxt = j;
                    nrev = 1;
                }
            }
            if (nxt < 0)
                break;
            if (nxt == first || it[nxt].used) {
                c->closed = nxt == first;
                break;
            }
            cur = nxt;
            rev = nrev;
        }
    }
    /* Isolated points not at a node or at an earlier point. */
    slong p0 = r->n_points;
    for (slong i = 0; i < ni && st == CB_OK; i++) {
        const _cb_ssi_piece *p = it[i].p;
        if (!p->isolated)
            continue;
        int dup = 0;
        for (slong q = 0; q < nn && !dup; q++)
            dup = nodes[q].deg > 0 && d3(nodes[q].X, p->xyz) <= merge_tol;
        for (slong q = p0; q < r->n_points && !dup; q++)
            dup = d3(r->point[q].p.xyz, p->xyz) <= merge_tol;
        if (dup)
            continue;
        if (r->n_points == r->alloc_points) {
            slong alloc = r->alloc_points ? 2 * r->alloc_points : 8;
            cb_ssi_isolated *q = realloc(r->point, (size_t)alloc * sizeof(*q));
            if (!q) {
                st = CB_ERR_NOMEM;
                break;
            }
            r->point = q;
            r->alloc_points = alloc;
        }
        cb_ssi_isolated *o = r->point + r->n_points++;
        out_point(&o->p, p->xyz, p->pt, swapped);
        o->tangential = 1;
        o->face_a = face_a;
        o->face_b = face_b;
    }
    free(it);
    free(nodes);
    return st;
}
