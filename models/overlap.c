/* overlap.c — volumes of two solids and of their common part by integrating, over a jittered
 * grid of vertical lines, the lengths the lines spend inside each solid (cb_model_overlap_estimate
 * in models.h). Independent of the Boolean code: it needs only ray/face intersections. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "brep/face.h"
#include "brep/parallel.h"
#include "models/models.h"

enum { MAX_HITS = 256, MAX_TRIES = 8 };

/* A prepared body: its faces and their boxes. */
typedef struct {
    cb_face *faces;
    cb_aabb *boxes;
    int n;
    double tol;
} solid;

static void solid_clear(solid *s)
{
    for (int k = 0; k < s->n; k++)
        cb_face_clear(s->faces + k);
    free(s->faces);
    free(s->boxes);
    memset(s, 0, sizeof *s);
}

static cb_status solid_init(solid *s, const cb_topo_body *b, cb_error *err)
{
    memset(s, 0, sizeof *s);
    s->tol = b->tol;
    s->faces = calloc((size_t)(b->n_faces + 1), sizeof *s->faces);
    s->boxes = calloc((size_t)(b->n_faces + 1), sizeof *s->boxes);
    if (!s->faces || !s->boxes) {
        solid_clear(s);
        return cb_error_set(err, CB_ERR_NOMEM, "overlap estimate: out of memory");
    }
    for (int k = 0; k < b->n_faces; k++) {
        cb_status st = cb_face_init(s->faces + k, b, k, b->tol, err);
        if (st) {
            solid_clear(s);
            return cb_error_prefix(err, "overlap estimate: face %d: ", k);
        }
        s->n++;
        cb_face_box(s->boxes + k, s->faces + k);
    }
    return CB_OK;
}

/* The parameters where the vertical line through (x, y) enters and leaves the solid, sorted,
 * in t (z = z0 + t); their count, or -1 when the line cannot be trusted: a hit grazes or lies
 * on an edge, or the crossings do not alternate in, out, in, out (a missed root). */
static int line_hits(double *t, const solid *s, double x, double y, double z0, double len,
                     double graze)
{
    const double o[3] = {x, y, z0}, d[3] = {0, 0, 1};
    cb_face_hit h[MAX_HITS];
    double cosv[MAX_HITS];
    int n = 0;
    for (int k = 0; k < s->n; k++) {
        const cb_aabb *b = s->boxes + k;
        if (x < b->lo[0] - s->tol || x > b->hi[0] + s->tol || y < b->lo[1] - s->tol ||
            y > b->hi[1] + s->tol)
            continue;
        int m = cb_face_ray(h, MAX_HITS, s->faces + k, o, d, 0, len, s->tol, graze);
        if (m > MAX_HITS || n + m > MAX_HITS)
            return -1;
        for (int j = 0; j < m; j++) {
            if (h[j].kind != CB_FACE_HIT_CROSS)
                return -1;
            t[n] = h[j].t;
            cosv[n++] = h[j].cos;
        }
    }
    /* Sort t with its cosines: few hits, so insertion sort. */
    for (int i = 1; i < n; i++)
        for (int j = i; j > 0 && t[j] < t[j - 1]; j--) {
            double a = t[j];
            t[j] = t[j - 1];
            t[j - 1] = a;
            a = cosv[j];
            cosv[j] = cosv[j - 1];
            cosv[j - 1] = a;
        }
    if (n % 2)
        return -1;
    for (int j = 0; j < n; j++)
        if ((j % 2 == 0) != (cosv[j] < 0))
            return -1;
    return n;
}

/* Length of the union of intervals [a0,a1], [a2,a3], ... intersected with [b0,b1], ... */
static double common_length(const double *a, int na, const double *b, int nb)
{
    double len = 0;
    for (int i = 0; i < na; i += 2)
        for (int j = 0; j < nb; j += 2)
            len += fmax(0, fmin(a[i + 1], b[j + 1]) - fmax(a[i], b[j]));
    return len;
}

static double total_length(const double *a, int n)
{
    double len = 0;
    for (int i = 0; i < n; i += 2)
        len += a[i + 1] - a[i];
    return len;
}

/* A uniform number in [0, 1) from the cell and the attempt (splitmix64): the same samples on
 * any number of threads. */
static double jitter(uint64_t key)
{
    uint64_t z = key + 0x9e3779b97f4a7c15ull;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    z ^= z >> 31;
    return (double)(z >> 11) * 0x1p-53;
}

typedef struct {
    const solid *s[2];
    double x0, y0, hx, hy, z0, len, graze;
    int n;
    double (*f)[3]; /* per cell: length in A, in B, in both */
    int *tries;     /* per cell: attempts used; MAX_TRIES + 1 when every one failed */
} sweep;

static void sweep_rows(void *ctx, size_t begin, size_t end)
{
    sweep *w = ctx;
    double ta[MAX_HITS], tb[MAX_HITS];
    for (size_t i = begin; i < end; i++)
        for (int j = 0; j < w->n; j++) {
            size_t c = i * (size_t)w->n + (size_t)j;
            w->tries[c] = MAX_TRIES + 1;
            for (int a = 0; a < MAX_TRIES; a++) {
                uint64_t key = ((uint64_t)c * MAX_TRIES + (uint64_t)a) * 2;
                double x = w->x0 + w->hx * ((double)i + jitter(key));
                double y = w->y0 + w->hy * ((double)j + jitter(key + 1));
                int na = line_hits(ta, w->s[0], x, y, w->z0, w->len, w->graze);
                int nb = na < 0 ? -1 : line_hits(tb, w->s[1], x, y, w->z0, w->len, w->graze);
                if (nb < 0)
                    continue;
                w->f[c][0] = total_length(ta, na);
                w->f[c][1] = total_length(tb, nb);
                w->f[c][2] = common_length(ta, na, tb, nb);
                w->tries[c] = a + 1;
                break;
            }
        }
}

cb_status cb_model_overlap_estimate(cb_overlap_estimate *e, const cb_topo_body *A,
                                    const cb_topo_body *B, int n, int threads, cb_error *err)
{
    memset(e, 0, sizeof *e);
    if (n < 2 || n % 2 || n > 20000)
        return cb_error_set(err, CB_ERR_INVALID,
                            "overlap estimate: grid size %d is not an even number in [2, 20000]", n);
    solid s[2];
    cb_status st = solid_init(s, A, err);
    if (st)
        return st;
    st = solid_init(s + 1, B, err);
    if (st) {
        solid_clear(s);
        return st;
    }
    cb_aabb box[2];
    cb_topo_body_edge_box(box, A);
    cb_topo_body_edge_box(box + 1, B);
    /* The faces' boxes hold the faces (cb_face_box); the edge boxes may not. */
    for (int k = 0; k < 2; k++)
        for (int f = 0; f < s[k].n; f++)
            for (int i = 0; i < 3; i++) {
                box[k].lo[i] = fmin(box[k].lo[i], s[k].boxes[f].lo[i]);
                box[k].hi[i] = fmax(box[k].hi[i], s[k].boxes[f].hi[i]);
            }
    sweep w;
    memset(&w, 0, sizeof w);
    w.s[0] = s;
    w.s[1] = s + 1;
    w.n = n;
    /* The rectangle holding the xy shadow of both solids, so that V(A) and V(B) are whole. */
    w.x0 = fmin(box[0].lo[0], box[1].lo[0]);
    w.y0 = fmin(box[0].lo[1], box[1].lo[1]);
    w.hx = (fmax(box[0].hi[0], box[1].hi[0]) - w.x0) / n;
    w.hy = (fmax(box[0].hi[1], box[1].hi[1]) - w.y0) / n;
    double zlo = fmin(box[0].lo[2], box[1].lo[2]), zhi = fmax(box[0].hi[2], box[1].hi[2]);
    w.z0 = zlo - 0.01 * (zhi - zlo) - 1;
    w.len = zhi + 0.01 * (zhi - zlo) + 1 - w.z0;
    w.graze = CB_OVERLAP_GRAZE_COS;
    w.f = calloc((size_t)n * (size_t)n, sizeof *w.f);
    w.tries = calloc((size_t)n * (size_t)n, sizeof *w.tries);
    if (!w.f || !w.tries)
        st = cb_error_set(err, CB_ERR_NOMEM, "overlap estimate: out of memory");
    if (!st)
        st = cb_parallel_for((size_t)n, 1, threads, sweep_rows, &w);
    if (st && st != CB_ERR_NOMEM)
        cb_error_set(err, st, "overlap estimate: the parallel sweep failed");
    else if (st)
        cb_error_set(err, st, "overlap estimate: out of memory");
    double area = w.hx * w.hy, sum[3] = {0, 0, 0}, var[3] = {0, 0, 0};
    for (size_t c = 0; !st && c < (size_t)n * (size_t)n; c++) {
        if (w.tries[c] > MAX_TRIES) {
            st = cb_error_set(err, CB_ERR_NUMERIC,
                              "overlap estimate: %d lines through cell (%zu, %zu) all graze, "
                              "touch an edge or miss a crossing",
                              MAX_TRIES, c / (size_t)n, c % (size_t)n);
            break;
        }
        e->retries += w.tries[c] - 1;
        for (int k = 0; k < 3; k++) {
            sum[k] += w.f[c][k];
            /* One sample per cell: the variance of cells 2i and 2i + 1 of a column together is
             * at most their squared difference in expectation (plus the squared difference of
             * their means), so the sum over pairs bounds the estimator's variance. */
            if (c % 2)
                var[k] += (w.f[c][k] - w.f[c - 1][k]) * (w.f[c][k] - w.f[c - 1][k]);
        }
    }
    if (!st) {
        e->lines = (long)n * n + e->retries;
        e->volume_a = area * sum[0];
        e->volume_b = area * sum[1];
        e->volume_ab = area * sum[2];
        e->sigma_a = area * sqrt(var[0]);
        e->sigma_b = area * sqrt(var[1]);
        e->sigma_ab = area * sqrt(var[2]);
    }
    free(w.f);
    free(w.tries);
    solid_clear(s);
    solid_clear(s + 1);
    return st;
}
