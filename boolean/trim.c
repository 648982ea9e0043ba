/* trim.c — the SSI of two bodies restricted to their trimmed faces (cb_bool_ssi_trim). */
#include <stdlib.h>
#include <string.h>

#include "boolean/cut_internal.h"

/* Does cut b continue cut a: the same SSI curve, b starting where a ends? (A curve split at a
 * periodic window's end gives both pieces that point exactly.) */
static int continues(const cb_bool_cut *a, const cb_bool_cut *b)
{
    return a->curve >= 0 && a->curve == b->curve && !a->closed && !b->closed &&
           !memcmp(a->xyz + 3 * (a->n - 1), b->xyz, 3 * sizeof(double));
}

/* Cuts [first, last] (each continuing the one before) of curve src as one curve: the shared
 * points once; closed when src is and the last ends where the first starts (a loop split at a
 * window's end, or a whole loop rotated to start there). */
static cb_status join(cb_ssi_curve *out, const cb_bool_cut *k, int first, int last,
                      const cb_ssi_curve *src)
{
    slong n = 1;
    for (int c = first; c <= last; c++)
        n += k[c].n - 1;
    cb_ssi_point *p = malloc((size_t)n * sizeof *p);
    if (!p)
        return CB_ERR_NOMEM;
    slong m = 0;
    for (int c = first; c <= last; c++)
        for (int i = c == first ? 0 : 1; i < k[c].n; i++, m++) {
            memcpy(p[m].xyz, k[c].xyz + 3 * i, sizeof p[m].xyz);
            memcpy(p[m].uv_a, k[c].uv[0] + 2 * i, sizeof p[m].uv_a);
            memcpy(p[m].uv_b, k[c].uv[1] + 2 * i, sizeof p[m].uv_b);
        }
    memset(out, 0, sizeof *out);
    out->n = n;
    out->pt = p;
    out->face_a = src->face_a;
    out->face_b = src->face_b;
    out->tangential = k[first].tangential;
    out->certified = src->certified;
    out->closed = k[first].closed ||
                  (src->closed && !memcmp(p[0].xyz, p[n - 1].xyz, sizeof p[0].xyz));
    return CB_OK;
}

/* The curves of r replaced by those of cuts (in order, consecutive pieces of one curve
 * joined). */
static cb_status take_cuts(cb_ssi_result_struct *r, const cb_bool_cuts *cuts)
{
    cb_ssi_curve *cv = malloc((size_t)(cuts->n + 1) * sizeof *cv);
    if (!cv)
        return CB_ERR_NOMEM;
    slong n = 0;
    cb_status st = CB_OK;
    for (int c = 0; c < cuts->n && !st;) {
        const cb_bool_cut *k = cuts->cut + c;
        int last = c;
        while (last + 1 < cuts->n && continues(cuts->cut + last, cuts->cut + last + 1))
            last++;
        if (k->curve >= 0) {
            st = join(cv + n, cuts->cut, c, last, r->curve + k->curve);
            n += st == CB_OK;
        }
        c = last + 1;
    }
    if (st) {
        for (slong i = 0; i < n; i++)
            free(cv[i].pt);
        free(cv);
        return st;
    }
    for (slong i = 0; i < r->n_curves; i++)
        free(r->curve[i].pt);
    free(r->curve);
    r->curve = cv;
    r->n_curves = n;
    r->alloc_curves = cuts->n + 1;
    return CB_OK;
}

cb_status cb_bool_ssi_trim(cb_ssi_result_struct *r, const cb_topo_body *A, const cb_topo_body *B,
                           double tol, cb_error *err)
{
    cb_bool_solid *S[2];
    cb_bool_cuts cuts;
    cb_status st = _cb_bool_solids_cuts(S, &cuts, r, A, B, tol, 0, err);
    if (!st && take_cuts(r, &cuts) != CB_OK)
        st = cb_error_set(err, CB_ERR_NOMEM, "ssi trim: out of memory");
    /* Isolated points: kept when inside (or on the boundary of) both faces. */
    slong m = 0;
    for (slong q = 0; q < r->n_points && !st; q++) {
        const cb_ssi_isolated *p = r->point + q;
        if (cb_face_classify_uv(cb_bool_solid_face(S[0], p->face_a), p->p.uv_a[0],
                                p->p.uv_a[1], tol) != CB_FACE_OUT &&
            cb_face_classify_uv(cb_bool_solid_face(S[1], p->face_b), p->p.uv_b[0],
                                p->p.uv_b[1], tol) != CB_FACE_OUT)
            r->point[m++] = *p;
    }
    if (!st)
        r->n_points = m;
    cb_bool_cuts_clear(&cuts);
    cb_bool_solid_free(S[0]);
    cb_bool_solid_free(S[1]);
    return st;
}
