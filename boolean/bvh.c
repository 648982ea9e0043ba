/* Bounding volume hierarchy over boxes and the broad phase of face pairs. */
#include <stdlib.h>
#include <string.h>

#include "boolean/bool.h"

enum { LEAF_SIZE = 4, STACK = 128 };

typedef struct {
    const cb_aabb *boxes;
    int axis;
} sort_ctx;

static double centre(const cb_aabb *b, int i) { return 0.5 * (b->lo[i] + b->hi[i]); }

/* Sorts idx[0..n) by box centre along axis, ties by index (deterministic). Insertion sort
 * below 16 items, merge sort above: qsort has no context argument in C11. */
static void sort_items(int *idx, int *tmp, int n, const cb_aabb *boxes, int axis)
{
    if (n < 16) {
        for (int i = 1; i < n; i++) {
            int x = idx[i], j = i - 1;
            double cx = centre(&boxes[x], axis);
            while (j >= 0) {
                double cj = centre(&boxes[idx[j]], axis);
                if (cj < cx || (cj == cx && idx[j] < x))
                    break;
                idx[j + 1] = idx[j];
                j--;
            }
            idx[j + 1] = x;
        }
        return;
    }
    int h = n / 2;
    sort_items(idx, tmp, h, boxes, axis);
    sort_items(idx + h, tmp, n - h, boxes, axis);
    int i = 0, j = h, k = 0;
    while (i < h || j < n) {
        int take_left = j >= n;
        if (i < h && j < n) {
            double a = centre(&boxes[idx[i]], axis), b = centre(&boxes[idx[j]], axis);
            take_left = a < b || (a == b && idx[i] < idx[j]);
        }
        tmp[k++] = take_left && i < h ? idx[i++] : idx[j++];
    }
    memcpy(idx, tmp, (size_t)n * sizeof *idx);
}

static void box_of(cb_aabb *out, const cb_bool_bvh *t, int first, int count)
{
    for (int i = 0; i < 3; i++) {
        out->lo[i] = HUGE_VAL;
        out->hi[i] = -HUGE_VAL;
    }
    for (int k = first; k < first + count; k++) {
        const cb_aabb *b = &t->boxes[t->order[k]];
        for (int i = 0; i < 3; i++) {
            out->lo[i] = fmin(out->lo[i], b->lo[i]);
            out->hi[i] = fmax(out->hi[i], b->hi[i]);
        }
    }
}

static int build(cb_bool_bvh *t, int *tmp, int first, int count)
{
    int id = t->n_nodes++;
    cb_bool_bvh_node *nd = &t->nodes[id];
    box_of(&nd->box, t, first, count);
    nd->first = first;
    nd->count = count;
    nd->left = nd->right = -1;
    if (count <= LEAF_SIZE)
        return id;
    double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    for (int k = first; k < first + count; k++)
        for (int i = 0; i < 3; i++) {
            double c = centre(&t->boxes[t->order[k]], i);
            lo[i] = fmin(lo[i], c);
            hi[i] = fmax(hi[i], c);
        }
    int axis = 0;
    for (int i = 1; i < 3; i++)
        if (hi[i] - lo[i] > hi[axis] - lo[axis])
            axis = i;
    sort_items(t->order + first, tmp, count, t->boxes, axis);
    int h = count / 2;
    int left = build(t, tmp, first, h);
    int right = build(t, tmp, first + h, count - h);
    t->nodes[id].left = left;
    t->nodes[id].right = right;
    return id;
}

void cb_bool_bvh_clear(cb_bool_bvh *t)
{
    free(t->nodes);
    free(t->order);
    free(t->boxes);
    memset(t, 0, sizeof *t);
}

cb_status cb_bool_bvh_init(cb_bool_bvh *t, const cb_aabb *boxes, int n, cb_error *err)
{
    memset(t, 0, sizeof *t);
    if (n < 0)
        return cb_error_set(err, CB_ERR_INVALID, "bvh: %d boxes", n);
    for (int k = 0; k < n; k++)
        for (int i = 0; i < 3; i++)
            if (isnan(boxes[k].lo[i]) || isnan(boxes[k].hi[i]))
                return cb_error_set(err, CB_ERR_INVALID, "bvh: box %d has a NaN coordinate", k);
    size_t m = n ? (size_t)n : 1;
    t->nodes = malloc(2 * m * sizeof *t->nodes);
    t->order = malloc(m * sizeof *t->order);
    t->boxes = malloc(m * sizeof *t->boxes);
    int *tmp = malloc(m * sizeof *tmp);
    if (!t->nodes || !t->order || !t->boxes || !tmp) {
        free(tmp);
        cb_bool_bvh_clear(t);
        return cb_error_set(err, CB_ERR_NOMEM, "bvh: out of memory for %d boxes", n);
    }
    if (n)
        memcpy(t->boxes, boxes, (size_t)n * sizeof *boxes);
    t->n_items = n;
    for (int k = 0; k < n; k++)
        t->order[k] = k;
    if (n)
        build(t, tmp, 0, n);
    free(tmp);
    return CB_OK;
}

static int int_cmp(const void *x, const void *y)
{
    int a = *(const int *)x, b = *(const int *)y;
    return (a > b) - (a < b);
}

/* Entry test of the segment in box b grown by tol. */
static int seg_meets(const cb_aabb *b, const double o[3], const double d[3], double s0,
                     double s1, double tol)
{
    for (int i = 0; i < 3; i++) {
        double lo = b->lo[i] - tol, hi = b->hi[i] + tol;
        if (d[i] == 0) {
            if (o[i] < lo || o[i] > hi)
                return 0;
            continue;
        }
        double a = (lo - o[i]) / d[i], c = (hi - o[i]) / d[i];
        s0 = fmax(s0, fmin(a, c));
        s1 = fmin(s1, fmax(a, c));
        if (s0 > s1)
            return 0;
    }
    return 1;
}

/* Traversal shared by both queries: ray NULL for the box query. */
static int query(int *out, int max, const cb_bool_bvh *t, const cb_aabb *box, const double *o,
                 const double *d, double s0, double s1, double tol)
{
    if (!t->n_items)
        return 0;
    int stack[STACK], top = 0, n = 0;
    stack[top++] = 0;
    while (top) {
        const cb_bool_bvh_node *nd = &t->nodes[stack[--top]];
        int hit = o ? seg_meets(&nd->box, o, d, s0, s1, tol) : cb_aabb_overlap(&nd->box, box, tol);
        if (!hit)
            continue;
        if (nd->left < 0) {
            for (int k = nd->first; k < nd->first + nd->count; k++) {
                int it = t->order[k];
                const cb_aabb *b = &t->boxes[it];
                int h = o ? seg_meets(b, o, d, s0, s1, tol) : cb_aabb_overlap(b, box, tol);
                if (h) {
                    if (n < max)
                        out[n] = it;
                    n++;
                }
            }
            continue;
        }
        /* The depth of a median split tree is log2(n / LEAF_SIZE) + 1, far below STACK. */
        stack[top++] = nd->right;
        stack[top++] = nd->left;
    }
    qsort(out, (size_t)(n < max ? n : max), sizeof *out, int_cmp);
    return n;
}

int cb_bool_bvh_query_box(int *out, int max, const cb_bool_bvh *t, const cb_aabb *box,
                          double tol)
{
    return query(out, max, t, box, NULL, NULL, 0, 0, tol);
}

int cb_bool_bvh_query_ray(int *out, int max, const cb_bool_bvh *t, const double o[3],
                          const double d[3], double s0, double s1, double tol)
{
    return query(out, max, t, NULL, o, d, s0, s1, tol);
}

/* ---------------------------------------------------------------- broad phase -------------- */

cb_status cb_bool_box_pairs(int **pairs, int *n, const cb_aabb *a, int na, const cb_aabb *b,
                            int nb, double tol, cb_error *err)
{
    *pairs = NULL;
    *n = 0;
    cb_bool_bvh t;
    cb_status st = cb_bool_bvh_init(&t, b, nb, err);
    if (st)
        return st;
    int cap = 0, m = 0, *out = NULL;
    int *buf = malloc((size_t)(nb ? nb : 1) * sizeof *buf);
    if (!buf)
        st = cb_error_set(err, CB_ERR_NOMEM, "face pairs: out of memory");
    for (int i = 0; i < na && !st; i++) {
        int k = cb_bool_bvh_query_box(buf, nb, &t, &a[i], tol);
        if (m + k > cap) {
            int c = cap ? cap : 64;
            while (c < m + k)
                c *= 2;
            int *p = realloc(out, (size_t)c * 2 * sizeof *p);
            if (!p) {
                st = cb_error_set(err, CB_ERR_NOMEM, "face pairs: out of memory");
                break;
            }
            out = p;
            cap = c;
        }
        for (int j = 0; j < k; j++) {
            out[2 * m] = i;
            out[2 * m + 1] = buf[j];
            m++;
        }
    }
    free(buf);
    cb_bool_bvh_clear(&t);
    if (st) {
        free(out);
        return st;
    }
    *pairs = out;
    *n = m;
    return CB_OK;
}

cb_status cb_bool_face_boxes(cb_aabb *boxes, const cb_topo_body *b, double prep_tol,
                             cb_error *err)
{
    for (int k = 0; k < b->n_faces; k++) {
        cb_face f;
        cb_status st = cb_face_init(&f, b, k, prep_tol, err);
        if (st)
            return st;
        cb_face_box(&boxes[k], &f);
        cb_face_clear(&f);
    }
    return CB_OK;
}

cb_status cb_bool_face_pairs(int **pairs, int *n, const cb_topo_body *A, const cb_topo_body *B,
                             double tol, cb_error *err)
{
    *pairs = NULL;
    *n = 0;
    cb_aabb *ba = malloc((size_t)(A->n_faces + 1) * sizeof *ba);
    cb_aabb *bb = malloc((size_t)(B->n_faces + 1) * sizeof *bb);
    cb_status st = CB_OK;
    if (!ba || !bb)
        st = cb_error_set(err, CB_ERR_NOMEM, "face pairs: out of memory");
    if (!st && (st = cb_bool_face_boxes(ba, A, A->tol > 0 ? A->tol : tol, err)))
        cb_error_prefix(err, "face pairs: first body: ");
    if (!st && (st = cb_bool_face_boxes(bb, B, B->tol > 0 ? B->tol : tol, err)))
        cb_error_prefix(err, "face pairs: second body: ");
    if (!st)
        st = cb_bool_box_pairs(pairs, n, ba, A->n_faces, bb, B->n_faces, tol, err);
    free(ba);
    free(bb);
    return st;
}
