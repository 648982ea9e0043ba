/* The arrangement of polylines, second stage (boolean/arrange.h): runs between the same two
 * nodes merge into edges; face walks around the planar graph, edges ordered by angle at each
 * node, find the dangling edges and then the faces; edges chain into pieces; the bounded faces
 * become regions with their holes and an inner point. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "boolean/arrange.h"

typedef struct {
    int n_nodes;
    const double *xy, *uv;
    int n_run;
    const _cb_arr_run *run;
    double sc[2], tol;
    /* Edges: the runs between the same two nodes ea < eb, e_run[e_first[m] .. e_first[m + 1]) */
    int n_e;
    int *ea, *eb, *e_first, *e_run, *run_e;
    /* Half-edges 2 m (ea -> eb) and 2 m + 1 (eb -> ea); those leaving node v are
     * v_he[v_first[v] .. v_first[v + 1]) by increasing angle, h at place he_pos[h]. */
    int *v_first, *v_he, *he_pos;
    int *dangling; /* per edge */
    /* Faces without the dangling edges: walk f is f_he[f_first[f] .. f_first[f + 1]) */
    int n_f;
    int *he_f, *f_first, *f_he, *f_outer, *f_comp;
    double *f_area, *f_box;
    int n_comp;
    int *comp, *comp_left, *comp_in; /* node -> component; its leftmost node; enclosing face */
    /* Pieces: edge m is the pidx-th of piece pc, walked ea -> eb when prel = +1 */
    int *pc, *pidx, *prel;
} fwork;

static int org(const fwork *w, int h) { return h & 1 ? w->eb[h >> 1] : w->ea[h >> 1]; }
static int dst(const fwork *w, int h) { return h & 1 ? w->ea[h >> 1] : w->eb[h >> 1]; }

static double orient(const double *a, const double *b, const double *c)
{
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

/* ---------------------------------------------------------------- edges -------------------- */

typedef struct {
    int lo, hi, r;
} run_key;

static int cmp_run_key(const void *pa, const void *pb)
{
    const run_key *a = pa, *b = pb;
    if (a->lo != b->lo)
        return a->lo < b->lo ? -1 : 1;
    if (a->hi != b->hi)
        return a->hi < b->hi ? -1 : 1;
    return (a->r > b->r) - (a->r < b->r);
}

typedef struct {
    int v;
    double ang;
    int h;
} he_key;

static int cmp_he_key(const void *pa, const void *pb)
{
    const he_key *a = pa, *b = pb;
    if (a->v != b->v)
        return a->v < b->v ? -1 : 1;
    if (a->ang != b->ang)
        return a->ang < b->ang ? -1 : 1;
    return (a->h > b->h) - (a->h < b->h);
}

/* Merges the runs into edges and orders the half-edges around the nodes: -1 on NOMEM. */
static int make_edges(fwork *w)
{
    int nr = w->n_run;
    run_key *key = malloc((size_t)(nr + 1) * sizeof *key);
    w->ea = malloc((size_t)(nr + 1) * sizeof *w->ea);
    w->eb = malloc((size_t)(nr + 1) * sizeof *w->eb);
    w->e_first = malloc((size_t)(nr + 2) * sizeof *w->e_first);
    w->e_run = malloc((size_t)(nr + 1) * sizeof *w->e_run);
    w->run_e = malloc((size_t)(nr + 1) * sizeof *w->run_e);
    if (!key || !w->ea || !w->eb || !w->e_first || !w->e_run || !w->run_e) {
        free(key);
        return -1;
    }
    for (int r = 0; r < nr; r++) {
        int a = w->run[r].n0, b = w->run[r].n1;
        key[r] = (run_key){a < b ? a : b, a < b ? b : a, r};
    }
    qsort(key, (size_t)nr, sizeof *key, cmp_run_key);
    int m = -1;
    for (int k = 0; k < nr; k++) {
        if (k == 0 || key[k].lo != key[k - 1].lo || key[k].hi != key[k - 1].hi) {
            m++;
            w->ea[m] = key[k].lo;
            w->eb[m] = key[k].hi;
            w->e_first[m] = k;
        }
        w->e_run[k] = key[k].r;
        w->run_e[key[k].r] = m;
    }
    free(key);
    w->n_e = m + 1;
    w->e_first[w->n_e] = nr;

    int nh = 2 * w->n_e;
    he_key *hk = malloc((size_t)(nh + 1) * sizeof *hk);
    w->v_first = calloc((size_t)w->n_nodes + 1, sizeof *w->v_first);
    w->v_he = malloc((size_t)(nh + 1) * sizeof *w->v_he);
    w->he_pos = malloc((size_t)(nh + 1) * sizeof *w->he_pos);
    if (!hk || !w->v_first || !w->v_he || !w->he_pos) {
        free(hk);
        return -1;
    }
    for (int h = 0; h < nh; h++) {
        const double *a = w->xy + 2 * org(w, h), *b = w->xy + 2 * dst(w, h);
        hk[h] = (he_key){org(w, h), atan2(b[1] - a[1], b[0] - a[0]), h};
        w->v_first[org(w, h) + 1]++;
    }
    for (int v = 0; v < w->n_nodes; v++)
        w->v_first[v + 1] += w->v_first[v];
    qsort(hk, (size_t)nh, sizeof *hk, cmp_he_key);
    for (int k = 0; k < nh; k++) {
        w->v_he[k] = hk[k].h;
        w->he_pos[hk[k].h] = k - w->v_first[hk[k].v];
    }
    free(hk);
    return 0;
}

/* ---------------------------------------------------------------- faces -------------------- */

/* The half-edge after h along its face (the face on the left): at the end of h, the next
 * live half-edge clockwise from h's twin. */
static int walk_next(const fwork *w, int h, const int *dead)
{
    int t = h ^ 1, v = org(w, t), f = w->v_first[v], d = w->v_first[v + 1] - f;
    for (int s = 1; s < d; s++) {
        int g = w->v_he[f + (w->he_pos[t] - s + d) % d];
        if (!dead || !dead[g >> 1])
            return g;
    }
    return t;
}

/* Labels the live half-edges with their face (face[h], -1 when dead); list, when given, gets
 * each face's half-edges in walk order and first the offsets. Returns the face count. */
static int label_faces(const fwork *w, int *face, const int *dead, int *first, int *list)
{
    int nh = 2 * w->n_e, nf = 0, k = 0;
    for (int h = 0; h < nh; h++)
        face[h] = -1;
    for (int h = 0; h < nh; h++) {
        if ((dead && dead[h >> 1]) || face[h] >= 0)
            continue;
        if (first)
            first[nf] = k;
        int g = h, steps = 0;
        do { /* next is a permutation of the live half-edges: the walk returns to h */
            face[g] = nf;
            if (list)
                list[k++] = g;
            g = walk_next(w, g, dead);
        } while (g != h && ++steps <= nh);
        nf++;
    }
    if (first)
        first[nf] = k;
    return nf;
}

static int find(int *parent, int x)
{
    while (parent[x] != x)
        x = parent[x] = parent[parent[x]];
    return x;
}

/* Winding number of the closed walk f around p (scaled plane). */
static int winding(const fwork *w, int f, const double *p)
{
    int wn = 0;
    for (int k = w->f_first[f]; k < w->f_first[f + 1]; k++) {
        int h = w->f_he[k];
        const double *a = w->xy + 2 * org(w, h), *b = w->xy + 2 * dst(w, h);
        if (a[1] <= p[1]) {
            if (b[1] > p[1] && orient(a, b, p) > 0)
                wn++;
        } else if (b[1] <= p[1] && orient(a, b, p) < 0)
            wn--;
    }
    return wn;
}

/* Dangling edges (the same face on both sides), the faces of the rest with their areas and
 * boxes, the components with their outer walks and the bounded face each lies in. */
static int make_faces(fwork *w)
{
    int nh = 2 * w->n_e, nn = w->n_nodes;
    w->dangling = malloc((size_t)(w->n_e + 1) * sizeof *w->dangling);
    w->he_f = malloc((size_t)(nh + 1) * sizeof *w->he_f);
    w->f_first = malloc((size_t)(nh + 2) * sizeof *w->f_first);
    w->f_he = malloc((size_t)(nh + 1) * sizeof *w->f_he);
    w->comp = malloc((size_t)(nn + 1) * sizeof *w->comp);
    if (!w->dangling || !w->he_f || !w->f_first || !w->f_he || !w->comp)
        return -1;
    label_faces(w, w->he_f, NULL, NULL, NULL);
    for (int m = 0; m < w->n_e; m++)
        w->dangling[m] = w->he_f[2 * m] == w->he_f[2 * m + 1];
    int nf = w->n_f = label_faces(w, w->he_f, w->dangling, w->f_first, w->f_he);

    w->f_area = malloc((size_t)(nf + 1) * sizeof *w->f_area);
    w->f_box = malloc((size_t)(4 * nf + 1) * sizeof *w->f_box);
    w->f_outer = calloc((size_t)nf + 1, sizeof *w->f_outer);
    w->f_comp = malloc((size_t)(nf + 1) * sizeof *w->f_comp);
    if (!w->f_area || !w->f_box || !w->f_outer || !w->f_comp)
        return -1;
    for (int f = 0; f < nf; f++) {
        const double *ref = w->uv + 2 * org(w, w->f_he[w->f_first[f]]);
        double s = 0, *box = w->f_box + 4 * f;
        box[0] = box[1] = HUGE_VAL;
        box[2] = box[3] = -HUGE_VAL;
        for (int k = w->f_first[f]; k < w->f_first[f + 1]; k++) {
            int h = w->f_he[k];
            const double *a = w->uv + 2 * org(w, h), *b = w->uv + 2 * dst(w, h);
            s += (a[0] - ref[0]) * (b[1] - ref[1]) - (b[0] - ref[0]) * (a[1] - ref[1]);
            const double *p = w->xy + 2 * org(w, h);
            for (int i = 0; i < 2; i++) {
                box[i] = fmin(box[i], p[i]);
                box[2 + i] = fmax(box[2 + i], p[i]);
            }
        }
        w->f_area[f] = 0.5 * s;
    }

    /* Components of the live graph; each one's outer walk leaves its leftmost (then lowest)
     * node along the live half-edge of greatest angle, all others pointing right of it. */
    for (int v = 0; v < nn; v++)
        w->comp[v] = v;
    for (int m = 0; m < w->n_e; m++)
        if (!w->dangling[m]) {
            int a = find(w->comp, w->ea[m]), b = find(w->comp, w->eb[m]);
            if (a != b)
                w->comp[a > b ? a : b] = a < b ? a : b;
        }
    int *left = malloc((size_t)(nn + 1) * sizeof *left), nc = 0;
    if (!left)
        return -1;
    for (int v = 0; v < nn; v++)
        left[v] = -1;
    for (int v = 0; v < nn; v++) {
        int live = 0;
        for (int k = w->v_first[v]; k < w->v_first[v + 1]; k++)
            live |= !w->dangling[w->v_he[k] >> 1];
        if (!live)
            continue;
        int r = find(w->comp, v);
        const double *p = w->xy + 2 * v, *q = left[r] < 0 ? NULL : w->xy + 2 * left[r];
        if (!q || p[0] < q[0] || (p[0] == q[0] && p[1] < q[1]))
            left[r] = v;
    }
    w->comp_left = malloc((size_t)(nn + 1) * sizeof *w->comp_left);
    w->comp_in = malloc((size_t)(nn + 1) * sizeof *w->comp_in);
    if (!w->comp_left || !w->comp_in) {
        free(left);
        return -1;
    }
    for (int v = 0; v < nn; v++) /* renumber the components 0 .. nc - 1 */
        if (left[v] >= 0) {
            w->comp_left[nc] = left[v];
            left[v] = nc++;
        }
    for (int v = 0; v < nn; v++) /* flatten first: the next loop overwrites the roots */
        w->comp[v] = find(w->comp, v);
    for (int v = 0; v < nn; v++)
        w->comp[v] = left[w->comp[v]];
    free(left);
    w->n_comp = nc;
    for (int f = 0; f < nf; f++)
        w->f_comp[f] = w->comp[org(w, w->f_he[w->f_first[f]])];
    for (int c = 0; c < nc; c++) {
        int v = w->comp_left[c], top = -1;
        for (int k = w->v_first[v]; k < w->v_first[v + 1]; k++)
            if (!w->dangling[w->v_he[k] >> 1])
                top = w->v_he[k];
        w->f_outer[w->he_f[top]] = 1;
    }
    /* The bounded face of another component around each component, the smallest of those
     * around its leftmost node: faces of different components nest. */
    for (int c = 0; c < nc; c++) {
        const double *p = w->xy + 2 * w->comp_left[c];
        int in = -1;
        for (int f = 0; f < nf; f++) {
            const double *box = w->f_box + 4 * f;
            if (w->f_outer[f] || w->f_comp[f] == c || p[0] < box[0] || p[1] < box[1] ||
                p[0] > box[2] || p[1] > box[3])
                continue;
            if ((in < 0 || fabs(w->f_area[f]) < fabs(w->f_area[in])) && winding(w, f, p))
                in = f;
        }
        w->comp_in[c] = in;
    }
    return 0;
}

/* ---------------------------------------------------------------- pieces ------------------- */

/* The edge that continues edge m through node c within one piece, or -1: c has two edges and
 * each run of m goes on, along its polyline, into a run of the other. */
static int chain_next(const fwork *w, int m, int c)
{
    int f = w->v_first[c];
    if (w->v_first[c + 1] - f != 2)
        return -1;
    int m2 = w->v_he[f] >> 1;
    if (m2 == m)
        m2 = w->v_he[f + 1] >> 1;
    int k0 = w->e_first[m], cnt = w->e_first[m + 1] - k0;
    if (m2 == m || w->e_first[m2 + 1] - w->e_first[m2] != cnt)
        return -1;
    for (int i = 0; i < cnt; i++) {
        int r = w->e_run[k0 + i], fwd = w->run[r].n1 == c, r2 = fwd ? r + 1 : r - 1;
        if (r2 < 0 || r2 >= w->n_run || w->run[r2].poly != w->run[r].poly || w->run_e[r2] != m2 ||
            (fwd ? w->run[r2].n0 : w->run[r2].n1) != c)
            return -1;
        for (int j = 0; j < i; j++) { /* two passes of a polyline must not meet in one run */
            int rj = w->e_run[k0 + j];
            if ((w->run[rj].n1 == c ? rj + 1 : rj - 1) == r2)
                return -1;
        }
    }
    return m2;
}

typedef struct {
    int poly;
    double p0, p1;
} track;

static int track_before(const track *a, const track *b)
{
    if (a->poly != b->poly)
        return a->poly < b->poly;
    return fmin(a->p0, a->p1) < fmin(b->p0, b->p1);
}

/* Chains the edges into pieces and numbers their end nodes as vertices: -1 on NOMEM. */
static int make_pieces(fwork *w, cb_arr *out, const cb_arr_polyline *in)
{
    int ne = w->n_e;
    w->pc = malloc((size_t)(ne + 1) * sizeof *w->pc);
    w->pidx = malloc((size_t)(ne + 1) * sizeof *w->pidx);
    w->prel = malloc((size_t)(ne + 1) * sizeof *w->prel);
    int *chain = malloc((size_t)(ne + 1) * sizeof *chain);
    int *cnode = malloc((size_t)(ne + 2) * sizeof *cnode);
    int *vert = malloc((size_t)(w->n_nodes + 1) * sizeof *vert);
    track *tr = malloc((size_t)(w->n_run + 1) * sizeof *tr);
    out->piece = calloc((size_t)ne + 1, sizeof *out->piece);
    out->vertex_uv = malloc((size_t)(4 * ne + 2) * sizeof *out->vertex_uv);
    int ok =
        w->pc && w->pidx && w->prel && chain && cnode && vert && tr && out->piece && out->vertex_uv;
    for (int m = 0; ok && m < ne; m++)
        w->pc[m] = -1;
    for (int v = 0; ok && v < w->n_nodes; v++)
        vert[v] = -1;
    for (int m = 0; ok && m < ne; m++) {
        if (w->pc[m] >= 0)
            continue;
        /* Back to where the chain breaks (or, round a loop with no break, m itself). */
        int start = m, node = w->ea[m];
        for (int steps = 0; steps < ne; steps++) {
            int pm = chain_next(w, start, node);
            if (pm < 0)
                break;
            if (pm == m) {
                start = m;
                node = w->ea[m];
                break;
            }
            node = w->ea[pm] == node ? w->eb[pm] : w->ea[pm];
            start = pm;
        }
        int L = 0, e = start;
        cnode[0] = node;
        for (;;) {
            chain[L] = e;
            cnode[L + 1] = w->ea[e] == cnode[L] ? w->eb[e] : w->ea[e];
            L++;
            int nx = chain_next(w, e, cnode[L]);
            if (nx < 0 || nx == start || L >= ne)
                break;
            e = nx;
        }
        /* A track per run of the first edge: its polyline's positions at the two ends. */
        int k0 = w->e_first[chain[0]], ns = w->e_first[chain[0] + 1] - k0;
        for (int i = 0; i < ns; i++) {
            int r = w->e_run[k0 + i], fwd = w->run[r].n0 == cnode[0];
            int last = fwd ? r + L - 1 : r - (L - 1);
            tr[i] = (track){w->run[r].poly, fwd ? w->run[r].pos0 : w->run[r].pos1,
                            fwd ? w->run[last].pos1 : w->run[last].pos0};
        }
        for (int i = 1; i < ns; i++) /* insertion sort: few sources */
            for (int j = i; j > 0 && track_before(&tr[j], &tr[j - 1]); j--) {
                track t = tr[j];
                tr[j] = tr[j - 1];
                tr[j - 1] = t;
            }
        if (tr[0].p0 > tr[0].p1) { /* run the way src[0]'s positions grow */
            for (int i = 0, j = L - 1; i < j; i++, j--) {
                int t = chain[i];
                chain[i] = chain[j];
                chain[j] = t;
            }
            for (int i = 0, j = L; i < j; i++, j--) {
                int t = cnode[i];
                cnode[i] = cnode[j];
                cnode[j] = t;
            }
            for (int i = 0; i < ns; i++) {
                double t = tr[i].p0;
                tr[i].p0 = tr[i].p1;
                tr[i].p1 = t;
            }
        }
        int id = out->n_pieces;
        cb_arr_piece *pc = &out->piece[id];
        pc->n = L + 1;
        pc->n_src = ns;
        pc->uv = malloc((size_t)(2 * (L + 1) + 2 * ns) * sizeof *pc->uv);
        pc->src = malloc((size_t)(2 * ns) * sizeof *pc->src);
        if (!pc->uv || !pc->src) {
            free(pc->uv);
            free(pc->src);
            pc->uv = NULL;
            pc->src = NULL;
            ok = 0;
            break;
        }
        out->n_pieces++;
        pc->pos0 = pc->uv + 2 * (L + 1);
        pc->pos1 = pc->pos0 + ns;
        pc->src_id = pc->src + ns;
        for (int i = 0; i < ns; i++) {
            pc->src[i] = tr[i].poly;
            pc->src_id[i] = in[tr[i].poly].id;
            pc->pos0[i] = tr[i].p0;
            pc->pos1[i] = tr[i].p1;
        }
        for (int i = 0; i <= L; i++) {
            pc->uv[2 * i] = w->uv[2 * cnode[i]];
            pc->uv[2 * i + 1] = w->uv[2 * cnode[i] + 1];
        }
        for (int i = 0; i < 2; i++) {
            int v = cnode[i ? L : 0];
            if (vert[v] < 0) {
                vert[v] = out->n_vertices++;
                out->vertex_uv[2 * vert[v]] = w->uv[2 * v];
                out->vertex_uv[2 * vert[v] + 1] = w->uv[2 * v + 1];
            }
        }
        pc->v0 = vert[cnode[0]];
        pc->v1 = vert[cnode[L]];
        pc->dangling = w->dangling[chain[0]];
        for (int i = 0; i < L; i++) {
            w->pc[chain[i]] = id;
            w->pidx[chain[i]] = i;
            w->prel[chain[i]] = w->ea[chain[i]] == cnode[i] ? 1 : -1;
        }
    }
    free(chain);
    free(cnode);
    free(vert);
    free(tr);
    return ok ? 0 : -1;
}

/* ---------------------------------------------------------------- regions ------------------ */

/* The piece use of half-edge h when h starts its piece (in h's direction), else 0. */
static int piece_start(const fwork *w, const cb_arr *out, int h)
{
    int m = h >> 1, dir = h & 1 ? -w->prel[m] : w->prel[m];
    int at = dir > 0 ? 0 : out->piece[w->pc[m]].n - 2;
    return w->pidx[m] == at ? dir : 0;
}

/* Appends walk f's pieces to use, from a piece start; returns the count. */
static int emit_walk(const fwork *w, const cb_arr *out, int f, cb_arr_use *use)
{
    int a = w->f_first[f], len = w->f_first[f + 1] - a, i0 = 0, n = 0;
    while (i0 < len && !piece_start(w, out, w->f_he[a + i0]))
        i0++;
    for (int j = 0; j < len; j++) {
        int h = w->f_he[a + (i0 + j) % len], dir = piece_start(w, out, h);
        if (dir) {
            if (use)
                use[n] = (cb_arr_use){w->pc[h >> 1], dir};
            n++;
        }
    }
    return n;
}

static double seg_dist(const double *p, const double *a, const double *b)
{
    double ex = b[0] - a[0], ey = b[1] - a[1], L2 = ex * ex + ey * ey;
    double t = L2 > 0 ? ((p[0] - a[0]) * ex + (p[1] - a[1]) * ey) / L2 : 0;
    t = fmin(1, fmax(0, t));
    double dx = p[0] - a[0] - t * ex, dy = p[1] - a[1] - t * ey;
    return sqrt(dx * dx + dy * dy);
}

static int cmp_double(const void *pa, const void *pb)
{
    double a = *(const double *)pa, b = *(const double *)pb;
    return (a > b) - (a < b);
}

/* A point inside the region bounded by half-edges hes[0 .. nh) (scaled): of the two widest
 * chords on each of K lines y = const across its box, the midpoint farthest from the
 * boundary; K = 16, then 256 when none is farther than tol. xs holds nh doubles. */
static void inner_point(const fwork *w, const int *hes, int nh, double *xs, double p[2],
                        double *clear)
{
    double ylo = HUGE_VAL, yhi = -HUGE_VAL, best = -1;
    for (int i = 0; i < nh; i++) {
        double y = w->xy[2 * org(w, hes[i]) + 1];
        ylo = fmin(ylo, y);
        yhi = fmax(yhi, y);
    }
    const double *a0 = w->xy + 2 * org(w, hes[0]), *b0 = w->xy + 2 * dst(w, hes[0]);
    p[0] = 0.5 * (a0[0] + b0[0]); /* no chord at all: a flat region */
    p[1] = 0.5 * (a0[1] + b0[1]);
    for (int K = 16; K <= 256; K *= 16) {
        for (int k = 0; k < K; k++) {
            /* An irrational offset keeps the lines off the round coordinates of vertices. */
            double y = ylo + (yhi - ylo) * (k + 0.6180339887498949) / K;
            int n = 0;
            for (int i = 0; i < nh; i++) {
                const double *a = w->xy + 2 * org(w, hes[i]), *b = w->xy + 2 * dst(w, hes[i]);
                if ((a[1] > y) != (b[1] > y))
                    xs[n++] = a[0] + (y - a[1]) * (b[0] - a[0]) / (b[1] - a[1]);
            }
            qsort(xs, (size_t)n, sizeof *xs, cmp_double);
            int w1 = -1, w2 = -1;
            for (int i = 0; i + 1 < n; i += 2) {
                double d = xs[i + 1] - xs[i];
                if (w1 < 0 || d > xs[w1 + 1] - xs[w1]) {
                    w2 = w1;
                    w1 = i;
                } else if (w2 < 0 || d > xs[w2 + 1] - xs[w2])
                    w2 = i;
            }
            for (int c = 0; c < 2; c++) {
                int i = c ? w2 : w1;
                if (i < 0)
                    continue;
                double q[2] = {0.5 * (xs[i] + xs[i + 1]), y}, cl = HUGE_VAL;
                for (int j = 0; j < nh && cl > best; j++)
                    cl = fmin(cl,
                              seg_dist(q, w->xy + 2 * org(w, hes[j]), w->xy + 2 * dst(w, hes[j])));
                if (cl > best) {
                    best = cl;
                    p[0] = q[0];
                    p[1] = q[1];
                }
            }
        }
        if (best > w->tol)
            break;
    }
    *clear = fmax(best, 0);
}

/* The regions: each bounded face, its outer walk then the outer walks of the components
 * directly inside it. -1 on NOMEM. */
static int make_regions(fwork *w, cb_arr *out)
{
    int nf = w->n_f, nr = 0, total_uses = 0, total_cycles = 0, max_he = 1;
    int *reg = malloc((size_t)(nf + 1) * sizeof *reg);
    int *n_holes = calloc((size_t)nf + 1, sizeof *n_holes);
    int *hole_first = malloc((size_t)(nf + 2) * sizeof *hole_first);
    int *hole = malloc((size_t)(w->n_comp + 1) * sizeof *hole);
    int *hes = malloc((size_t)(2 * w->n_e + 1) * sizeof *hes);
    double *xs = malloc((size_t)(2 * w->n_e + 1) * sizeof *xs);
    int ok = reg && n_holes && hole_first && hole && hes && xs;
    for (int f = 0; ok && f < nf; f++)
        reg[f] = w->f_outer[f] ? -1 : nr++;
    for (int c = 0; ok && c < w->n_comp; c++)
        if (w->comp_in[c] >= 0)
            n_holes[w->comp_in[c]]++;
    if (ok) {
        hole_first[0] = 0;
        for (int f = 0; f < nf; f++)
            hole_first[f + 1] = hole_first[f] + n_holes[f];
        for (int c = 0; c < w->n_comp; c++)
            if (w->comp_in[c] >= 0)
                hole[hole_first[w->comp_in[c]] + --n_holes[w->comp_in[c]]] = c;
    }
    /* A component's outer walk, by its leftmost node. */
    int *outer_of = ok ? malloc((size_t)(w->n_comp + 1) * sizeof *outer_of) : NULL;
    ok = ok && outer_of;
    for (int f = 0; ok && f < nf; f++)
        if (w->f_outer[f])
            outer_of[w->f_comp[f]] = f;
    for (int f = 0; ok && f < nf; f++) {
        if (reg[f] < 0)
            continue;
        total_cycles += 1 + hole_first[f + 1] - hole_first[f];
        total_uses += emit_walk(w, out, f, NULL);
        int nh = w->f_first[f + 1] - w->f_first[f];
        for (int k = hole_first[f]; k < hole_first[f + 1]; k++) {
            int g = outer_of[hole[k]];
            total_uses += emit_walk(w, out, g, NULL);
            nh += w->f_first[g + 1] - w->f_first[g];
        }
        max_he = nh > max_he ? nh : max_he;
    }
    if (ok) {
        out->region = calloc((size_t)nr + 1, sizeof *out->region);
        out->cycle_pool = malloc((size_t)(total_cycles + nr + 1) * sizeof *out->cycle_pool);
        out->use_pool = malloc((size_t)(total_uses + 1) * sizeof *out->use_pool);
        ok = out->region && out->cycle_pool && out->use_pool;
    }
    int *cyc = out->cycle_pool;
    cb_arr_use *use = out->use_pool;
    for (int f = 0; ok && f < nf; f++) {
        if (reg[f] < 0)
            continue;
        cb_arr_region *R = &out->region[out->n_regions++];
        R->n_cycles = 1 + hole_first[f + 1] - hole_first[f];
        R->cycle = cyc;
        R->use = use;
        R->area = w->f_area[f];
        int n = 0, nh = 0;
        for (int c = 0; c < R->n_cycles; c++) {
            int g = c ? outer_of[hole[hole_first[f] + c - 1]] : f;
            cyc[c] = n;
            n += emit_walk(w, out, g, use + n);
            if (c)
                R->area += w->f_area[g];
            for (int k = w->f_first[g]; k < w->f_first[g + 1]; k++)
                hes[nh++] = w->f_he[k];
        }
        cyc[R->n_cycles] = n;
        cyc += R->n_cycles + 1;
        use += n;
        double p[2];
        inner_point(w, hes, nh, xs, p, &R->clearance);
        R->inner[0] = p[0] / w->sc[0];
        R->inner[1] = p[1] / w->sc[1];
    }
    free(reg);
    free(n_holes);
    free(hole_first);
    free(hole);
    free(hes);
    free(xs);
    free(outer_of);
    return ok ? 0 : -1;
}

cb_status _cb_arr_faces(cb_arr *out, const cb_arr_polyline *in, int n_nodes, const double *node_xy,
                        const double *node_uv, int n_run, const _cb_arr_run *run,
                        const double scale[2], double snap_tol, cb_error *err)
{
    fwork w;
    memset(&w, 0, sizeof w);
    w.n_nodes = n_nodes;
    w.xy = node_xy;
    w.uv = node_uv;
    w.n_run = n_run;
    w.run = run;
    w.sc[0] = scale[0];
    w.sc[1] = scale[1];
    w.tol = snap_tol;
    int fail =
        make_edges(&w) || make_faces(&w) || make_pieces(&w, out, in) || make_regions(&w, out);
    int *arrays[] = {w.ea,     w.eb,        w.e_first, w.e_run,   w.run_e, w.v_first, w.v_he,
                     w.he_pos, w.dangling,  w.he_f,    w.f_first, w.f_he,  w.f_outer, w.f_comp,
                     w.comp,   w.comp_left, w.comp_in, w.pc,      w.pidx,  w.prel};
    for (size_t k = 0; k < sizeof arrays / sizeof *arrays; k++)
        free(arrays[k]);
    free(w.f_area);
    free(w.f_box);
    if (fail)
        return cb_error_set(err, CB_ERR_NOMEM, "arrangement: out of memory (%d nodes, %d runs)",
                            n_nodes, n_run);
    return CB_OK;
}
