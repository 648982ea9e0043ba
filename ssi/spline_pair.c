/* spline_pair.c — subdivision, normal-cone certification, boundary points and marching for one
 * pair of polynomial Bezier patches (see ssi/spline.h for the method and what it proves). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "brep/geom.h"
#include "ssi/spline.h"

/* Sides of one patch pair lying on each other: 16 pairs of sides at most, 8 in practice
 * (two patches sharing every side twice over is a coincidence, found before). */
#define MAX_COSIDES 8
/* Boxes of the (edge parameter, other patch) search per boundary curve. */
#define EDGE_BUDGET 4000
/* Boundary points kept per sub-patch pair; more means many branches (split further). */
#define MAX_BPTS 16

/* Within the tolerance (see _cb_ssi_spline_pair): sub-patches within TINY_TOL tol in 3D are not
 * split further; a sub-pair the tests cannot certify whose sub-patches are within STOP_TOL tol
 * and proved within tol of each other (slab_within) is not split either; a cluster of such
 * sub-pairs is resolved when its 3D diameter is at most tol, or at most WT_MAX_TOL tol with
 * every member proved within tol (a region where the two surfaces lie within tol of each
 * other: a near-tangent node or contact). WT_MAX_TOL: the branch ends moved onto the region's
 * point run to it inside the region, by chords of at most that length; at the default tol
 * (1e-6 of the model's size) 1000 tol is 1e-3 of the size, whose sagitta on a surface of
 * curvature radius the model's size is a tenth of tol. The nodes of bicubic graph pairs in
 * generic poses need up to about 1000 tol (bench_ssi_corpus). A wider cluster, every member
 * proved within tol, is a contact band (ssi_band.c): its valley curves, or one node that the
 * branch ends reach along the zero set of the distance. */
#define TINY_TOL 0.125
#define STOP_TOL 8.0
#define WT_MAX_TOL 1000.0
/* Runs other than the band run measure their tangent clusters each time this many sub-pairs
 * have joined them (a sort of them each time; a contact band along a bicubic tangential loop
 * passes WT_MAX_TOL tol after about 7000, a node's region stays below it). */
#define TINY_CHECK 256

/* ---------------------------------------------------------------- sub-patches -------------- */

typedef struct {
    double box[4];   /* local parameters of the Bezier patch: u0, u1, v0, v1 */
    _cb_iv *net;     /* dim (m + 1)(n + 1) enclosures of the sub-patch's control points
                        (homogeneous for a rational patch) */
    _cb_iv *enet;    /* their Euclidean enclosures, 3 per point (net itself when polynomial) */
    double *nm, *nr; /* Bernstein coefficients of S_u x S_v (in the sub-patch's own
                        parameters): centres (3 each) and radii bounding every component */
    double nsum[3];  /* sum of the centres: a mean normal direction */
    double lo[3], hi[3], size;
    int np;          /* control points in enet */
    int child[4], depth;
} node;

typedef struct {
    const _cb_ssi_bez *b;
    node *nd;
    int n, alloc, nn; /* nodes; nn normal coefficients per node */
    /* C(r, k) for r <= rows (the degrees of the normals' products, 3 max(m, n)), row-major:
     * every node's normal coefficients weigh each term by binomials, too many to recompute
     * (the rational patches of degree 6 x 10 spent most of their subdivision time there).
     * Doubles, exact below 2^53. */
    double *bin;
    int rows;
    double frac[2]; /* where a node is split in u and in v, as a fraction of its box */
} tree;

static double binom(const tree *T, int n, int k)
{
    return T->bin[n * (T->rows + 1) + k];
}

/* A scalar polynomial in Bernstein form of bidegree (a, b), coefficients c[i (b + 1) + j]. */
typedef struct {
    int a, b;
    _cb_iv *c;
} bpoly;

/* out += sg f g (out of bidegree (f.a + g.a, f.b + g.b), already sized): the Bernstein product
 * c_kl = sum C(a1,i) C(a2,k-i) / C(a1+a2,k) C(b1,j) C(b2,l-j) / C(b1+b2,l) f_ij g_(k-i)(l-j),
 * the weights enclosed with outward rounding. */
static void bp_mul_acc(const tree *T, bpoly *out, const bpoly *f, const bpoly *g, int sg)
{
    int A = f->a + g->a, B = f->b + g->b;
    for (int i = 0; i <= f->a; i++)
        for (int j = 0; j <= f->b; j++)
            for (int i2 = 0; i2 <= g->a; i2++) {
                double ci = binom(T, f->a, i) * binom(T, g->a, i2), cj = binom(T, f->b, j);
                double dk = binom(T, A, i + i2);
                for (int j2 = 0; j2 <= g->b; j2++) {
                    double num = ci * (cj * binom(T, g->b, j2));
                    double den = dk * binom(T, B, j + j2);
                    double w = sg * num / den;
                    _cb_iv wi = {_cb_iv_dn(w), _cb_iv_up(w)};
                    _cb_iv *o = out->c + (i + i2) * (B + 1) + j + j2;
                    *o = _cb_iv_add(*o, _cb_iv_mul(wi, _cb_iv_mul(f->c[i * (f->b + 1) + j],
                                                                   g->c[i2 * (g->b + 1) + j2])));
                }
            }
}

static void bp_zero(bpoly *p, int a, int b)
{
    p->a = a;
    p->b = b;
    for (int k = 0; k < (a + 1) * (b + 1); k++)
        p->c[k] = _cb_iv_pt(0);
}

/* Bernstein coefficients of N = w (P_u x P_v) - w_u (P x P_v) - w_v (P_u x P), bidegree
 * (3m - 1, 3n - 1), for the homogeneous net H (4 per point) of a rational patch: S_u x S_v =
 * N / w^3 (the constant factors m, n of the derivatives dropped, as they are positive), so N
 * points along every normal of the patch, which is what the direction test needs. Out:
 * 3 (3m)(3n) intervals, coefficient (k, l) at 3 (k (3n) + l). */
static int rational_normals(const tree *T, _cb_iv *out, const _cb_iv *H, int m, int n)
{
    bpoly P[4], Pu[4], Pv[4], C[1], N[1];
    /* One arena: 12 factors of at most (m + 1)(n + 1) coefficients, C of at most
     * (2m + 1)(2n + 1), N of (3m)(3n). */
    size_t fs = (size_t)((m + 1) * (n + 1)), cs = (size_t)((2 * m + 1) * (2 * n + 1));
    _cb_iv *arena = malloc((12 * fs + cs + (size_t)(9 * m * n)) * sizeof(_cb_iv));
    if (!arena)
        return -1;
    for (int q = 0; q < 4; q++) {
        P[q].c = arena + (size_t)q * fs;
        Pu[q].c = arena + (size_t)(4 + q) * fs;
        Pv[q].c = arena + (size_t)(8 + q) * fs;
    }
    C->c = arena + 12 * fs;
    N->c = C->c + cs;
    for (int q = 0; q < 4; q++) {
        P[q].a = m;
        P[q].b = n;
        Pu[q].a = m - 1;
        Pu[q].b = n;
        Pv[q].a = m;
        Pv[q].b = n - 1;
        for (int i = 0; i <= m; i++)
            for (int j = 0; j <= n; j++) {
                P[q].c[i * (n + 1) + j] = H[4 * (i * (n + 1) + j) + q];
                if (i < m)
                    Pu[q].c[i * (n + 1) + j] = _cb_iv_sub(H[4 * ((i + 1) * (n + 1) + j) + q],
                                                          H[4 * (i * (n + 1) + j) + q]);
                if (j < n)
                    Pv[q].c[i * n + j] =
                        _cb_iv_sub(H[4 * (i * (n + 1) + j + 1) + q], H[4 * (i * (n + 1) + j) + q]);
            }
    }
    /* terms (weight factor, left, right) of N = w (Pu x Pv) - w_u (P x Pv) - w_v (Pu x P) */
    const bpoly *wf[3] = {P + 3, Pu + 3, Pv + 3};
    const bpoly *lf[3] = {Pu, P, Pu}, *rt[3] = {Pv, Pv, P};
    const int sg[3] = {1, -1, -1};
    for (int q = 0; q < 3; q++) {
        int a = (q + 1) % 3, b = (q + 2) % 3;
        bp_zero(N, 3 * m - 1, 3 * n - 1);
        for (int t = 0; t < 3; t++) {
            /* C = (left x right)_q = left_a right_b - left_b right_a */
            bp_zero(C, lf[t][0].a + rt[t][0].a, lf[t][0].b + rt[t][0].b);
            bp_mul_acc(T, C, lf[t] + a, rt[t] + b, 1);
            bp_mul_acc(T, C, lf[t] + b, rt[t] + a, -1);
            bp_mul_acc(T, N, wf[t], C, sg[t]);
        }
        for (int k = 0; k < 3 * m; k++)
            for (int l = 0; l < 3 * n; l++)
                out[3 * (k * 3 * n + l) + q] = N->c[k * (3 * n) + l];
    }
    free(arena);
    return 0;
}

/* Normal coefficients and box of node k from its net; -1 when out of memory. */
static int node_finish(tree *T, int k)
{
    node *d = T->nd + k;
    int m = T->b->m, n = T->b->n, nv = n + 1;
    if (T->b->rat)
        _cb_ssi_net_eucl(d->enet, d->net, (m + 1) * nv, 4);
    const _cb_iv *P = d->enet;
    d->np = (m + 1) * nv;
    for (int q = 0; q < 3; q++) {
        d->lo[q] = HUGE_VAL;
        d->hi[q] = -HUGE_VAL;
    }
    for (int i = 0; i < (m + 1) * nv; i++)
        for (int q = 0; q < 3; q++) {
            d->lo[q] = fmin(d->lo[q], P[3 * i + q].lo);
            d->hi[q] = fmax(d->hi[q], P[3 * i + q].hi);
        }
    d->size = sqrt((d->hi[0] - d->lo[0]) * (d->hi[0] - d->lo[0]) +
                   (d->hi[1] - d->lo[1]) * (d->hi[1] - d->lo[1]) +
                   (d->hi[2] - d->lo[2]) * (d->hi[2] - d->lo[2]));
    int K = (T->b->rat ? 3 : 2) * m, L = (T->b->rat ? 3 : 2) * n;
    _cb_iv *N = calloc((size_t)(3 * K * L), sizeof(_cb_iv));
    if (!N || (T->b->rat && rational_normals(T, N, d->net, m, n))) {
        free(N);
        return -1;
    }
    for (int i = 0; i < m && !T->b->rat; i++)
        for (int j = 0; j <= n; j++) {
            _cb_iv A[3];
            for (int q = 0; q < 3; q++)
                A[q] = _cb_iv_sub(P[3 * ((i + 1) * nv + j) + q], P[3 * (i * nv + j) + q]);
            for (int i2 = 0; i2 <= m; i2++)
                for (int j2 = 0; j2 < n; j2++) {
                    _cb_iv B[3], X[3];
                    for (int q = 0; q < 3; q++)
                        B[q] = _cb_iv_sub(P[3 * (i2 * nv + j2 + 1) + q], P[3 * (i2 * nv + j2) + q]);
                    for (int q = 0; q < 3; q++) {
                        int a = (q + 1) % 3, b = (q + 2) % 3;
                        X[q] = _cb_iv_sub(_cb_iv_mul(A[a], B[b]), _cb_iv_mul(A[b], B[a]));
                    }
                    int k = i + i2, l = j + j2;
                    double num = (binom(T, m - 1, i) * binom(T, m, i2)) *
                                 (binom(T, n, j) * binom(T, n - 1, j2));
                    double den = binom(T, 2 * m - 1, k) * binom(T, 2 * n - 1, l);
                    double w = num / den;
                    _cb_iv wi = {_cb_iv_dn(w), _cb_iv_up(w)};
                    for (int q = 0; q < 3; q++)
                        N[3 * (k * L + l) + q] =
                            _cb_iv_add(N[3 * (k * L + l) + q], _cb_iv_mul(wi, X[q]));
                }
        }
    for (int q = 0; q < 3; q++)
        d->nsum[q] = 0;
    for (int c = 0; c < K * L; c++) {
        double r = 0;
        for (int q = 0; q < 3; q++) {
            _cb_iv x = N[3 * c + q];
            double mid = 0.5 * x.lo + 0.5 * x.hi;
            d->nm[3 * c + q] = mid;
            r = fmax(r, fmax(_cb_iv_up(x.hi - mid), _cb_iv_up(mid - x.lo)));
            d->nsum[q] += mid;
        }
        d->nr[c] = r;
    }
    free(N);
    return 0;
}

/* A new node with its arrays; -1 when out of memory (the tree is left as it was). */
static int node_add(tree *T)
{
    if (T->n == T->alloc) {
        int alloc = T->alloc ? 2 * T->alloc : 64;
        node *q = realloc(T->nd, (size_t)alloc * sizeof(node));
        if (!q)
            return -1;
        T->nd = q;
        T->alloc = alloc;
    }
    node *d = T->nd + T->n;
    memset(d, 0, sizeof(*d));
    int np = (T->b->m + 1) * (T->b->n + 1);
    d->net = malloc((size_t)(T->b->dim * np) * sizeof(_cb_iv));
    d->enet = T->b->rat ? malloc((size_t)(3 * np) * sizeof(_cb_iv)) : d->net;
    d->nm = malloc((size_t)(3 * T->nn) * sizeof(double));
    d->nr = malloc((size_t)T->nn * sizeof(double));
    if (!d->net || !d->enet || !d->nm || !d->nr) {
        if (d->enet != d->net)
            free(d->enet);
        free(d->net);
        free(d->nm);
        free(d->nr);
        return -1;
    }
    for (int c = 0; c < 4; c++)
        d->child[c] = -1;
    return T->n++;
}

static void tree_clear(tree *T);

/* Split fractions: away from 1/2 (designs put features on parameter midpoints: a node or a
 * branch on a split line leaves every sub-pair along it with roots on its sides), and
 * different for the two patches, also after reversing a direction (two patches parameterised
 * alike, up to a transposition or a reversal, as patches sharing knot lines are, would
 * otherwise get split lines that meet where a branch crosses both: a boundary root on a side of
 * both sub-patches, ambiguous in every sub-pair along the branch). P's fractions lie in
 * Q(sqrt 5) (the golden section's offset), Q's in Q(sqrt 2): no split line of one is a split line
 * of the other, reversed or not, unless both are rational (the fields share only the
 * rationals). */
#define SPLIT_LO 0.4618033988749895   /* 1/2 - (2 - golden ratio)/10 */
#define SPLIT_HI 0.5381966011250105   /* 1 - SPLIT_LO */
#define SPLIT_Q_LO 0.4528595479208968 /* 1/2 - sqrt(2)/30 */
#define SPLIT_Q_HI 0.5471404520791032 /* 1 - SPLIT_Q_LO */

/* The tree of b with its root, split at the fractions (fu, fv); -1 when out of memory (nothing
 * held). */
static int tree_init(tree *T, const _cb_ssi_bez *b, double fu, double fv)
{
    memset(T, 0, sizeof(*T));
    T->b = b;
    T->frac[0] = fu;
    T->frac[1] = fv;
    T->nn = (b->rat ? 9 : 4) * b->m * b->n;
    T->rows = 3 * (b->m > b->n ? b->m : b->n);
    int w = T->rows + 1;
    T->bin = malloc((size_t)(w * w) * sizeof(double));
    if (!T->bin)
        return -1;
    for (int r = 0; r < w; r++) {
        T->bin[r * w] = 1;
        for (int c = 1; c < w; c++)
            T->bin[r * w + c] = r ? T->bin[(r - 1) * w + c - 1] + T->bin[(r - 1) * w + c] : 0;
    }
    int k = node_add(T);
    if (k < 0) {
        free(T->bin);
        return -1;
    }
    node *d = T->nd + k;
    const double box[4] = {0, 1, 0, 1};
    memcpy(d->box, box, sizeof box);
    for (int i = 0; i < b->dim * (b->m + 1) * (b->n + 1); i++)
        d->net[i] = _cb_iv_pt(b->pts[i]);
    if (node_finish(T, k)) {
        tree_clear(T);
        return -1;
    }
    return 0;
}

static void tree_clear(tree *T)
{
    for (int k = 0; k < T->n; k++) {
        if (T->nd[k].enet != T->nd[k].net)
            free(T->nd[k].enet);
        free(T->nd[k].net);
        free(T->nd[k].nm);
        free(T->nd[k].nr);
    }
    free(T->nd);
    free(T->bin);
}

/* Children of node k (u halves outer, v halves inner), made once; -1 when out of memory (the
 * node then has no children). */
static int node_split(tree *T, int k)
{
    if (T->nd[k].child[0] >= 0)
        return 0;
    int m = T->b->m, n = T->b->n, nv = n + 1, np = (m + 1) * nv, D = T->b->dim;
    _cb_iv *ulo = malloc((size_t)(D * np) * sizeof(_cb_iv)),
           *uhi = malloc((size_t)(D * np) * sizeof(_cb_iv)),
           *tmp = malloc((size_t)(D * np) * sizeof(_cb_iv));
    int c[4] = {-1, -1, -1, -1}, ok = ulo && uhi && tmp;
    for (int q = 0; q < 4 && ok; q++)
        ok = (c[q] = node_add(T)) >= 0;
    /* The split parameters, and their fractions of the box as intervals (the split values are
     * rounded to doubles; the nets are split where they are). */
    const double *pb = T->nd[k].box;
    double um = pb[0] + T->frac[0] * (pb[1] - pb[0]), vm = pb[2] + T->frac[1] * (pb[3] - pb[2]);
    _cb_iv tu = _cb_iv_div(_cb_iv_sub(_cb_iv_pt(um), _cb_iv_pt(pb[0])),
                           _cb_iv_sub(_cb_iv_pt(pb[1]), _cb_iv_pt(pb[0])));
    _cb_iv tv = _cb_iv_div(_cb_iv_sub(_cb_iv_pt(vm), _cb_iv_pt(pb[2])),
                           _cb_iv_sub(_cb_iv_pt(pb[3]), _cb_iv_pt(pb[2])));
    if (ok) {
        for (int j = 0; j <= n; j++)
            _cb_ssi_split_iv_at(ulo + D * j, uhi + D * j, T->nd[k].net + D * j, m, D * nv, D,
                                tu);
        for (int h = 0; h < 2; h++) {
            const _cb_iv *half = h ? uhi : ulo;
            for (int g = 0; g < 2; g++) {
                node *par = T->nd + k, *d = T->nd + c[2 * h + g];
                d->depth = par->depth + 1;
                d->box[0] = h ? um : par->box[0];
                d->box[1] = h ? par->box[1] : um;
                d->box[2] = g ? vm : par->box[2];
                d->box[3] = g ? par->box[3] : vm;
                for (int i = 0; i <= m; i++) {
                    if (g)
                        _cb_ssi_split_iv_at(tmp + D * i * nv, d->net + D * i * nv,
                                            half + D * i * nv, n, D, D, tv);
                    else
                        _cb_ssi_split_iv_at(d->net + D * i * nv, tmp + D * i * nv,
                                            half + D * i * nv, n, D, D, tv);
                }
                ok = ok && !node_finish(T, c[2 * h + g]);
            }
        }
    }
    if (ok)
        for (int q = 0; q < 4; q++)
            T->nd[k].child[q] = c[q];
    free(ulo);
    free(uhi);
    free(tmp);
    return ok ? 0 : -1;
}

/* ---------------------------------------------------------------- tests -------------------- */

/* 1 when the nets' projections on some axis are disjoint (proved: interval nets, rounding
 * margin). */
/* Range of d . x over the sub-patch (d a unit vector), widened by the rounding of the sums:
 * over its box's corners, or (net) over each control point's enclosure, which is what a
 * tilted sub-patch needs (its box projects to about size |d|_1 however flat it is). */
static void proj_range(double r[2], const node *nd, const double d[3], int net)
{
    double lo = HUGE_VAL, hi = -HUGE_VAL, mag = 0;
    net = net && nd->np > 0;
    int cnt = net ? nd->np : 1;
    for (int i = 0; i < cnt; i++) {
        double l = 0, h = 0;
        for (int q = 0; q < 3; q++) {
            double pl = net ? nd->enet[3 * i + q].lo : nd->lo[q];
            double ph = net ? nd->enet[3 * i + q].hi : nd->hi[q];
            l += d[q] >= 0 ? d[q] * pl : d[q] * ph;
            h += d[q] >= 0 ? d[q] * ph : d[q] * pl;
        }
        lo = fmin(lo, l);
        hi = fmax(hi, h);
    }
    for (int q = 0; q < 3; q++)
        mag += fabs(d[q]) * fmax(fabs(nd->lo[q]), fabs(nd->hi[q]));
    r[0] = lo - 1e-14 * mag;
    r[1] = hi + 1e-14 * mag;
}

/* 1 when the sub-patches are disjoint: their boxes, or their control nets along one of the
 * directions given (the hulls lie on the two sides of a plane normal to it). */
static int separated(const node *a, const node *b, const double extra[][3], int nextra)
{
    for (int q = 0; q < 3; q++)
        if (a->hi[q] < b->lo[q] || b->hi[q] < a->lo[q])
            return 1;
    for (int net = 0; net < 2; net++)
        for (int x = 0; x < nextra; x++) {
            double r[2][2];
            proj_range(r[0], a, extra[x], net);
            proj_range(r[1], b, extra[x], net);
            if (r[0][1] < r[1][0] || r[1][1] < r[0][0])
                return 1;
        }
    return 0;
}

/* 1 when the control polygon of side (0 u = lo, 1 u = hi, 2 v = lo, 3 v = hi) of node c (a
 * patch of degree m, n) is separated from node s: that boundary curve misses s. */
static int edge_separated(const node *c, int m, int n, int side, const node *s,
                          const double extra[][3], int nextra)
{
    node t;
    _cb_iv pts[3 * 32];
    for (int q = 0; q < 3; q++) {
        t.lo[q] = HUGE_VAL;
        t.hi[q] = -HUGE_VAL;
    }
    int cnt = side < 2 ? n + 1 : m + 1;
    /* The side's own control points when they fit (its box alone otherwise). */
    t.enet = pts;
    t.np = cnt <= 32 ? cnt : 0;
    for (int k = 0; k < cnt; k++) {
        int i = side == 0 ? 0 : side == 1 ? m : k, j = side == 2 ? 0 : side == 3 ? n : k;
        const _cb_iv *p = c->enet + 3 * (i * (n + 1) + j);
        for (int q = 0; q < 3; q++) {
            t.lo[q] = fmin(t.lo[q], p[q].lo);
            t.hi[q] = fmax(t.hi[q], p[q].hi);
            if (t.np)
                pts[3 * k + q] = p[q];
        }
    }
    return separated(&t, s, extra, nextra);
}

/* A direction e with e . (a x b) > 0 proved for all normal coefficients a of A and b of B
 * (then for all normals, their convex combinations). */
static int cone_direction(double e[3], const node *A, const node *B, int na, int nb)
{
    const double *p = A->nsum, *q = B->nsum;
    e[0] = p[1] * q[2] - p[2] * q[1];
    e[1] = p[2] * q[0] - p[0] * q[2];
    e[2] = p[0] * q[1] - p[1] * q[0];
    double len = sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
    if (!(len > 0) || !isfinite(len))
        return 0;
    for (int k = 0; k < 3; k++)
        e[k] /= len;
    const double E[3] = {fabs(e[0]), fabs(e[1]), fabs(e[2])};
    const double eps = 0x1p-52;
    for (int i = 0; i < na; i++) {
        const double *a = A->nm + 3 * i, ra = A->nr[i];
        const double Aa[3] = {fabs(a[0]), fabs(a[1]), fabs(a[2])};
        for (int j = 0; j < nb; j++) {
            const double *b = B->nm + 3 * j, rb = B->nr[j];
            const double Bb[3] = {fabs(b[0]), fabs(b[1]), fabs(b[2])};
            double t = e[0] * (a[1] * b[2] - a[2] * b[1]) + e[1] * (a[2] * b[0] - a[0] * b[2]) +
                       e[2] * (a[0] * b[1] - a[1] * b[0]);
            /* |e . (a' x b') - e . (a x b)| for |a' - a|, |b' - b| <= ra, rb per component,
             * plus the rounding of t (< 8 eps of the sum of absolute terms). */
            double bound = 0;
            for (int x = 0; x < 3; x++) {
                int y = (x + 1) % 3, z = (x + 2) % 3;
                bound += E[x] * (ra * (Bb[z] + rb) + Aa[y] * rb + ra * (Bb[y] + rb) + Aa[z] * rb);
                bound += 8 * eps * E[x] * (Aa[y] * Bb[z] + Aa[z] * Bb[y]);
            }
            if (!(t > bound * (1 + 1e-12) + 1e-300))
                return 0;
        }
    }
    return 1;
}

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* 1 when the sub-patches of A and B lie in one slab of width at most w and each is a graph
 * over the slab's plane (tolerance-certificates.md section 2, steps 1 and 2, proved on the
 * interval nets and normal coefficients): wherever one lies over the other, they are within w
 * of each other along the slab's normal. The normal is the mean of the two sub-patches' mean
 * normals (B's turned to agree with A's). */
static int slab_within(const node *A, const node *B, int na, int nb, double w)
{
    double n[3], la = sqrt(dot3(A->nsum, A->nsum)), lb = sqrt(dot3(B->nsum, B->nsum));
    if (!(la > 0 && lb > 0) || !isfinite(la + lb))
        return 0;
    double sb = dot3(A->nsum, B->nsum) < 0 ? -1 : 1;
    for (int q = 0; q < 3; q++)
        n[q] = A->nsum[q] / la + sb * B->nsum[q] / lb;
    double ln = sqrt(dot3(n, n));
    if (!(ln > 0))
        return 0;
    for (int q = 0; q < 3; q++)
        n[q] /= ln;
    const double N1 = fabs(n[0]) + fabs(n[1]) + fabs(n[2]), eps = 0x1p-52;
    /* The slab: n . x over every control point enclosure of both. */
    double ra[2], rb[2];
    proj_range(ra, A, n, 1);
    proj_range(rb, B, n, 1);
    if (!(fmax(ra[1], rb[1]) - fmin(ra[0], rb[0]) <= w))
        return 0;
    const node *nd[2] = {A, B};
    /* Graphs: every normal coefficient on the same side of n (A's as given, B's times sb). */
    const int cnt[2] = {na, nb};
    const double sg[2] = {1, sb};
    for (int s = 0; s < 2; s++)
        for (int c = 0; c < cnt[s]; c++) {
            const double *m = nd[s]->nm + 3 * c;
            double d = sg[s] * (n[0] * m[0] + n[1] * m[1] + n[2] * m[2]);
            double mm = fabs(m[0]) + fabs(m[1]) + fabs(m[2]);
            if (!(d > N1 * nd[s]->nr[c] + 8 * eps * mm * N1))
                return 0;
        }
    return 1;
}

/* ---------------------------------------------------------------- boundary points ---------- */

typedef struct {
    double x[4]; /* u, v, s, t (local) */
    double h;    /* e . X */
    int entry;
    int which, side; /* on side `side` (0 u = lo, 1 u = hi, 2 v = lo, 3 v = hi) of the sub-box of
                        P (which 0) or Q (1) */
    double c;        /* that side's parameter */
    _cb_iv w;        /* Krawczyk enclosure of the free parameter along it */
} bpt;

static void cross(double c[3], const double a[3], const double b[3])
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

static double dot(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Velocity of the curve (tangent T) in the parameters of a patch with partials Xu, Xv. */
static void param_velocity(double d[2], const double Xu[3], const double Xv[3], const double T[3])
{
    double g11 = dot(Xu, Xu), g12 = dot(Xu, Xv), g22 = dot(Xv, Xv);
    double r1 = dot(Xu, T), r2 = dot(Xv, T), det = g11 * g22 - g12 * g12;
    d[0] = (g22 * r1 - g12 * r2) / det;
    d[1] = (g11 * r2 - g12 * r1) / det;
}

/* 1 when node d reaches side `side` (0 u = 0, 1 u = 1, 2 v = 0, 3 v = 1) of its patch. */
static int touches(const node *d, int side)
{
    return d->box[side] == (double)(side % 2);
}

/* Boundary points of the sub-pair: -1 ambiguous, else their number. side: 0 u = lo, 1 u = hi,
 * 2 v = lo, 3 v = hi of patch P (which = 0) or Q (which = 1). The cosides cs[k] with bit k of
 * act set run along a side of both sub-patches: those sides are not searched (their points
 * are the coside's piece), nor the strips of width ep, eq along them on the sides across
 * (roots there lie within CB_SSI_COSIDE_STRIP tol of the coside's curve: its crossing of that
 * side). */
static int boundary_points(bpt *out, const _cb_ssi_bez *P, const _cb_ssi_bez *Q, const node *a,
                           const node *b, const double e[3], long *spent,
                           const _cb_ssi_coside *cs, int ncs, unsigned act)
{
    int nb = 0;
    for (int which = 0; which < 2; which++) {
        const _cb_ssi_bez *C = which ? Q : P, *S = which ? P : Q;
        const node *cn = which ? b : a, *sn = which ? a : b;
        double ax[1][3], ls = sqrt(dot(sn->nsum, sn->nsum));
        for (int q = 0; q < 3; q++)
            ax[0][q] = sn->nsum[q] / ls;
        for (int side = 0; side < 4; side++) {
            int skip = 0;
            double wlo = 0, whi = 1;
            for (int k = 0; k < ncs; k++) {
                if (!(act >> k & 1))
                    continue;
                int s = which ? cs[k].sq : cs[k].sp;
                double strip = which ? cs[k].eq : cs[k].ep;
                if (s == side)
                    skip = 1;
                else if ((s < 2) != (side < 2)) {
                    if (s % 2 == 0)
                        wlo = fmax(wlo, strip);
                    else
                        whi = fmin(whi, 1 - strip);
                }
            }
            if (skip || edge_separated(cn, C->m, C->n, side, sn, (const double(*)[3])ax,
                                       ls > 0 && isfinite(ls)))
                continue;
            int dir = side < 2 ? 0 : 1;
            double c = cn->box[side];
            double w0 = dir == 0 ? cn->box[2] : cn->box[0], w1 = dir == 0 ? cn->box[3] : cn->box[1];
            double v0 = fmax(w0, wlo), v1 = fmin(w1, whi);
            if (!(v0 < v1))
                continue;
            _cb_ssi_edge_root r[MAX_BPTS];
            _cb_iv cnet[4 * (CB_MAX_DEGREE + 1)];
            int nc = dir == 0 ? C->n + 1 : C->m + 1, D = C->dim;
            for (int k = 0; k < nc; k++) {
                int i = side == 0   ? 0
                        : side == 1 ? C->m
                                    : k,
                    j = side == 2   ? 0
                        : side == 3 ? C->n
                                    : k;
                memcpy(cnet + D * k, cn->net + D * (i * (C->n + 1) + j),
                       (size_t)D * sizeof(_cb_iv));
            }
            if (v0 > w0 || v1 < w1)
                _cb_ssi_restrict_iv(cnet, nc - 1, D, w0, w1, v0, v1);
            int n = 0;
            if (!_cb_ssi_edge_roots(r, MAX_BPTS, &n, C, dir, c, v0, v1, cnet, S, sn->box, sn->net,
                                    EDGE_BUDGET, spent))
                return -1;
            for (int k = 0; k < n; k++) {
                if (nb == MAX_BPTS)
                    return -1;
                double cp[2] = {dir == 0 ? c : r[k].y[0], dir == 0 ? r[k].y[0] : c};
                bpt *o = out + nb++;
                o->which = which;
                o->side = side;
                o->c = c;
                o->w = r[k].k[0];
                double *own = which ? o->x + 2 : o->x, *oth = which ? o->x : o->x + 2;
                own[0] = cp[0];
                own[1] = cp[1];
                oth[0] = r[k].y[1];
                oth[1] = r[k].y[2];
                double X[3], Pu[3], Pv[3], Y[3], Qs[3], Qt[3], nP[3], nQ[3], T[3], vel[2];
                _cb_ssi_bez_eval(X, Pu, Pv, P, o->x[0], o->x[1]);
                _cb_ssi_bez_eval(Y, Qs, Qt, Q, o->x[2], o->x[3]);
                cross(nP, Pu, Pv);
                cross(nQ, Qs, Qt);
                cross(T, nP, nQ);
                if (dot(e, T) < 0)
                    for (int q = 0; q < 3; q++)
                        T[q] = -T[q];
                o->h = 0.5 * (dot(e, X) + dot(e, Y));
                if (which)
                    param_velocity(vel, Qs, Qt, T);
                else
                    param_velocity(vel, Pu, Pv, T);
                /* Across the side the velocity is non-zero at a simple root; a tiny one is
                 * too close to call. */
                double across = vel[dir] *
                                sqrt(dot(dir == 0 ? (which ? Qs : Pu) : (which ? Qt : Pv),
                                         dir == 0 ? (which ? Qs : Pu) : (which ? Qt : Pv))) /
                                sqrt(dot(T, T));
                if (!(fabs(across) > 1e-9))
                    return -1;
                o->entry = (side % 2 == 0) ? across > 0 : across < 0;
            }
        }
    }
    return nb;
}

/* ---------------------------------------------------------------- marching ----------------- */

typedef struct {
    const _cb_ssi_bez *P, *Q;
    double e[3];
    const double *bp, *bq; /* boxes */
    double tol;
    double chord, max_seg; /* for the cosides' pieces (march takes its own) */
} march_ctx;

static void jac(double J[4][4], double F[4], double X[3], double Y[3], const march_ctx *m,
                const double x[4], double h)
{
    double Pu[3], Pv[3], Qs[3], Qt[3];
    _cb_ssi_bez_eval(X, Pu, Pv, m->P, x[0], x[1]);
    _cb_ssi_bez_eval(Y, Qs, Qt, m->Q, x[2], x[3]);
    for (int q = 0; q < 3; q++) {
        J[q][0] = Pu[q];
        J[q][1] = Pv[q];
        J[q][2] = -Qs[q];
        J[q][3] = -Qt[q];
        F[q] = X[q] - Y[q];
    }
    J[3][0] = dot(m->e, Pu);
    J[3][1] = dot(m->e, Pv);
    J[3][2] = J[3][3] = 0;
    F[3] = dot(m->e, X) - h;
}

static int in_boxes(const march_ctx *m, const double x[4])
{
    const double sl = 1e-12;
    return x[0] >= m->bp[0] - sl && x[0] <= m->bp[1] + sl && x[1] >= m->bp[2] - sl &&
           x[1] <= m->bp[3] + sl && x[2] >= m->bq[0] - sl && x[2] <= m->bq[1] + sl &&
           x[3] >= m->bq[2] - sl && x[3] <= m->bq[3] + sl;
}

/* Newton onto the branch at height h; 1 when it settled inside the boxes with |P - Q| <= tol /
 * 100. Steps stall at round-off (larger where the normals are nearly parallel), so settling
 * means steps below 1e-9 once the residual is met, not a fixed round-off level. */
static int correct(double x[4], const march_ctx *m, double h)
{
    double step = HUGE_VAL;
    for (int it = 0; it < 20 && step > 1e-14; it++) {
        double J[4][4], F[4], X[3], Y[3];
        jac(J, F, X, Y, m, x, h);
        if (!cb_linsolve(&J[0][0], F, 4, 0))
            return 0;
        const double *d = F;
        step = 0;
        for (int k = 0; k < 4; k++) {
            x[k] -= d[k];
            step = fmax(step, fabs(d[k]));
        }
        if (!isfinite(step) || !in_boxes(m, x))
            return 0;
    }
    double J[4][4], F[4], X[3], Y[3];
    jac(J, F, X, Y, m, x, h);
    return step < 1e-9 && sqrt(F[0] * F[0] + F[1] * F[1] + F[2] * F[2]) <= m->tol / 100;
}

/* dx/dh along the branch at x. */
static int tangent(double t[4], const march_ctx *m, const double x[4], double h)
{
    double J[4][4], F[4], X[3], Y[3], rhs[4] = {0, 0, 0, 1};
    jac(J, F, X, Y, m, x, h);
    if (!cb_linsolve(&J[0][0], rhs, 4, 0))
        return 0;
    memcpy(t, rhs, sizeof rhs);
    return 1;
}

static void point_xyz(double X[3], const march_ctx *m, const double x[4])
{
    double A[3], B[3], d1[3], d2[3];
    _cb_ssi_bez_eval(A, d1, d2, m->P, x[0], x[1]);
    _cb_ssi_bez_eval(B, d1, d2, m->Q, x[2], x[3]);
    for (int q = 0; q < 3; q++)
        X[q] = 0.5 * (A[q] + B[q]);
}

/* Appends the point x of both patches to pc; CB_ERR_NOMEM. */
static cb_status push(_cb_ssi_piece *pc, const march_ctx *m, const double x[4])
{
    double X[3], A[3], B[3], d1[3], d2[3];
    _cb_ssi_bez_eval(A, d1, d2, m->P, x[0], x[1]);
    _cb_ssi_bez_eval(B, d1, d2, m->Q, x[2], x[3]);
    for (int q = 0; q < 3; q++)
        X[q] = 0.5 * (A[q] + B[q]);
    double gap = sqrt((A[0] - B[0]) * (A[0] - B[0]) + (A[1] - B[1]) * (A[1] - B[1]) +
                      (A[2] - B[2]) * (A[2] - B[2]));
    _cb_ssi_pq q;
    memset(&q, 0, sizeof q);
    const double *dp = m->P->dom, *dq = m->Q->dom;
    q.uv[0] = dp[0] + x[0] * (dp[1] - dp[0]);
    q.uv[1] = dp[2] + x[1] * (dp[3] - dp[2]);
    q.st[0] = dq[0] + x[2] * (dq[1] - dq[0]);
    q.st[1] = dq[2] + x[3] * (dq[3] - dq[2]);
    pc->gap = fmax(pc->gap, gap);
    return _cb_ssi_piece_push(pc, &q, X);
}

static double seg_dist(const double p[3], const double a[3], const double b[3])
{
    double ab[3], ap[3];
    for (int q = 0; q < 3; q++) {
        ab[q] = b[q] - a[q];
        ap[q] = p[q] - a[q];
    }
    double l2 = dot(ab, ab), f = l2 > 0 ? fmin(1, fmax(0, dot(ab, ap) / l2)) : 0, d = 0;
    for (int q = 0; q < 3; q++)
        d += (ap[q] - f * ab[q]) * (ap[q] - f * ab[q]);
    return sqrt(d);
}

/* x in the Bezier patch's local [0, 1] mapped to its domain [d0, d1] (0 and 1 exactly to the
 * ends, so neighbouring patches' shared sides compare equal), rounded down (dn) or up. */
static double to_dom(double x, double d0, double d1, int dn)
{
    if (x == 0)
        return d0;
    if (x == 1)
        return d1;
    double y = d0 + x * (d1 - d0);
    double e = (fabs(y) + fabs(d0) + fabs(d1 - d0)) * 0x1p-51;
    return dn < 0 ? y - e : (dn > 0 ? y + e : y);
}

/* The line of boundary point b as the end e of its piece, in the patches' domains: the
 * sub-box side it was found on and its Krawczyk enclosure along it. */
static void end_line(_cb_ssi_end *e, const march_ctx *m, const bpt *b)
{
    const double *dom = b->which ? m->Q->dom : m->P->dom;
    int dir = b->side < 2 ? 0 : 1, fr = 1 - dir;
    double c = to_dom(b->c, dom[2 * dir], dom[2 * dir + 1], 0);
    _cb_ssi_end_line *l = _cb_ssi_end_add_line(
        e, b->which, dir, b->side % 2 == 0 ? 1 : -1, c,
        to_dom(fmax(b->w.lo, 0), dom[2 * fr], dom[2 * fr + 1], -1),
        to_dom(fmin(b->w.hi, 1), dom[2 * fr], dom[2 * fr + 1], 1));
    if (l) {
        l->range[0] = dom[2 * fr];
        l->range[1] = dom[2 * fr + 1];
    }
}

/* Marches the single branch from entry a to exit b; 1 on success (piece appended), 0 when
 * marching fails, -1 when out of memory (nothing appended either way). */
static int march(_cb_ssi_piece_set *out, const march_ctx *m, const bpt *a, const bpt *b,
                 double chord, double max_seg)
{
    double span = b->h - a->h;
    if (!(span > 0))
        return 0;
    _cb_ssi_piece pc;
    _cb_ssi_piece_init(&pc);
    int ok = push(&pc, m, a->x) == CB_OK ? 1 : -1;
    double x[4], h = a->h, dh = span / 2;
    memcpy(x, a->x, sizeof x);
    while (ok == 1) {
        if (dh < span * 1e-9) {
            ok = 0;
            break;
        }
        double hn = h + dh, xn[4], xm[4], t[4];
        int last = hn >= b->h - 1e-12 * span;
        if (last) {
            hn = b->h;
            memcpy(xn, b->x, sizeof xn);
        } else {
            if (!tangent(t, m, x, h)) {
                ok = 0;
                break;
            }
            for (int k = 0; k < 4; k++)
                xn[k] = x[k] + (hn - h) * t[k];
            if (!correct(xn, m, hn)) {
                dh *= 0.5;
                continue;
            }
        }
        double X0[3], X1[3], Xm[3];
        point_xyz(X0, m, x);
        point_xyz(X1, m, xn);
        for (int k = 0; k < 4; k++)
            xm[k] = 0.5 * (x[k] + xn[k]);
        if (!correct(xm, m, 0.5 * (h + hn))) {
            dh *= 0.5;
            continue;
        }
        point_xyz(Xm, m, xm);
        double len = sqrt((X1[0] - X0[0]) * (X1[0] - X0[0]) + (X1[1] - X0[1]) * (X1[1] - X0[1]) +
                          (X1[2] - X0[2]) * (X1[2] - X0[2]));
        if (len > max_seg || seg_dist(Xm, X0, X1) > chord) {
            dh *= 0.5;
            continue;
        }
        if (push(&pc, m, xn) != CB_OK) {
            ok = -1;
            break;
        }
        memcpy(x, xn, sizeof x);
        h = hn;
        if (last)
            break;
        dh *= 1.5;
    }
    _cb_ssi_piece *p = ok == 1 ? _cb_ssi_piece_set_add(out) : NULL;
    if (p) {
        end_line(pc.end, m, a);
        end_line(pc.end + 1, m, b);
        *p = pc;
        return 1;
    }
    _cb_ssi_piece_clear(&pc);
    return ok == 1 ? -1 : ok;
}

/* The point of coside r at parameter t of P's side, as local (u, v, s, t) of both patches. */
static void coside_x(double x[4], const _cb_ssi_coside *r, double t)
{
    double mu = _cb_ssi_coside_mu(r, t);
    x[0] = r->sp < 2 ? r->sp : t;
    x[1] = r->sp < 2 ? t : r->sp - 2;
    x[2] = r->sq < 2 ? r->sq : mu;
    x[3] = r->sq < 2 ? mu : r->sq - 2;
}

/* Appends the points of coside r over (t0, t1] to pc: halved until every chord is within
 * chord of its middle point and max_seg long. */
static cb_status coside_sample(_cb_ssi_piece *pc, const march_ctx *m, const _cb_ssi_coside *r,
                               double t0, double t1, int depth)
{
    double x0[4], x1[4], xm[4], X0[3], X1[3], Xm[3];
    coside_x(x0, r, t0);
    coside_x(x1, r, t1);
    coside_x(xm, r, 0.5 * (t0 + t1));
    point_xyz(X0, m, x0);
    point_xyz(X1, m, x1);
    point_xyz(Xm, m, xm);
    if (depth < 40 && (cb_vec3_dist(X0, X1) > m->max_seg || seg_dist(Xm, X0, X1) > m->chord)) {
        cb_status st = coside_sample(pc, m, r, t0, 0.5 * (t0 + t1), depth + 1);
        return st == CB_OK ? coside_sample(pc, m, r, 0.5 * (t0 + t1), t1, depth + 1) : st;
    }
    return push(pc, m, x1);
}

/* An end of a coside's piece on the line of a sub-box side: surface sigma's parameter dir fixed
 * to c (local), the piece on half; the free parameter is the coside's side value (exact). */
static void coside_end(_cb_ssi_end *e, const _cb_ssi_bez *B, int sigma, int dir, double c,
                       int half, int side)
{
    const double *dom = B->dom;
    int fr = 1 - dir;
    double w = to_dom(side % 2, dom[2 * fr], dom[2 * fr + 1], 0);
    _cb_ssi_end_line *l =
        _cb_ssi_end_add_line(e, sigma, dir, half, to_dom(c, dom[2 * dir], dom[2 * dir + 1], 0),
                             w, w);
    if (l) {
        l->range[0] = dom[2 * fr];
        l->range[1] = dom[2 * fr + 1];
    }
}

/* The piece of coside r in the sub-pair (a, b), both reaching its sides: P's side over a's
 * range, where Q's side is in b's range. Its ends lie on the sub-box sides across it that
 * bound that range (both where they coincide); tangential: the sub-pair had no direction (the
 * surfaces within tol of each other there). 1 when a piece was appended, 0 when the ranges do
 * not overlap, -1 when out of memory. */
static int coside_piece(_cb_ssi_piece_set *out, const march_ctx *m, const node *a,
                        const node *b, const _cb_ssi_coside *r, int tangential)
{
    int dp = r->sp < 2, dq = r->sq < 2; /* the parameter along the side: 1 v, 0 u */
    double a0 = a->box[2 * dp], a1 = a->box[2 * dp + 1];
    double b0 = b->box[2 * dq], b1 = b->box[2 * dq + 1];
    double tb0 = _cb_ssi_coside_tau(r, b0), tb1 = _cb_ssi_coside_tau(r, b1);
    int rev = tb0 > tb1; /* Q's side runs against P's */
    double blo = rev ? tb1 : tb0, bhi = rev ? tb0 : tb1;
    double lo = fmax(fmax(a0, blo), r->t0), hi = fmin(fmin(a1, bhi), r->t1);
    if (!(lo < hi))
        return 0;
    _cb_ssi_piece pc;
    _cb_ssi_piece_init(&pc);
    double x[4];
    coside_x(x, r, lo);
    cb_status st = push(&pc, m, x);
    if (st == CB_OK)
        st = coside_sample(&pc, m, r, lo, hi, 0);
    _cb_ssi_piece *p = st == CB_OK ? _cb_ssi_piece_set_add(out) : NULL;
    if (!p) {
        _cb_ssi_piece_clear(&pc);
        return -1;
    }
    for (int k = 0; k < 2; k++) {
        double t = k ? hi : lo;
        _cb_ssi_end *e = pc.end + k;
        /* At a corner of P's patch the pieces of two cosides meet (two sides of one corner on
         * the other surface): the corner's number makes them one point (ssi_stitch.c). */
        if (t == 0 || t == 1) {
            double x[4];
            coside_x(x, r, t);
            e->vid = (slong)(x[0] + 2 * x[1]);
        }
        if (t == (k ? a1 : a0))
            coside_end(e, m->P, 0, dp, k ? a1 : a0, k ? -1 : 1, r->sp);
        if (t == (k ? bhi : blo)) {
            /* Q's bound giving that end: b1 where Q's side runs against P's, on its low half. */
            int upper = k != rev;
            coside_end(e, m->Q, 1, dq, upper ? b1 : b0, upper ? -1 : 1, r->sq);
        }
    }
    pc.within = 1;
    pc.side = 1;
    pc.tangential = tangential;
    *p = pc;
    return 1;
}

/* ---------------------------------------------------------------- the pair ----------------- */

static void add_box(double u[4], const double b[4], int first)
{
    if (first) {
        memcpy(u, b, 4 * sizeof(double));
        return;
    }
    u[0] = fmin(u[0], b[0]);
    u[1] = fmax(u[1], b[1]);
    u[2] = fmin(u[2], b[2]);
    u[3] = fmax(u[3], b[3]);
}

static void uncertified(_cb_ssi_spline_stats *st, const node *a, const node *b)
{
    add_box(st->box_p, a->box, st->uncertified == 0);
    add_box(st->box_q, b->box, st->uncertified == 0);
    st->uncertified++;
}

static double width(const node *d)
{
    return fmax(d->box[1] - d->box[0], d->box[3] - d->box[2]);
}

/* The certified sub-pair (a, b) along coside r (its rules decided there, within tolerance):
 * its piece of the side appended to out (coside_piece), and counted in st with its boxes (3D:
 * of the piece, or of the sub-patches where it has none) and the side's proved width. */
static void coside_add(_cb_ssi_piece_set *out, _cb_ssi_spline_stats *st, const march_ctx *m,
                       const node *a, const node *b, const _cb_ssi_coside *r, int tangential)
{
    slong n0 = out->n;
    int got = coside_piece(out, m, a, b, r, tangential);
    if (got < 0) {
        st->nomem = 1;
        return;
    }
    const _cb_ssi_piece *pc = got ? out->p + n0 : NULL;
    int first = st->side_subpairs == 0;
    add_box(st->side_box_p, a->box, first);
    add_box(st->side_box_q, b->box, first);
    for (slong i = 0; i < (pc ? pc->n : 2); i++)
        for (int q = 0; q < 3; q++) {
            double lo = pc ? pc->xyz[3 * i + q] : i ? b->lo[q] : a->lo[q];
            double hi = pc ? lo : i ? b->hi[q] : a->hi[q];
            st->side_lo[q] = first && i == 0 ? lo : fmin(st->side_lo[q], lo);
            st->side_hi[q] = first && i == 0 ? hi : fmax(st->side_hi[q], hi);
        }
    st->side_width = fmax(st->side_width, r->width);
    st->side_subpairs++;
    st->side_pieces += pc != NULL;
}

/* ---------------------------------------------------------------- within the tolerance ---- */

void _cb_ssi_tiny_set_init(_cb_ssi_tiny_set *ts) { memset(ts, 0, sizeof *ts); }

void _cb_ssi_tiny_set_clear(_cb_ssi_tiny_set *ts)
{
    free(ts->t);
    memset(ts, 0, sizeof *ts);
}

/* The point of patch Q nearest X, from the local parameters st (updated; Gauss-Newton clamped
 * to [0, 1]^2, each step kept only when it gets closer): Y = Q(st). */
static void foot_on(double st[2], double Y[3], const _cb_ssi_bez *Q, const double X[3])
{
    double Qs[3], Qt[3];
    _cb_ssi_bez_eval(Y, Qs, Qt, Q, st[0], st[1]);
    double best = (Y[0] - X[0]) * (Y[0] - X[0]) + (Y[1] - X[1]) * (Y[1] - X[1]) +
                  (Y[2] - X[2]) * (Y[2] - X[2]);
    for (int it = 0; it < 20 && best > 0; it++) {
        double a = dot3(Qs, Qs), b = dot3(Qs, Qt), c = dot3(Qt, Qt), r[3];
        for (int q = 0; q < 3; q++)
            r[q] = X[q] - Y[q];
        double p = dot3(Qs, r), q2 = dot3(Qt, r), det = a * c - b * b;
        if (!(det > 0))
            break;
        double n[2] = {fmin(1, fmax(0, st[0] + (c * p - b * q2) / det)),
                       fmin(1, fmax(0, st[1] + (a * q2 - b * p) / det))};
        double Z[3], Zs[3], Zt[3];
        _cb_ssi_bez_eval(Z, Zs, Zt, Q, n[0], n[1]);
        double e = (Z[0] - X[0]) * (Z[0] - X[0]) + (Z[1] - X[1]) * (Z[1] - X[1]) +
                   (Z[2] - X[2]) * (Z[2] - X[2]);
        if (!(e < best))
            break;
        best = e;
        memcpy(st, n, sizeof n);
        memcpy(Y, Z, sizeof Z);
        memcpy(Qs, Zs, sizeof Zs);
        memcpy(Qt, Zt, sizeof Zt);
    }
}

/* Appends the unresolved sub-pair (a, b) of pair job to ts; -1 when out of memory. */
static int tiny_add(_cb_ssi_tiny_set *ts, const node *a, const node *b, const _cb_ssi_bez *P,
                    const _cb_ssi_bez *Q, int reason, int slab, int job, double tol)
{
    if (ts->n == ts->alloc) {
        slong na = ts->alloc ? 2 * ts->alloc : 64;
        _cb_ssi_tiny *q = realloc(ts->t, (size_t)na * sizeof *q);
        if (!q)
            return -1;
        ts->t = q;
        ts->alloc = na;
    }
    _cb_ssi_tiny *t = ts->t + ts->n++;
    for (int q = 0; q < 3; q++) {
        t->lo[q] = fmin(a->lo[q], b->lo[q]);
        t->hi[q] = fmax(a->hi[q], b->hi[q]);
    }
    const double *dp = P->dom, *dq = Q->dom;
    for (int k = 0; k < 2; k++) {
        t->bp[2 * k] = dp[2 * k] + a->box[2 * k] * (dp[2 * k + 1] - dp[2 * k]);
        t->bp[2 * k + 1] = dp[2 * k] + a->box[2 * k + 1] * (dp[2 * k + 1] - dp[2 * k]);
        t->bq[2 * k] = dq[2 * k] + b->box[2 * k] * (dq[2 * k + 1] - dq[2 * k]);
        t->bq[2 * k + 1] = dq[2 * k] + b->box[2 * k + 1] * (dq[2 * k + 1] - dq[2 * k]);
    }
    /* The candidate point: P's middle and its foot on Q, each on its patch; where that is
     * farther than tol (a sub-pair where the patches meet only at their corners, as where a
     * curve along their sides passes from one patch pair to the next), the nearest of the
     * sub-patch's corners and their feet. */
    double x[4] = {0}, A[3] = {0}, B[3] = {0}, d1[3], d2[3];
    t->gap = HUGE_VAL;
    for (int k = 0; k < 5 && !(t->gap <= tol); k++) {
        double y[4] = {k ? a->box[(k - 1) & 1] : 0.5 * (a->box[0] + a->box[1]),
                       k ? a->box[2 + ((k - 1) >> 1)] : 0.5 * (a->box[2] + a->box[3]),
                       0.5 * (b->box[0] + b->box[1]), 0.5 * (b->box[2] + b->box[3])};
        double Y[3], Z[3];
        _cb_ssi_bez_eval(Y, d1, d2, P, y[0], y[1]);
        foot_on(y + 2, Z, Q, Y);
        double g = cb_vec3_dist(Y, Z);
        if (k == 0 || g < t->gap) {
            t->gap = g;
            memcpy(x, y, sizeof x);
            memcpy(A, Y, sizeof A);
            memcpy(B, Z, sizeof B);
        }
    }
    for (int q = 0; q < 3; q++)
        t->X[q] = 0.5 * (A[q] + B[q]);
    t->uv[0] = dp[0] + x[0] * (dp[1] - dp[0]);
    t->uv[1] = dp[2] + x[1] * (dp[3] - dp[2]);
    t->st[0] = dq[0] + x[2] * (dq[1] - dq[0]);
    t->st[1] = dq[2] + x[3] * (dq[3] - dq[2]);
    t->reason = reason;
    t->slab = slab;
    t->blocker = 0;
    t->job = job;
    return 0;
}

static int tiny_find(_cb_ssi_tiny *t, int k)
{
    while (t[k].root != k) {
        t[k].root = t[t[k].root].root;
        k = t[k].root;
    }
    return k;
}

static int in_box(const double X[3], const double lo[3], const double hi[3], double slack)
{
    for (int q = 0; q < 3; q++)
        if (X[q] < lo[q] - slack || X[q] > hi[q] + slack)
            return 0;
    return 1;
}

/* By low x, then by the order of arrival (root holds it while sorting). */
static int cmp_tiny(const void *x, const void *y)
{
    const _cb_ssi_tiny *a = x, *b = y;
    if (a->lo[0] != b->lo[0])
        return a->lo[0] < b->lo[0] ? -1 : 1;
    return (a->root > b->root) - (a->root < b->root);
}

/* Whether a piece end of sets lies in a box of the cluster c's members grown by tol. */
static int band_has_end(const _cb_ssi_piece_set *sets, slong nsets, _cb_ssi_tiny *t, slong nt,
                        slong c, double tol)
{
    for (slong k = 0; k < nsets; k++)
        for (slong q = 0; q < sets[k].n; q++) {
            const _cb_ssi_piece *pc = sets[k].p + q;
            /* A coside's pieces continue through the members that reach it. */
            if (pc->n < 1 || pc->closed || pc->side)
                continue;
            for (int e = 0; e < 2; e++) {
                const double *X = pc->xyz + 3 * (e ? pc->n - 1 : 0);
                for (slong i = c; i < nt; i++)
                    if (tiny_find(t, (int)i) == c && in_box(X, t[i].lo, t[i].hi, tol))
                        return 1;
            }
        }
    return 0;
}

/* The clusters of the n entries t: boxes that meet within a tenth of the tolerance are one
 * cluster. root[i] gets the smallest index of i's cluster. Sorted by low x (an index array:
 * t keeps its order), each box is compared with those after it that start before it ends in
 * x. -1 when out of memory. */
typedef struct {
    double x;
    slong i;
} lo_key;

static int cmp_lo_key(const void *x, const void *y)
{
    const lo_key *a = x, *b = y;
    if (a->x != b->x)
        return a->x < b->x ? -1 : 1;
    return (a->i > b->i) - (a->i < b->i);
}

static slong key_find(slong *root, slong k)
{
    while (root[k] != k) {
        root[k] = root[root[k]];
        k = root[k];
    }
    return k;
}

static int tiny_clusters(slong *root, const _cb_ssi_tiny *t, slong n, double tol)
{
    lo_key *key = malloc((size_t)n * sizeof *key);
    if (!key)
        return -1;
    for (slong i = 0; i < n; i++) {
        key[i].x = t[i].lo[0];
        key[i].i = i;
        root[i] = i;
    }
    qsort(key, (size_t)n, sizeof *key, cmp_lo_key);
    for (slong a = 0; a < n; a++)
        for (slong b = a + 1; b < n && key[b].x <= t[key[a].i].hi[0] + 0.1 * tol; b++)
            if (_cb_ssi_tiny_meet(t + key[a].i, t + key[b].i, 0.1 * tol)) {
                slong ra = key_find(root, key[a].i), rb = key_find(root, key[b].i);
                if (ra != rb)
                    root[ra > rb ? ra : rb] = ra < rb ? ra : rb;
            }
    for (slong i = 0; i < n; i++)
        root[i] = key_find(root, i);
    free(key);
    return 0;
}

/* The widest 3D diameter of the clusters of the n entries t; -1 when out of memory. */
static double tiny_widest(const _cb_ssi_tiny *t, slong n, double tol)
{
    slong *root = malloc((size_t)n * sizeof *root);
    double *box = malloc((size_t)n * 6 * sizeof *box);
    if (!root || !box || tiny_clusters(root, t, n, tol)) {
        free(root);
        free(box);
        return -1;
    }
    for (slong i = 0; i < n; i++)
        for (int q = 0; q < 3; q++) {
            box[6 * i + q] = HUGE_VAL;
            box[6 * i + 3 + q] = -HUGE_VAL;
        }
    for (slong i = 0; i < n; i++)
        for (int q = 0; q < 3; q++) {
            double *b = box + 6 * root[i];
            b[q] = fmin(b[q], t[i].lo[q]);
            b[3 + q] = fmax(b[3 + q], t[i].hi[q]);
        }
    double widest = 0;
    for (slong i = 0; i < n; i++)
        if (root[i] == i) {
            double d2 = 0;
            for (int q = 0; q < 3; q++)
                d2 += (box[6 * i + 3 + q] - box[6 * i + q]) * (box[6 * i + 3 + q] - box[6 * i + q]);
            widest = fmax(widest, sqrt(d2));
        }
    free(root);
    free(box);
    return widest;
}

/* Two sides lying on the other surface (_cb_ssi_coside) cross at a patch corner, a node of
 * the intersection; where the surfaces stay within tol around it, the region rid resolved
 * beside it (box lo, hi) may leave the corner just outside its box: the two sides' pieces from
 * the region's point to the corner (one end moved onto the point, the other the corner's
 * vertex, within grow of the box) are then a loop through the node's own region, dropped; the
 * sides run on from the region's point. Returns the number of ends dropped so. */
static int corner_loops(_cb_ssi_piece_set *sets, slong nsets, slong rid, const double lo[3],
                        const double hi[3], double grow)
{
    int dropped = 0;
    for (slong k = 0; k < nsets; k++) {
        _cb_ssi_piece_set *out = sets + k;
        for (slong q = 0; q < out->n; q++) {
            const _cb_ssi_piece *a = out->p + q;
            /* ea: the end not moved (the other one is on the region's point) */
            int ea = a->end[0].region == rid ? 1 : a->end[1].region == rid ? 0 : -1;
            if (!a->side || ea < 0 || a->end[ea].vid < 0 ||
                !in_box(a->xyz + 3 * (ea ? a->n - 1 : 0), lo, hi, grow))
                continue;
            for (slong r = q + 1; r < out->n; r++) {
                const _cb_ssi_piece *b = out->p + r;
                int eb = b->end[0].region == rid ? 1 : b->end[1].region == rid ? 0 : -1;
                if (!b->side || eb < 0 || b->end[eb].vid != a->end[ea].vid)
                    continue;
                /* r first: it lies after q. */
                _cb_ssi_piece_clear(out->p + r);
                memmove(out->p + r, out->p + r + 1, (size_t)(out->n - r - 1) * sizeof *out->p);
                _cb_ssi_piece_clear(out->p + q);
                memmove(out->p + q, out->p + q + 1, (size_t)(out->n - q - 2) * sizeof *out->p);
                out->n -= 2;
                q--;
                dropped += 2;
                break;
            }
        }
    }
    return dropped;
}

/* Cluster c not resolved: each pair with a member in it is bad, counts them, and its bad_box
 * (8 per pair: P's then Q's {u0, u1, v0, v1}, in the domains) takes their parameter boxes. */
static void mark_bad(_cb_ssi_tiny *t, slong nt, slong c, char *bad, long *unres,
                     double *bad_box)
{
    for (slong i = c; i < nt; i++)
        if (tiny_find(t, (int)i) == c && !t[i].blocker) {
            double *bb = bad_box + 8 * t[i].job;
            add_box(bb, t[i].bp, !bad[t[i].job]);
            add_box(bb + 4, t[i].bq, !bad[t[i].job]);
            bad[t[i].job] = 1;
            unres[t[i].job]++;
        }
}

int _cb_ssi_tiny_resolve(_cb_ssi_piece_set *sets, slong nsets, const _cb_ssi_tiny_set *tiny,
                         char *bad, long *unres, double *bad_box, double tol, long *regions,
                         long *nodes, double *width, _cb_ssi_tiny_region **out, slong *nout,
                         char *within, const cb_ssi_surface *P, const cb_ssi_surface *Q,
                         double chord, double max_seg)
{
    *out = NULL;
    *nout = 0;
    slong nt = 0, alloc_out = 0;
    for (slong k = 0; k < nsets; k++)
        nt += tiny[k].n;
    if (nt == 0)
        return 0;
    _cb_ssi_tiny *t = malloc((size_t)nt * sizeof *t);
    if (!t)
        return -1;
    nt = 0;
    for (slong k = 0; k < nsets; k++)
        for (slong i = 0; i < tiny[k].n; i++) {
            t[nt] = tiny[k].t[i];
            t[nt].root = (int)nt;
            nt++;
        }
    /* Sorted by their low x, ties by the order they came in (so the result does not depend
     * on threads), then clustered (tiny_clusters). */
    for (slong i = 0; i < nt; i++)
        t[i].root = (int)i;
    qsort(t, (size_t)nt, sizeof *t, cmp_tiny);
    slong *croot = malloc((size_t)nt * sizeof *croot);
    if (!croot || tiny_clusters(croot, t, nt, tol)) {
        free(croot);
        free(t);
        return -1;
    }
    for (slong i = 0; i < nt; i++)
        t[i].root = (int)croot[i];
    free(croot);
    int st = 0;
    for (slong c = 0; c < nt && st == 0; c++) {
        if (tiny_find(t, (int)c) != c)
            continue;
        double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
        int all_slab = 1, blocked = 0;
        for (slong i = c; i < nt; i++)
            if (tiny_find(t, (int)i) == c) {
                all_slab = all_slab && t[i].slab;
                blocked = blocked || t[i].blocker;
                for (int q = 0; q < 3; q++) {
                    lo[q] = fmin(lo[q], t[i].lo[q]);
                    hi[q] = fmax(hi[q], t[i].hi[q]);
                }
            }
        double diam = sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                           (hi[2] - lo[2]) * (hi[2] - lo[2]));
        /* A contact band: its curves traced along the valley of the distance; one that holds
         * branch ends, or where no valley was traced, is one point (_cb_ssi_band_node). */
        if (!blocked && all_slab && diam > WT_MAX_TOL * tol && P && Q) {
            slong nm = 0;
            for (slong i = c; i < nt; i++)
                nm += tiny_find(t, (int)i) == c;
            const _cb_ssi_tiny **m = malloc((size_t)nm * sizeof *m);
            slong rid = *nout;
            int res = -1;
            if (m) {
                nm = 0;
                for (slong i = c; i < nt; i++)
                    if (tiny_find(t, (int)i) == c)
                        m[nm++] = t + i;
                res = band_has_end(sets, nsets, t, nt, c, tol)
                          ? 0
                          : _cb_ssi_band_trace(sets + t[c].job, sets, nsets, P, Q, m, nm, tol,
                                               chord, max_seg);
                _cb_ssi_tiny_region *rg =
                    res > 0 ? _cb_ssi_region_slot(out, *nout, &alloc_out) : NULL;
                if (rg) {
                    (*nout)++;
                    memset(rg, 0, sizeof *rg);
                    memcpy(rg->lo, lo, sizeof rg->lo);
                    memcpy(rg->hi, hi, sizeof rg->hi);
                    rg->width = diam;
                    memcpy(rg->X, t[c].X, sizeof rg->X);
                    memcpy(rg->uv, t[c].uv, sizeof rg->uv);
                    memcpy(rg->st, t[c].st, sizeof rg->st);
                    rg->slab = 1;
                    rg->job = t[c].job;
                } else if (res > 0) {
                    res = -1;
                } else if (res == 0) {
                    res = _cb_ssi_band_node(sets, nsets, P, Q, m, nm, tol, chord, max_seg,
                                            t[c].job, out, nout, &alloc_out, within);
                }
            }
            free(m);
            if (res < 0) {
                st = -1;
                break;
            }
            if (res > 0) {
                for (slong i = c; i < nt; i++)
                    if (tiny_find(t, (int)i) == c)
                        within[t[i].job] = 1;
                (*regions)++;
                *nodes += (*out)[rid].ends > 0;
                *width = fmax(*width, diam);
                continue;
            }
        }
        if (blocked || !(diam <= tol || (all_slab && diam <= WT_MAX_TOL * tol))) {
            mark_bad(t, nt, c, bad, unres, bad_box);
            continue;
        }
        /* The point: the candidate of the member nearest the cluster's centre among those
         * whose two surface points are within tol (so the point is within tol / 2 of both);
         * with none, the region is not resolved. */
        double cen[3] = {0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])};
        slong best = -1;
        double bd = HUGE_VAL;
        for (slong i = c; i < nt; i++) {
            if (tiny_find(t, (int)i) != c || !(t[i].gap <= tol))
                continue;
            double m[3] = {0.5 * (t[i].lo[0] + t[i].hi[0]), 0.5 * (t[i].lo[1] + t[i].hi[1]),
                           0.5 * (t[i].lo[2] + t[i].hi[2])};
            double d = sqrt((m[0] - cen[0]) * (m[0] - cen[0]) + (m[1] - cen[1]) * (m[1] - cen[1]) +
                            (m[2] - cen[2]) * (m[2] - cen[2]));
            if (d < bd) {
                bd = d;
                best = i;
            }
        }
        if (best < 0) {
            mark_bad(t, nt, c, bad, unres, bad_box);
            continue;
        }
        _cb_ssi_pq node_pq;
        memset(&node_pq, 0, sizeof node_pq);
        memcpy(node_pq.uv, t[best].uv, sizeof node_pq.uv);
        memcpy(node_pq.st, t[best].st, sizeof node_pq.st);
        double X[3];
        memcpy(X, t[best].X, sizeof X);
        /* Onto the intersection where Newton's method takes it within the region's diameter
         * of it: within tol of both surfaces either way, but the ends moved there then run on
         * along the curve (a crossing at a small angle leaves a region of hundreds of tol along
         * its curve, one along a patch side may be thinner than the curve's distance from the
         * candidate). */
        if (P && Q)
            _cb_ssi_band_zero_point(P, Q, node_pq.uv, node_pq.st, X, lo, hi, diam, tol);
        /* Its record, whose index the moved ends carry (stitching joins them). */
        slong rid = *nout;
        _cb_ssi_tiny_region *rg = _cb_ssi_region_slot(out, *nout, &alloc_out);
        if (!rg) {
            st = -1;
            break;
        }
        (*nout)++;
        memcpy(rg->lo, lo, sizeof rg->lo);
        memcpy(rg->hi, hi, sizeof rg->hi);
        rg->width = diam;
        memcpy(rg->X, X, sizeof rg->X);
        memcpy(rg->uv, node_pq.uv, sizeof rg->uv);
        memcpy(rg->st, node_pq.st, sizeof rg->st);
        rg->slab = all_slab;
        rg->job = t[c].job;
        for (slong i = c; i < nt; i++)
            if (tiny_find(t, (int)i) == c)
                within[t[i].job] = 1;
        /* Branch ends in the region (grown by the tolerance) move onto the point; a piece
         * lying wholly in it (between two of its sub-pairs) is dropped. */
        int ends = 0, touched = 0;
        for (slong k = 0; k < nsets; k++) {
            _cb_ssi_piece_set *out = sets + k;
            for (slong q = 0; q < out->n; q++) {
                _cb_ssi_piece *pc = out->p + q;
                if (pc->isolated || pc->n < 2)
                    continue;
                int inside = 1;
                for (slong i = 0; i < pc->n && inside; i++)
                    inside = in_box(pc->xyz + 3 * i, lo, hi, tol);
                /* The polyline's vertices may all lie outside a region its chords cross. */
                for (slong i = 0; i < pc->n && !touched; i++) {
                    const double *A = pc->xyz + 3 * i, *B = i + 1 < pc->n ? A + 3 : A;
                    touched = cb_seg3_meets_box(A, B, lo, hi, tol);
                }
                if (inside) {
                    _cb_ssi_piece_clear(pc);
                    memmove(pc, pc + 1, (size_t)(out->n - q - 1) * sizeof *pc);
                    out->n--;
                    q--;
                    continue;
                }
                for (int e = 0; e < 2; e++) {
                    slong i = e ? pc->n - 1 : 0;
                    if (!in_box(pc->xyz + 3 * i, lo, hi, tol))
                        continue;
                    pc->pt[i] = node_pq;
                    memcpy(pc->xyz + 3 * i, X, 3 * sizeof(double));
                    /* Moved: its vertex, sides and enclosures describe another point now. */
                    _cb_ssi_end_clear(pc->end + e);
                    pc->end[e].region = rid;
                    within[k] = 1;
                    ends++;
                }
            }
        }
        ends -= corner_loops(sets, nsets, rid, lo, hi, diam);
        /* No end and no branch through it: one isolated contact point, unless it lies
         * near a region branches end in (below). A region a branch runs through or beside
         * (surfaces crossing at a small angle near it) is that branch's. */
        rg->lone = ends == 0 && !touched;
        rg->ends = ends;
        (*regions)++;
        *nodes += ends > 0;
        *width = fmax(*width, diam);
    }
    /* A lone region within WT_MAX_TOL tol of a region that branch ends joined (a pocket
     * where the surfaces stay within tol beside a cusp's or node's region, separated from it
     * by sub-pairs proved apart) is part of that feature within the tolerance, as is one
     * within WT_MAX_TOL tol of a wider lone region (one contact whose region sub-pairs proved
     * apart cut in two); the others are isolated contact points. */
    for (slong g = 0; g < *nout && st == 0; g++) {
        _cb_ssi_tiny_region *rg = *out + g;
        if (!rg->lone)
            continue;
        int near = 0;
        for (slong h = 0; h < *nout && !near; h++) {
            const _cb_ssi_tiny_region *o = *out + h;
            int wider = o->lone && (o->width > rg->width || (o->width == rg->width && h < g));
            if (h == g || (o->ends == 0 && !wider))
                continue;
            double d2 = 0;
            for (int q = 0; q < 3; q++) {
                double gap = fmax(o->lo[q] - rg->hi[q], rg->lo[q] - o->hi[q]);
                d2 += gap > 0 ? gap * gap : 0;
            }
            near = sqrt(d2) <= WT_MAX_TOL * tol;
        }
        if (near)
            continue;
        _cb_ssi_pq pq;
        memset(&pq, 0, sizeof pq);
        memcpy(pq.uv, rg->uv, sizeof pq.uv);
        memcpy(pq.st, rg->st, sizeof pq.st);
        _cb_ssi_piece *pc = _cb_ssi_piece_set_add(sets + rg->job);
        if (!pc || _cb_ssi_piece_push(pc, &pq, rg->X) != CB_OK) {
            st = -1;
        } else {
            pc->isolated = pc->tangential = 1;
            pc->end[0].region = g;
        }
    }
    free(t);
    return st;
}

void _cb_ssi_spline_pair(_cb_ssi_piece_set *out, _cb_ssi_spline_stats *st, const _cb_ssi_bez *P,
                         const _cb_ssi_bez *Q, const _cb_ssi_spline_opts *o,
                         _cb_ssi_tiny_set *tiny, int job)
{
    memset(st, 0, sizeof(*st));
    tree TP, TQ;
    int okp = tree_init(&TP, P, SPLIT_LO, SPLIT_HI) == 0,
        okq = tree_init(&TQ, Q, SPLIT_Q_HI, SPLIT_Q_LO) == 0;
    double floor_w = ldexp(1.0, -o->max_depth);
    long alloc = 64, sp = 0;
    int(*stack)[2] = malloc((size_t)alloc * sizeof(*stack));
    if (!okp || !okq || !stack) {
        /* Out of memory: nothing is known of the pair, which says so. */
        st->nomem = 1;
        st->uncertified = 1;
        free(stack);
        if (okp)
            tree_clear(&TP);
        if (okq)
            tree_clear(&TQ);
        return;
    }
    stack[sp][0] = 0;
    stack[sp][1] = 0;
    sp++;
    /* Sides lying on each other: their curve is taken as it is (_cb_ssi_coside). */
    _cb_ssi_coside cs[MAX_COSIDES];
    int ncs = _cb_ssi_cosides_find(cs, MAX_COSIDES, P, Q, o->tol);
    /* A band run is kept only when it leaves nothing uncertified (ssi_pairs.c): once one
     * sub-pair is, the rest is not needed. */
    /* A run that is not the band run gives up once a cluster of its tangent sub-pairs is
     * wider than WT_MAX_TOL tol: it could resolve it only as a contact band, which the band
     * run covers with far fewer sub-pairs (checked each time TINY_CHECK more have come). */
    slong tiny0 = tiny->n, tiny_seen = tiny->n;
    int wide = 0;
    while (sp > 0 && !st->nomem && !(o->band && st->uncertified > 0)) {
        if (!o->band && !wide && tiny->n - tiny_seen >= TINY_CHECK) {
            tiny_seen = tiny->n;
            double w = tiny_widest(tiny->t + tiny0, tiny->n - tiny0, o->tol);
            if (w < 0) {
                st->nomem = 1;
                break;
            }
            wide = st->wide = w > WT_MAX_TOL * o->tol;
        }
        sp--;
        int ia = stack[sp][0], ib = stack[sp][1];
        /* The boundary-root searches' boxes have a budget too (the band run's: a band is
         * crossed by slabs, and where roots cost the work, curves along patch sides at 45
         * boxes per sub-pair against under 7, the second run would only be long). */
        if (wide || st->subpairs >= o->max_subpairs ||
            (o->max_edge_boxes > 0 && st->edge_boxes >= o->max_edge_boxes)) {
            uncertified(st, TP.nd + ia, TQ.nd + ib);
            /* A region left open here: a tangent region meeting it is not resolved. */
            if (tiny_add(tiny, TP.nd + ia, TQ.nd + ib, P, Q, 0, 0, job, o->tol))
                st->nomem = 1;
            else
                tiny->t[tiny->n - 1].blocker = 1;
            continue;
        }
        st->subpairs++;
        const node *a = TP.nd + ia, *b = TQ.nd + ib;
        double axes[3][3];
        double la = sqrt(dot(a->nsum, a->nsum)), lb = sqrt(dot(b->nsum, b->nsum));
        int nax = 0;
        if (la > 0 && isfinite(la)) {
            for (int q = 0; q < 3; q++)
                axes[nax][q] = a->nsum[q] / la;
            nax++;
        }
        if (lb > 0 && isfinite(lb)) {
            for (int q = 0; q < 3; q++)
                axes[nax][q] = b->nsum[q] / lb;
            nax++;
        }
        if (separated(a, b, (const double(*)[3])axes, nax))
            continue;
        double e[3];
        int reason = 0; /* 1 no direction, 2 ambiguous roots, 3 several or inconsistent ends */
        bpt bp[MAX_BPTS];
        int nb = 0;
        /* The cosides both sub-patches reach. */
        unsigned act = 0;
        for (int k = 0; k < ncs; k++)
            act |= (unsigned)(touches(a, cs[k].sp) && touches(b, cs[k].sq)) << k;
        if (!cone_direction(e, a, b, TP.nn, TQ.nn)) {
            reason = 1;
            /* Along a coside where the sub-patches are proved within tol of each other and no
             * boundary root lies off the coside: its piece stands for the intersection there
             * (a contact band along the side, as beside a node at a corner; within tolerance,
             * tolerance-certificates.md section 2). e only orients roots, of which there are
             * none. */
            double la = sqrt(dot(a->nsum, a->nsum));
            if (act && la > 0 && isfinite(la) && slab_within(a, b, TP.nn, TQ.nn, o->tol)) {
                for (int q = 0; q < 3; q++)
                    e[q] = a->nsum[q] / la;
                if (boundary_points(bp, P, Q, a, b, e, &st->edge_boxes, cs, ncs, act) == 0)
                    reason = -1;
            }
        }
        if (!reason) {
            nb = boundary_points(bp, P, Q, a, b, e, &st->edge_boxes, cs, ncs, act);
            if (nb < 0)
                reason = 2;
            else if (nb > 0) {
                int ne = 0;
                for (int k = 0; k < nb; k++)
                    ne += bp[k].entry;
                /* Several branches, or two ends that do not read as entry below exit. */
                if (nb != 2 || ne != 1 || !(bp[bp[0].entry].h > bp[!bp[0].entry].h))
                    reason = 3;
            }
        }
        int touching = reason == -1;
        if (touching)
            reason = 0; /* nb = 0: only the cosides' pieces */
        if (!reason) {
            st->certified++;
            march_ctx mc = {P, Q, {e[0], e[1], e[2]}, a->box, b->box, o->tol, o->chord,
                            o->max_seg};
            for (int k = 0; k < ncs && !st->nomem; k++)
                if (act >> k & 1)
                    coside_add(out, st, &mc, a, b, cs + k, touching);
            if (nb == 2) {
                const bpt *en = bp[0].entry ? bp : bp + 1, *ex = bp[0].entry ? bp + 1 : bp;
                st->branches++;
                int marched = march(out, &mc, en, ex, o->chord, o->max_seg);
                if (marched < 0)
                    st->nomem = 1;
                if (marched == 0)
                    st->march_failed++;
                if (marched <= 0)
                    uncertified(st, a, b);
            }
            continue;
        }
        /* Both sub-patches within TINY_TOL tol, or within STOP_TOL tol and proved within tol
         * of each other: not split further; resolved with the others of its cluster after the
         * traversal. */
        int small = o->band ||
                    (a->size <= STOP_TOL * o->tol && b->size <= STOP_TOL * o->tol);
        int slab = small && slab_within(a, b, TP.nn, TQ.nn, o->tol);
        if ((a->size <= TINY_TOL * o->tol && b->size <= TINY_TOL * o->tol) || slab) {
            if (tiny_add(tiny, a, b, P, Q, reason, slab, job, o->tol)) {
                st->nomem = 1;
                uncertified(st, a, b);
                break;
            }
            st->unresolved++;
            /* The cosides it reaches are curves of the intersection whatever its region is
             * resolved as: their pieces continue the side through it (a region's rule moves
             * or drops them as any other piece; a contact band's valley ends on them). */
            march_ctx mc = {P, Q, {0, 0, 0}, a->box, b->box, o->tol, o->chord, o->max_seg};
            for (int k = 0; k < ncs && !st->nomem; k++)
                if (act >> k & 1)
                    coside_add(out, st, &mc, a, b, cs + k, 1);
            continue;
        }
        /* Split the larger sub-patch that is above the floor. */
        int can_a = width(a) > floor_w, can_b = width(b) > floor_w;
        if (!can_a && !can_b) {
            st->no_direction += reason == 1;
            st->ambiguous_roots += reason == 2;
            st->many_branches += reason == 3;
            uncertified(st, a, b);
            if (tiny_add(tiny, a, b, P, Q, reason, 0, job, o->tol))
                st->nomem = 1;
            else
                tiny->t[tiny->n - 1].blocker = 1;
            continue;
        }
        int split_a = can_a && (!can_b || a->size >= b->size);
        int split = split_a ? node_split(&TP, ia) : node_split(&TQ, ib);
        if (!split && sp + 4 > alloc) {
            int(*q)[2] = realloc(stack, (size_t)(2 * alloc) * sizeof(*stack));
            if (q) {
                stack = q;
                alloc *= 2;
            } else {
                split = -1;
            }
        }
        if (split) {
            st->nomem = 1;
            uncertified(st, TP.nd + ia, TQ.nd + ib);
            break;
        }
        for (int c = 3; c >= 0; c--) {
            stack[sp][0] = split_a ? TP.nd[ia].child[c] : ia;
            stack[sp][1] = split_a ? ib : TQ.nd[ib].child[c];
            sp++;
        }
    }
    free(stack);
    tree_clear(&TP);
    tree_clear(&TQ);
}
