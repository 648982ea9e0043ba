/* The arrangement of polylines, first stage (boolean/arrange.h): validation, a uniform grid
 * and snapping. The polylines become sites: their points, the projections of points onto
 * segments within snap_tol, the crossings of segments. Sites within snap_tol merge into nodes;
 * the runs of polyline between consecutive sites become runs between nodes, split further
 * until drawn straight they form a planar graph; arrange_face.c turns them into pieces and
 * regions. */
#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "boolean/arrange.h"

/* A crossing this close (in snap_tol) to a segment end is left to the snapping of that end:
 * below 1 so that the end is then surely within snap_tol of the other segment. */
#define CROSS_NEAR_END 0.5

typedef struct {
    int poly, seg; /* polyline; segment (point index for a point of the polyline) */
    double t;      /* fraction along the segment, in [0, 1] */
    int free_end;  /* an end of an open polyline: the last choice for a node's point */
    double xy[2];  /* scaled */
    double uv[2];
} site;

typedef struct {
    int i, j;
    double d;
} link;

typedef struct {
    double x0, y0, h;
    int nx, ny;
    int *start, *item; /* cell c holds item[start[c] .. start[c + 1]) */
} grid;

typedef struct {
    int *v;
    int n, cap;
} ibuf;

typedef struct {
    const cb_arr_polyline *in;
    int n_in;
    double sc[2], tol, margin;
    int *first; /* n_in + 1 offsets of the polylines' points */
    int n_pts;
    double *xy; /* scaled points */
    int n_seg;
    int *seg_v;  /* segment g runs from point seg_v[g] to seg_v[g] + 1 ... */
    int *seg_p;  /* ... of polyline seg_p[g] */
    grid sg, pg; /* over segments (within margin), over sites */
    site *sites;
    int n_sites, cap_sites;
    link *links;
    long n_links, cap_links;
    ibuf cells;
} work;

/* ---------------------------------------------------------------- small tools ------------- */

void cb_arr_init(cb_arr *a) { memset(a, 0, sizeof *a); }

void cb_arr_clear(cb_arr *a)
{
    for (int k = 0; k < a->n_pieces; k++) {
        free(a->piece[k].uv);
        free(a->piece[k].src);
    }
    free(a->piece);
    free(a->vertex_uv);
    free(a->region);
    free(a->cycle_pool);
    free(a->use_pool);
    cb_arr_init(a);
}

static int ibuf_push(ibuf *b, int x)
{
    if (b->n == b->cap) {
        int cap = b->cap ? 2 * b->cap : 64;
        int *v = realloc(b->v, (size_t)cap * sizeof *v);
        if (!v)
            return -1;
        b->v = v;
        b->cap = cap;
    }
    b->v[b->n++] = x;
    return 0;
}

/* Appends a site at fraction t of segment seg of polyline p; returns its index, -1 on NOMEM. */
static int push_site(work *w, int p, int seg, double t)
{
    if (w->n_sites == w->cap_sites) {
        if (w->cap_sites > INT_MAX / 2)
            return -1;
        int cap = 2 * w->cap_sites;
        site *s = realloc(w->sites, (size_t)cap * sizeof *s);
        if (!s)
            return -1;
        w->sites = s;
        w->cap_sites = cap;
    }
    site *s = &w->sites[w->n_sites];
    const double *a = w->in[p].uv + 2 * seg, *A = w->xy + 2 * (w->first[p] + seg);
    s->poly = p;
    s->seg = seg;
    s->t = t;
    s->free_end = 0;
    for (int i = 0; i < 2; i++) {
        /* Both from the segment's own ends, so a split point is on the segment up to rounding
         * in either plane. */
        s->uv[i] = t == 0 ? a[i] : a[i] + t * (a[i + 2] - a[i]);
        s->xy[i] = t == 0 ? A[i] : A[i] + t * (A[i + 2] - A[i]);
    }
    return w->n_sites++;
}

static int push_link(work *w, int i, int j, double d)
{
    if (w->n_links == w->cap_links) {
        long cap = w->cap_links ? 2 * w->cap_links : 1024;
        link *l = realloc(w->links, (size_t)cap * sizeof *l);
        if (!l)
            return -1;
        w->links = l;
        w->cap_links = cap;
    }
    w->links[w->n_links++] = (link){i, j, d};
    return 0;
}

/* sqrt, not hypot: several times faster, and coordinates squared overflow only beyond 1e154. */
static double dist(const double *a, const double *b)
{
    double dx = a[0] - b[0], dy = a[1] - b[1];
    return sqrt(dx * dx + dy * dy);
}

/* Twice the signed area of abc: > 0 when c is left of a -> b. */
static double orient(const double *a, const double *b, const double *c)
{
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

/* ---------------------------------------------------------------- grid --------------------- */

static int cell_of(double x0, double h, int n, double x)
{
    double f = floor((x - x0) / h);
    return f < 0 ? 0 : f >= n ? n - 1 : (int)f;
}

static int cell_at(const grid *G, const double *p)
{
    return cell_of(G->y0, G->h, G->ny, p[1]) * G->nx + cell_of(G->x0, G->h, G->nx, p[0]);
}

/* Cells near n items over [x0, x1] x [y0, y1], at least tol wide so that points within tol of
 * each other lie in neighbouring cells, and at most about 4 n of them. */
static void grid_shape(grid *G, double x0, double y0, double x1, double y1, int n, double tol)
{
    double W = x1 - x0, H = y1 - y0, h = fmax(sqrt(W * H / (n + 1.0)), tol);
    for (;;) {
        double fx = fmax(1, ceil(W / h)), fy = fmax(1, ceil(H / h));
        if (fx * fy <= 4.0 * n + 64) {
            G->nx = (int)fx;
            G->ny = (int)fy;
            break;
        }
        h *= 1.5;
    }
    G->x0 = x0;
    G->y0 = y0;
    G->h = h;
}

/* The cells that hold points within m of segment ab, row by row: the segment clipped to the
 * row's band grown by m, its x range grown by m. */
static int seg_cells(ibuf *out, const grid *G, const double *a, const double *b, double m)
{
    out->n = 0;
    int r0 = cell_of(G->y0, G->h, G->ny, fmin(a[1], b[1]) - m);
    int r1 = cell_of(G->y0, G->h, G->ny, fmax(a[1], b[1]) + m);
    double dx = b[0] - a[0], dy = b[1] - a[1];
    for (int r = r0; r <= r1; r++) {
        double lo = G->y0 + r * G->h - m, hi = G->y0 + (r + 1) * G->h + m, t0 = 0, t1 = 1;
        if (dy != 0) {
            double s0 = (lo - a[1]) / dy, s1 = (hi - a[1]) / dy;
            if (s0 > s1) {
                double s = s0;
                s0 = s1;
                s1 = s;
            }
            t0 = fmax(0, s0);
            t1 = fmin(1, s1);
            if (t0 > t1) /* missed by rounding only: the rows come from the segment's range */
                t0 = t1 = s1 < 0 ? 0 : 1;
        }
        double xa = a[0] + t0 * dx, xb = a[0] + t1 * dx;
        int c0 = cell_of(G->x0, G->h, G->nx, fmin(xa, xb) - m);
        int c1 = cell_of(G->x0, G->h, G->nx, fmax(xa, xb) + m);
        for (int c = c0; c <= c1; c++)
            if (ibuf_push(out, r * G->nx + c))
                return -1;
    }
    return 0;
}

/* Fills G's cells (shape already set) with items 0 .. n - 1, item k in the cells within m of
 * the segment seg[4k .. 4k + 4) (a point when both ends agree: m = 0 puts it in its own cell),
 * as compressed rows. -1 on NOMEM. */
static int grid_fill(grid *G, ibuf *cells, const double *seg, int n, double m)
{
    int nc = G->nx * G->ny;
    G->start = calloc((size_t)nc + 1, sizeof *G->start);
    G->item = NULL;
    if (!G->start)
        return -1;
    long total = 0;
    for (int pass = 0; pass < 2; pass++) {
        for (int k = 0; k < n; k++) {
            if (seg_cells(cells, G, seg + 4 * k, seg + 4 * k + 2, m))
                return -1;
            for (int i = 0; i < cells->n; i++) {
                if (pass == 0)
                    G->start[cells->v[i] + 1]++;
                else
                    G->item[G->start[cells->v[i]]++] = k;
            }
            total += cells->n;
        }
        if (pass == 0) {
            if (total > INT_MAX / 2)
                return -1;
            for (int c = 0; c < nc; c++)
                G->start[c + 1] += G->start[c];
            G->item = malloc((size_t)(total + 1) * sizeof *G->item);
            if (!G->item)
                return -1;
        } else { /* the fill advanced each start to the next cell's: shift back */
            memmove(G->start + 1, G->start, (size_t)nc * sizeof *G->start);
            G->start[0] = 0;
        }
    }
    return 0;
}

/* Segments into the cells within margin of them. */
static int grid_segments(work *w)
{
    double *seg = malloc((size_t)(4 * w->n_seg + 1) * sizeof *seg);
    if (!seg)
        return -1;
    for (int g = 0; g < w->n_seg; g++)
        memcpy(seg + 4 * g, w->xy + 2 * w->seg_v[g], 4 * sizeof *seg);
    int r = grid_fill(&w->sg, &w->cells, seg, w->n_seg, w->margin);
    free(seg);
    return r;
}

/* Points (2 coordinates each) into their cells of a grid shaped as G. */
static int grid_points(grid *out, const grid *G, ibuf *cells, const double *xy, int n)
{
    *out = *G;
    out->start = out->item = NULL;
    double *seg = malloc((size_t)(4 * n + 1) * sizeof *seg);
    if (!seg)
        return -1;
    for (int k = 0; k < n; k++) {
        memcpy(seg + 4 * k, xy + 2 * k, 2 * sizeof *seg);
        memcpy(seg + 4 * k + 2, xy + 2 * k, 2 * sizeof *seg);
    }
    int r = grid_fill(out, cells, seg, n, 0);
    free(seg);
    return r;
}

static int grid_sites(work *w)
{
    double *xy = malloc((size_t)(2 * w->n_sites + 1) * sizeof *xy);
    if (!xy)
        return -1;
    for (int s = 0; s < w->n_sites; s++)
        memcpy(xy + 2 * s, w->sites[s].xy, 2 * sizeof *xy);
    int r = grid_points(&w->pg, &w->sg, &w->cells, xy, w->n_sites);
    free(xy);
    return r;
}

/* ---------------------------------------------------------------- sites -------------------- */

/* Every point against the segments near it: joined to a segment end within tol, else split
 * onto the segment at its projection. The segments adjacent to the point are skipped. */
static int snap_points(work *w)
{
    double tol = w->tol;
    for (int p = 0; p < w->n_in; p++)
        for (int k = 0; k < w->in[p].n; k++) {
            int v = w->first[p] + k, c = cell_at(&w->sg, w->xy + 2 * v);
            const double *V = w->xy + 2 * v;
            for (int e = w->sg.start[c]; e < w->sg.start[c + 1]; e++) {
                int g = w->sg.item[e], q = w->seg_p[g], a = w->seg_v[g], ka = a - w->first[q];
                if (q == p && (ka == k || ka == k - 1))
                    continue;
                const double *A = w->xy + 2 * a, *B = A + 2;
                double ex = B[0] - A[0], ey = B[1] - A[1], L2 = ex * ex + ey * ey;
                double t = L2 > 0 ? ((V[0] - A[0]) * ex + (V[1] - A[1]) * ey) / L2 : 0;
                t = fmin(1, fmax(0, t));
                double P[2] = {A[0] + t * ex, A[1] + t * ey}, d = dist(V, P);
                if (d > tol)
                    continue;
                double da = dist(V, A), db = dist(V, B);
                if (da <= tol || db <= tol) {
                    if (push_link(w, v, da <= db ? a : a + 1, fmin(da, db)))
                        return -1;
                    continue;
                }
                int s = push_site(w, q, ka, t);
                if (s < 0 || push_link(w, v, s, d))
                    return -1;
            }
        }
    return 0;
}

/* Proper crossings of segments, away from their ends, as a pair of sites (one on each). */
static int cross_segments(work *w)
{
    int *mark = malloc((size_t)(w->n_seg + 1) * sizeof *mark);
    if (!mark)
        return -1;
    for (int g = 0; g < w->n_seg; g++)
        mark[g] = -1;
    double near = CROSS_NEAR_END * w->tol;
    for (int i = 0; i < w->n_seg; i++) {
        const double *ai = w->xy + 2 * w->seg_v[i], *bi = ai + 2;
        if (ai[0] == bi[0] && ai[1] == bi[1])
            continue;
        if (seg_cells(&w->cells, &w->sg, ai, bi, w->margin)) {
            free(mark);
            return -1;
        }
        for (int k = 0; k < w->cells.n; k++) {
            int c = w->cells.v[k];
            for (int e = w->sg.start[c]; e < w->sg.start[c + 1]; e++) {
                int j = w->sg.item[e];
                if (j <= i || mark[j] == i)
                    continue;
                mark[j] = i;
                const double *aj = w->xy + 2 * w->seg_v[j], *bj = aj + 2;
                double d1 = orient(aj, bj, ai), d2 = orient(aj, bj, bi);
                if (!((d1 < 0 && d2 > 0) || (d1 > 0 && d2 < 0)))
                    continue;
                double d3 = orient(ai, bi, aj), d4 = orient(ai, bi, bj);
                if (!((d3 < 0 && d4 > 0) || (d3 > 0 && d4 < 0)))
                    continue;
                double ti = d1 / (d1 - d2), tj = d3 / (d3 - d4);
                double X[2] = {ai[0] + ti * (bi[0] - ai[0]), ai[1] + ti * (bi[1] - ai[1])};
                double Y[2] = {aj[0] + tj * (bj[0] - aj[0]), aj[1] + tj * (bj[1] - aj[1])};
                /* Collinear segments pass the sign tests on rounding noise, with meaningless
                 * fractions: the two points then disagree. Their touching is the snapping's. */
                if (dist(X, Y) > near || dist(X, ai) <= near || dist(X, bi) <= near ||
                    dist(X, aj) <= near || dist(X, bj) <= near)
                    continue;
                int pi = w->seg_p[i], pj = w->seg_p[j];
                int si = push_site(w, pi, w->seg_v[i] - w->first[pi], ti);
                int sj = si < 0 ? -1 : push_site(w, pj, w->seg_v[j] - w->first[pj], tj);
                if (sj < 0 || push_link(w, si, sj, 0)) {
                    free(mark);
                    return -1;
                }
            }
        }
    }
    free(mark);
    return 0;
}

/* Every pair of sites within tol. */
static int near_sites(work *w)
{
    const grid *G = &w->pg;
    for (int s = 0; s < w->n_sites; s++) {
        const double *P = w->sites[s].xy;
        int cx = cell_of(G->x0, G->h, G->nx, P[0]), cy = cell_of(G->y0, G->h, G->ny, P[1]);
        for (int y = cy - 1; y <= cy + 1; y++)
            for (int x = cx - 1; x <= cx + 1; x++) {
                if (x < 0 || y < 0 || x >= G->nx || y >= G->ny)
                    continue;
                int c = y * G->nx + x;
                for (int e = G->start[c]; e < G->start[c + 1]; e++) {
                    int o = G->item[e];
                    double d;
                    if (o > s && (d = dist(P, w->sites[o].xy)) <= w->tol && push_link(w, s, o, d))
                        return -1;
                }
            }
    }
    return 0;
}

/* ---------------------------------------------------------------- refinement -------------- */

/* The nodes: scaled and (u,v) points. */
typedef struct {
    double *xy, *uv;
    int n, cap;
} nodes;

static int push_node(nodes *N, const double *xy, const double *uv)
{
    if (N->n == N->cap) {
        int cap = 2 * N->cap + 16;
        double *x = realloc(N->xy, (size_t)cap * 2 * sizeof *x);
        if (!x)
            return -1;
        N->xy = x;
        double *u = realloc(N->uv, (size_t)cap * 2 * sizeof *u);
        if (!u)
            return -1;
        N->uv = u;
        N->cap = cap;
    }
    memcpy(N->xy + 2 * N->n, xy, 2 * sizeof *xy);
    memcpy(N->uv + 2 * N->n, uv, 2 * sizeof *uv);
    return N->n++;
}

/* Node c splits run r at fraction t of the straight run. */
typedef struct {
    int r;
    double t;
    int c;
} hit;

typedef struct {
    hit *v;
    long n, cap;
} hits;

static int push_hit(hits *H, int r, double t, int c)
{
    if (H->n == H->cap) {
        long cap = 2 * H->cap + 64;
        hit *v = realloc(H->v, (size_t)cap * sizeof *v);
        if (!v)
            return -1;
        H->v = v;
        H->cap = cap;
    }
    H->v[H->n++] = (hit){r, t, c};
    return 0;
}

static int cmp_hit(const void *pa, const void *pb)
{
    const hit *a = pa, *b = pb;
    if (a->r != b->r)
        return a->r < b->r ? -1 : 1;
    if (a->t != b->t)
        return a->t < b->t ? -1 : 1;
    return (a->c > b->c) - (a->c < b->c);
}

/* Position along run R's polyline of the point nearest to p (scaled) on the part R covers,
 * which lies within one segment. */
static double run_pos(const work *w, const _cb_arr_run *R, const double *p)
{
    int k = (int)floor(R->pos0);
    if (k >= w->in[R->poly].n - 1 || R->pos1 <= R->pos0)
        return R->pos0;
    const double *A = w->xy + 2 * (w->first[R->poly] + k), *B = A + 2;
    double ex = B[0] - A[0], ey = B[1] - A[1], L2 = ex * ex + ey * ey;
    double t = L2 > 0 ? ((p[0] - A[0]) * ex + (p[1] - A[1]) * ey) / L2 : 0;
    return fmin(R->pos1, fmax(R->pos0, k + t));
}

/* The node of grid G nearest to p within tol, or -1. */
static int nearest_node(const grid *G, const nodes *N, const double *p, double tol)
{
    int cx = cell_of(G->x0, G->h, G->nx, p[0]), cy = cell_of(G->y0, G->h, G->ny, p[1]), best = -1;
    double bd = tol;
    for (int y = cy - 1; y <= cy + 1; y++)
        for (int x = cx - 1; x <= cx + 1; x++) {
            if (x < 0 || y < 0 || x >= G->nx || y >= G->ny)
                continue;
            int c = y * G->nx + x;
            for (int e = G->start[c]; e < G->start[c + 1]; e++) {
                double d = dist(p, N->xy + 2 * G->item[e]);
                if (d <= bd && (best < 0 || d < bd || G->item[e] < best)) {
                    bd = d;
                    best = G->item[e];
                }
            }
        }
    return best;
}

/* The hits of one round: proper crossings of runs with no common node and, when snapping,
 * the nodes within tol of a run's inside. A crossing becomes a new node; when snapping, a node
 * within tol of it takes it instead (it is then within tol of both runs), so that new nodes
 * stay tol apart and rounds in a tangle of runs do not multiply them. */
static int find_hits(work *w, nodes *N, const _cb_arr_run *run, int n_run, int snap, hits *H)
{
    grid NG = {0}, RG = w->sg;
    int ok = 0, *mark = NULL;
    double *seg = malloc((size_t)(4 * n_run + 1) * sizeof *seg);
    if (!seg)
        return -1;
    for (int r = 0; r < n_run; r++) {
        memcpy(seg + 4 * r, N->xy + 2 * run[r].n0, 2 * sizeof *seg);
        memcpy(seg + 4 * r + 2, N->xy + 2 * run[r].n1, 2 * sizeof *seg);
    }
    RG.start = RG.item = NULL;
    mark = malloc((size_t)(n_run + N->n + 1) * sizeof *mark);
    if (!mark || grid_points(&NG, &w->sg, &w->cells, N->xy, N->n) ||
        grid_fill(&RG, &w->cells, seg, n_run, w->margin))
        goto out;
    for (int k = 0; k < n_run + N->n; k++)
        mark[k] = -1;
    int *nmark = mark + n_run;
    for (int i = 0; i < n_run; i++) {
        const _cb_arr_run *R = &run[i];
        const double *A = seg + 4 * i, *B = A + 2;
        double ex = B[0] - A[0], ey = B[1] - A[1], L2 = ex * ex + ey * ey;
        if (!(L2 > 0))
            continue;
        if (seg_cells(&w->cells, &RG, A, B, w->margin))
            goto out;
        for (int k = 0; k < w->cells.n; k++) {
            int cell = w->cells.v[k];
            for (int e = NG.start[cell]; snap && e < NG.start[cell + 1]; e++) {
                int c = NG.item[e];
                if (nmark[c] == i || c == R->n0 || c == R->n1)
                    continue;
                nmark[c] = i;
                const double *C = N->xy + 2 * c;
                double t = ((C[0] - A[0]) * ex + (C[1] - A[1]) * ey) / L2;
                double P[2] = {A[0] + t * ex, A[1] + t * ey};
                if (t > 0 && t < 1 && dist(C, P) <= w->tol && push_hit(H, i, t, c))
                    goto out;
            }
            for (int e = RG.start[cell]; e < RG.start[cell + 1]; e++) {
                int j = RG.item[e];
                const _cb_arr_run *S = &run[j];
                if (j <= i || mark[j] == i || S->n0 == R->n0 || S->n0 == R->n1 || S->n1 == R->n0 ||
                    S->n1 == R->n1)
                    continue;
                mark[j] = i;
                const double *C = seg + 4 * j, *D = C + 2;
                double d1 = orient(C, D, A), d2 = orient(C, D, B);
                double d3 = orient(A, B, C), d4 = orient(A, B, D);
                if (!((d1 < 0 && d2 > 0) || (d1 > 0 && d2 < 0)) ||
                    !((d3 < 0 && d4 > 0) || (d3 > 0 && d4 < 0)))
                    continue;
                double ti = d1 / (d1 - d2), tj = d3 / (d3 - d4), X[2], Y[2], U[2];
                const double *ua = N->uv + 2 * R->n0, *ub = N->uv + 2 * R->n1;
                for (int q = 0; q < 2; q++) {
                    X[q] = A[q] + ti * (B[q] - A[q]);
                    Y[q] = C[q] + tj * (D[q] - C[q]);
                    U[q] = ua[q] + ti * (ub[q] - ua[q]);
                }
                if (dist(X, Y) > CROSS_NEAR_END * w->tol) /* collinear: as in cross_segments */
                    continue;
                int c = snap ? nearest_node(&NG, N, X, w->tol) : -1;
                if (c < 0 && (c = push_node(N, X, U)) < 0)
                    goto out;
                if ((c != R->n0 && c != R->n1 && push_hit(H, i, ti, c)) ||
                    (c != S->n0 && c != S->n1 && push_hit(H, j, tj, c)))
                    goto out;
            }
        }
    }
    ok = 1;
out:
    free(seg);
    free(mark);
    free(NG.start);
    free(NG.item);
    free(RG.start);
    free(RG.item);
    return ok ? 0 : -1;
}

/* Makes the runs, drawn straight between their nodes' points, a planar drawing. Merging moves
 * points by up to CB_ARR_CLUSTER_SPAN tol and may stop at the cap, so a node can end up on or
 * across a run it was never joined to; left so, runs overlap or cross without meeting and
 * faces come out with zero or wrong area. Rounds split runs at the nodes within tol of their
 * insides and at their crossings, until none is left or for SNAP_ROUNDS rounds (a piece of an
 * input segment never passes a node twice, which bounds them); then up to CROSS_ROUNDS rounds
 * split them at their remaining crossings only, at new nodes, which adds crossings only by
 * rounding and settles. The position of a split along the run's polyline is that of the nearest
 * point of the part the run covers. *run is reallocated. Returns 1 when crossings remain, -1 on
 * NOMEM. */
static int refine_runs(work *w, nodes *N, _cb_arr_run **run, int *n_run)
{
    enum { SNAP_ROUNDS = 16, CROSS_ROUNDS = 8 };
    hits H = {0};
    ibuf route = {0};
    _cb_arr_run *next = NULL;
    int ok = -1, *next_orig = NULL, *orig = malloc((size_t)(*n_run + 1) * sizeof *orig);
    if (!orig)
        goto out;
    for (int r = 0; r < *n_run; r++)
        orig[r] = r;
    for (int round = 0; round < SNAP_ROUNDS + CROSS_ROUNDS; round++) {
        H.n = 0;
        if (find_hits(w, N, *run, *n_run, round < SNAP_ROUNDS, &H))
            goto out;
        if (H.n == 0) /* settled */
            break;
        if (round == SNAP_ROUNDS + CROSS_ROUNDS - 1) { /* still crossing */
            ok = 1;
            goto out;
        }
        qsort(H.v, (size_t)H.n, sizeof *H.v, cmp_hit);
        long n_next = *n_run + H.n;
        if (n_next > INT_MAX / 2)
            goto out;
        next = malloc((size_t)n_next * sizeof *next);
        next_orig = malloc((size_t)n_next * sizeof *next_orig);
        if (!next || !next_orig)
            goto out;
        int m = 0;
        long h = 0;
        for (int r = 0; r < *n_run; r++) {
            /* The route so far of the input run r came from: a straight piece of one segment
             * never comes back to a node, and refusing so keeps the rounds finite. */
            if (r == 0 || orig[r] != orig[r - 1]) {
                route.n = 0;
                for (int q = r; q < *n_run && orig[q] == orig[r]; q++)
                    if (ibuf_push(&route, (*run)[q].n0) ||
                        ((q + 1 == *n_run || orig[q + 1] != orig[r]) &&
                         ibuf_push(&route, (*run)[q].n1)))
                        goto out;
            }
            _cb_arr_run R = (*run)[r];
            int from = R.n0;
            double pos = R.pos0;
            for (; h < H.n && H.v[h].r == r; h++) {
                int c = H.v[h].c, seen = 0;
                for (int g = 0; g < route.n && !seen; g++)
                    seen = route.v[g] == c;
                if (seen)
                    continue;
                if (ibuf_push(&route, c))
                    goto out;
                double p = run_pos(w, &R, N->xy + 2 * c);
                p = fmax(p, pos); /* positions must not run back */
                next_orig[m] = orig[r];
                next[m++] = (_cb_arr_run){R.poly, from, c, pos, p};
                from = c;
                pos = p;
            }
            next_orig[m] = orig[r];
            next[m++] = (_cb_arr_run){R.poly, from, R.n1, pos, R.pos1};
        }
        if (m == *n_run && round < SNAP_ROUNDS) /* all refused: on to the crossings alone */
            round = SNAP_ROUNDS - 1;
        free(*run);
        *run = next;
        *n_run = m;
        free(orig);
        orig = next_orig;
        next = NULL;
        next_orig = NULL;
    }
    ok = 0;
out:
    free(H.v);
    free(route.v);
    free(next);
    free(next_orig);
    free(orig);
    return ok;
}

/* ---------------------------------------------------------------- nodes -------------------- */

static int cmp_link(const void *pa, const void *pb)
{
    const link *a = pa, *b = pb;
    if (a->d != b->d)
        return a->d < b->d ? -1 : 1;
    if (a->i != b->i)
        return a->i < b->i ? -1 : 1;
    return (a->j > b->j) - (a->j < b->j);
}

static int find(int *parent, int x)
{
    while (parent[x] != x)
        x = parent[x] = parent[parent[x]];
    return x;
}

/* Merges linked sites, shortest links first, while a cluster's box stays within the span cap;
 * node[s] is the node of site s, numbered in order of first site. Returns the node count. */
static int cluster(int *node, work *w, int *parent, double *box)
{
    int n = w->n_sites;
    for (int s = 0; s < n; s++) {
        parent[s] = s;
        box[4 * s] = box[4 * s + 2] = w->sites[s].xy[0];
        box[4 * s + 1] = box[4 * s + 3] = w->sites[s].xy[1];
    }
    if (w->n_links) /* links is NULL when there are none */
        qsort(w->links, (size_t)w->n_links, sizeof *w->links, cmp_link);
    double span = CB_ARR_CLUSTER_SPAN * w->tol;
    for (long k = 0; k < w->n_links; k++) {
        int a = find(parent, w->links[k].i), b = find(parent, w->links[k].j);
        if (a == b)
            continue;
        double lo[2], hi[2];
        for (int i = 0; i < 2; i++) {
            lo[i] = fmin(box[4 * a + i], box[4 * b + i]);
            hi[i] = fmax(box[4 * a + 2 + i], box[4 * b + 2 + i]);
        }
        if (hypot(hi[0] - lo[0], hi[1] - lo[1]) > span)
            continue;
        if (a > b) { /* the lower index as root keeps the numbering independent of order */
            int t = a;
            a = b;
            b = t;
        }
        parent[b] = a;
        for (int i = 0; i < 2; i++) {
            box[4 * a + i] = lo[i];
            box[4 * a + 2 + i] = hi[i];
        }
    }
    int n_nodes = 0;
    for (int s = 0; s < n; s++) {
        int r = find(parent, s);
        node[s] = r == s ? n_nodes++ : node[r];
    }
    return n_nodes;
}

/* Site a is a better point for its node than b: not a free end, lower polyline, earlier. */
static int better_point(const site *a, int ia, const site *b, int ib)
{
    if (a->free_end != b->free_end)
        return a->free_end < b->free_end;
    if (a->poly != b->poly)
        return a->poly < b->poly;
    if (a->seg != b->seg)
        return a->seg < b->seg;
    if (a->t != b->t)
        return a->t < b->t;
    return ia < ib;
}

/* A site's place along the polylines, for sorting. */
typedef struct {
    int poly, seg;
    double t;
    int s;
} along;

static int cmp_along(const void *pa, const void *pb)
{
    const along *a = pa, *b = pb;
    if (a->poly != b->poly)
        return a->poly < b->poly ? -1 : 1;
    if (a->seg != b->seg)
        return a->seg < b->seg ? -1 : 1;
    if (a->t != b->t)
        return a->t < b->t ? -1 : 1;
    return (a->s > b->s) - (a->s < b->s);
}

/* ---------------------------------------------------------------- entry -------------------- */

static cb_status check_input(const cb_arr_polyline *in, int n, const double scale[2], double tol,
                             cb_error *err)
{
    if (n < 0 || (n > 0 && !in))
        return cb_error_set(err, CB_ERR_INVALID, "arrangement: %d polylines at %p", n,
                            (const void *)in);
    if (!scale || !(scale[0] > 0 && scale[1] > 0 && isfinite(scale[0]) && isfinite(scale[1])))
        return cb_error_set(err, CB_ERR_INVALID,
                            "arrangement: scale (%g, %g) is not positive and finite",
                            scale ? scale[0] : NAN, scale ? scale[1] : NAN);
    if (!(tol > 0 && isfinite(tol)))
        return cb_error_set(err, CB_ERR_INVALID,
                            "arrangement: snap_tol %g is not positive and finite", tol);
    long total = 0;
    for (int p = 0; p < n; p++) {
        if (in[p].n < 2)
            return cb_error_set(err, CB_ERR_INVALID,
                                "arrangement: polyline %d has %d points, at least 2 needed", p,
                                in[p].n);
        if (!in[p].uv)
            return cb_error_set(err, CB_ERR_INVALID, "arrangement: polyline %d has no points", p);
        for (int k = 0; k < in[p].n; k++) {
            double u = in[p].uv[2 * k], v = in[p].uv[2 * k + 1];
            if (!isfinite(u) || !isfinite(v) || !isfinite(u * scale[0]) || !isfinite(v * scale[1]))
                return cb_error_set(err, CB_ERR_INVALID,
                                    "arrangement: polyline %d point %d (%g, %g) is not finite "
                                    "(or not once scaled)",
                                    p, k, u, v);
        }
        total += in[p].n;
        if (total > INT_MAX / 16)
            return cb_error_set(err, CB_ERR_UNSUPPORTED,
                                "arrangement: more than %d points (at polyline %d)", INT_MAX / 16,
                                p);
    }
    return CB_OK;
}

static void work_clear(work *w)
{
    free(w->first);
    free(w->xy);
    free(w->seg_v);
    free(w->seg_p);
    free(w->sg.start);
    free(w->sg.item);
    free(w->pg.start);
    free(w->pg.item);
    free(w->sites);
    free(w->links);
    free(w->cells.v);
}

/* Points, segments, the grid and the sites of the points: -1 on NOMEM. */
static int setup(work *w)
{
    int n = w->n_in;
    w->first = malloc((size_t)(n + 1) * sizeof *w->first);
    if (!w->first)
        return -1;
    w->first[0] = 0;
    for (int p = 0; p < n; p++)
        w->first[p + 1] = w->first[p] + w->in[p].n;
    w->n_pts = w->first[n];
    w->n_seg = w->n_pts - n;
    w->xy = malloc((size_t)(2 * w->n_pts + 2) * sizeof *w->xy);
    w->seg_v = malloc((size_t)(w->n_seg + 1) * sizeof *w->seg_v);
    w->seg_p = malloc((size_t)(w->n_seg + 1) * sizeof *w->seg_p);
    w->cap_sites = 2 * w->n_pts + 16;
    w->sites = malloc((size_t)w->cap_sites * sizeof *w->sites);
    if (!w->xy || !w->seg_v || !w->seg_p || !w->sites)
        return -1;
    double lo[2] = {HUGE_VAL, HUGE_VAL}, hi[2] = {-HUGE_VAL, -HUGE_VAL}, big = 0;
    for (int p = 0, g = 0; p < n; p++)
        for (int k = 0; k < w->in[p].n; k++) {
            int v = w->first[p] + k;
            for (int i = 0; i < 2; i++) {
                double x = w->in[p].uv[2 * k + i] * w->sc[i];
                w->xy[2 * v + i] = x;
                lo[i] = fmin(lo[i], x);
                hi[i] = fmax(hi[i], x);
                big = fmax(big, fabs(x));
            }
            if (k + 1 < w->in[p].n) {
                w->seg_v[g] = v;
                w->seg_p[g++] = p;
            }
        }
    /* Slack for the rounding of the cell bounds and of the distances against tol. */
    w->margin = 1.5 * w->tol + 8 * DBL_EPSILON * big;
    grid_shape(&w->sg, lo[0] - 2 * w->margin, lo[1] - 2 * w->margin, hi[0] + 2 * w->margin,
               hi[1] + 2 * w->margin, w->n_seg, w->tol);
    for (int p = 0; p < n; p++) {
        int m = w->in[p].n;
        const double *a = w->xy + 2 * w->first[p], *b = a + 2 * (m - 1);
        int open = dist(a, b) > w->tol;
        for (int k = 0; k < m; k++) {
            int s = push_site(w, p, k, 0);
            if (s < 0)
                return -1;
            w->sites[s].free_end = open && (k == 0 || k == m - 1);
        }
    }
    return 0;
}

cb_status cb_arr_build(cb_arr *out, const cb_arr_polyline *in, int n, const double scale[2],
                       double snap_tol, cb_error *err)
{
    cb_arr_clear(out);
    cb_status st = check_input(in, n, scale, snap_tol, err);
    if (st)
        return st;
    work w;
    memset(&w, 0, sizeof w);
    w.in = in;
    w.n_in = n;
    w.sc[0] = scale[0];
    w.sc[1] = scale[1];
    w.tol = snap_tol;
    along *order = NULL;
    int *node = NULL, *parent = NULL, *best = NULL;
    double *box = NULL;
    nodes N = {0};
    _cb_arr_run *run = NULL;
    if (setup(&w) || grid_segments(&w) || snap_points(&w) || cross_segments(&w) || grid_sites(&w) ||
        near_sites(&w))
        goto nomem;
    int ns = w.n_sites;
    node = malloc((size_t)(ns + 1) * sizeof *node);
    parent = malloc((size_t)(ns + 1) * sizeof *parent);
    box = malloc((size_t)(ns + 1) * 4 * sizeof *box);
    order = malloc((size_t)(ns + 1) * sizeof *order);
    if (!node || !parent || !box || !order)
        goto nomem;
    int n_nodes = cluster(node, &w, parent, box);
    best = malloc((size_t)(n_nodes + 1) * sizeof *best);
    N.cap = n_nodes + 16;
    N.n = n_nodes;
    N.xy = malloc((size_t)(2 * N.cap) * sizeof *N.xy);
    N.uv = malloc((size_t)(2 * N.cap) * sizeof *N.uv);
    run = malloc((size_t)(ns + 1) * sizeof *run);
    if (!best || !N.xy || !N.uv || !run)
        goto nomem;
    for (int k = 0; k < n_nodes; k++)
        best[k] = -1;
    for (int s = 0; s < ns; s++) {
        int k = node[s];
        if (best[k] < 0 || better_point(&w.sites[s], s, &w.sites[best[k]], best[k]))
            best[k] = s;
    }
    for (int k = 0; k < n_nodes; k++)
        for (int i = 0; i < 2; i++) {
            N.xy[2 * k + i] = w.sites[best[k]].xy[i];
            N.uv[2 * k + i] = w.sites[best[k]].uv[i];
        }
    /* Along each polyline, a run between consecutive sites of different nodes. */
    for (int s = 0; s < ns; s++)
        order[s] = (along){w.sites[s].poly, w.sites[s].seg, w.sites[s].t, s};
    qsort(order, (size_t)ns, sizeof *order, cmp_along);
    int n_run = 0;
    for (int k = 0; k + 1 < ns; k++) {
        const site *a = &w.sites[order[k].s], *b = &w.sites[order[k + 1].s];
        int na = node[order[k].s], nb = node[order[k + 1].s];
        if (a->poly != b->poly || na == nb)
            continue;
        run[n_run++] = (_cb_arr_run){a->poly, na, nb, a->seg + a->t, b->seg + b->t};
    }
    int tangled = refine_runs(&w, &N, &run, &n_run);
    if (tangled < 0)
        goto nomem;
    if (tangled) {
        st = cb_error_set(err, CB_ERR_NUMERIC,
                          "arrangement: segments still cross after snapping (%d polylines, %d "
                          "points): points closer than snap_tol %g over long stretches?",
                          n, w.n_pts, snap_tol);
        goto done;
    }
    st = _cb_arr_faces(out, in, N.n, N.xy, N.uv, n_run, run, w.sc, w.tol, err);
    goto done;
nomem:
    st = cb_error_set(err, CB_ERR_NOMEM, "arrangement: out of memory (%d polylines, %d sites)", n,
                      w.n_sites);
done:
    work_clear(&w);
    free(order);
    free(node);
    free(parent);
    free(best);
    free(box);
    free(N.xy);
    free(N.uv);
    free(run);
    if (st)
        cb_arr_clear(out);
    return st;
}
