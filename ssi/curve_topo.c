/* Certified topology of phi(s, t) = 0 in a box: the sweep over critical lines (ssi/curve_topo.h). */
#include "ssi/curve_topo.h"

#include <string.h>

#include <flint/fmpz_mpoly_factor.h>

void cb_ctopo_opts_default(cb_ctopo_opts *o)
{
    o->coord_bits = 40;
    o->prec = 128;
    o->max_attempts = 40;
    /* Input rounded to doubles puts features that coincide in exact geometry (a fold of the
     * curve on a patch side, where a plane parallel to a torus's axis meets its equator) a
     * relative 2^-53 apart, so two fibre roots can lie ~2^-53 apart in t: 64 levels separate
     * them. The depth is spent only where a box fails its tests, so certified boxes elsewhere
     * cost nothing more. */
    o->max_depth = 64;
}

void cb_ctopo_init(cb_ctopo_t T)
{
    memset(T, 0, sizeof *T);
}

static void vertex_clear(cb_ctopo_vertex_struct *v)
{
    fmpq_clear(v->s_lo);
    fmpq_clear(v->s_hi);
    fmpq_clear(v->t_lo);
    fmpq_clear(v->t_hi);
}

void cb_ctopo_clear(cb_ctopo_t T)
{
    for (slong i = 0; i < T->n_lines; i++) {
        cb_ctopo_line_struct *L = T->line + i;
        fmpq_clear(L->lo);
        fmpq_clear(L->hi);
        fmpq_clear(L->left);
        fmpq_clear(L->right);
    }
    for (slong i = 0; i < T->n_vertices; i++)
        vertex_clear(T->vertex + i);
    flint_free(T->line);
    flint_free(T->vertex);
    flint_free(T->edge);
    flint_free(T->component_tangential);
    cb_bipoly_clear(T->h);
    memset(T, 0, sizeof *T);
}

/* ---------------------------------------------------------------------- graph building ----- */

static slong vertex_push(cb_ctopo_t T, cb_ctopo_kind kind, const fmpq_t s_lo, const fmpq_t s_hi,
                         const fmpq_t t_lo, const fmpq_t t_hi, slong line)
{
    if (T->n_vertices == T->alloc_vertices) {
        T->alloc_vertices = T->alloc_vertices ? 2 * T->alloc_vertices : 32;
        T->vertex = flint_realloc(T->vertex, (size_t)T->alloc_vertices * sizeof *T->vertex);
    }
    slong i = T->n_vertices++;
    cb_ctopo_vertex_struct *v = T->vertex + i;
    memset(v, 0, sizeof *v);
    fmpq_init(v->s_lo);
    fmpq_init(v->s_hi);
    fmpq_init(v->t_lo);
    fmpq_init(v->t_hi);
    fmpq_set(v->s_lo, s_lo);
    fmpq_set(v->s_hi, s_hi);
    fmpq_set(v->t_lo, t_lo);
    fmpq_set(v->t_hi, t_hi);
    v->kind = kind;
    v->line = line;
    v->component = -1;
    return i;
}

static void edge_push(cb_ctopo_t T, slong v0, slong v1, int vertical, int tangential)
{
    if (T->n_edges == T->alloc_edges) {
        T->alloc_edges = T->alloc_edges ? 2 * T->alloc_edges : 32;
        T->edge = flint_realloc(T->edge, (size_t)T->alloc_edges * sizeof *T->edge);
    }
    cb_ctopo_edge_struct *e = T->edge + T->n_edges++;
    e->v0 = v0;
    e->v1 = v1;
    e->vertical = vertical;
    e->tangential = tangential;
}

static double mid_d(const fmpq_t lo, const fmpq_t hi)
{
    fmpq_t m;
    fmpq_init(m);
    fmpq_add(m, lo, hi);
    fmpq_div_2exp(m, m, 1);
    double d = fmpq_get_d(m);
    fmpq_clear(m);
    return d;
}

static unsigned t_sides(const fmpq_t t0, const fmpq_t t1, const fmpq_t lo, const fmpq_t hi)
{
    if (!fmpq_equal(lo, hi))
        return 0;
    return fmpq_equal(lo, t0) ? CB_CTOPO_SIDE_T0 : fmpq_equal(lo, t1) ? CB_CTOPO_SIDE_T1 : 0;
}

/* Vertices of the helping roots R on the line s = a; returns the first index. A root lies on
 * a repeated factor g iff g(a, .) (squarefree there: a is not critical) changes sign on, or
 * vanishes at, its isolating interval. */
static slong helping_vertices(cb_ctopo_t T, const cb_bipoly_t rep, const fmpq_t t0,
                              const fmpq_t t1, cb_roots_t R, const fmpq_t a, slong width_bits)
{
    slong first = T->n_vertices;
    fmpz_poly_t g;
    fmpq_t w, v;
    fmpz_poly_init(g);
    fmpq_init(w);
    fmpq_init(v);
    fmpz_one(fmpq_numref(w));
    fmpz_one_2exp(fmpq_denref(w), (ulong)width_bits);
    if (rep->len > 1)
        cb_bipoly_eval_s_fmpq(g, rep, a);
    for (slong j = 0; j < R->n; j++) {
        cb_roots_refine(R, j, w);
        const cb_root_interval_struct *iv = R->root + j;
        slong id = vertex_push(T, CB_CTOPO_HELPING, a, a, iv->lo, iv->hi, -1);
        cb_ctopo_vertex_struct *x = T->vertex + id;
        x->s = fmpq_get_d(a);
        x->t = mid_d(iv->lo, iv->hi);
        x->rank = j;
        x->count = R->n;
        x->sides = t_sides(t0, t1, iv->lo, iv->hi);
        if (rep->len > 1) {
            int sl, sh;
            fmpz_poly_evaluate_fmpq(v, g, iv->lo);
            sl = fmpq_sgn(v);
            fmpz_poly_evaluate_fmpq(v, g, iv->hi);
            sh = fmpq_sgn(v);
            x->tangential = fmpq_equal(iv->lo, iv->hi) ? sl == 0 : sl * sh < 0;
        }
    }
    fmpq_clear(v);
    fmpq_clear(w);
    fmpz_poly_clear(g);
    return first;
}

/* --------------------------------------------------------------------- curve preparation --- */

static void curve_init(cb_ctopo_curve_struct *C)
{
    memset(C, 0, sizeof *C);
    cb_bipoly_init(C->h);
    cb_bipoly_init(C->rep);
    fmpz_poly_init(C->rep_res);
    fmpz_poly_init(C->res);
    fmpz_poly_init(C->lc);
    fmpz_poly_init(C->bnd[0]);
    fmpz_poly_init(C->bnd[1]);
    fmpq_init(C->s0);
    fmpq_init(C->s1);
    fmpq_init(C->t0);
    fmpq_init(C->t1);
}

static void curve_clear(cb_ctopo_curve_struct *C)
{
    cb_bipoly_clear(C->h);
    cb_bipoly_clear(C->rep);
    fmpz_poly_clear(C->rep_res);
    fmpz_poly_clear(C->res);
    fmpz_poly_clear(C->lc);
    fmpz_poly_clear(C->bnd[0]);
    fmpz_poly_clear(C->bnd[1]);
    fmpq_clear(C->s0);
    fmpq_clear(C->s1);
    fmpq_clear(C->t0);
    fmpq_clear(C->t1);
}

/* p = p / (den t - num) for a rational root num/den of p in t, exactly. */
static void divide_linear_t(cb_bipoly_t p, const fmpq_t r, const fmpz_mpoly_ctx_t ctx)
{
    fmpz_mpoly_t P, L;
    ulong e[2] = {0, 1};
    fmpz_mpoly_init(P, ctx);
    fmpz_mpoly_init(L, ctx);
    cb_bipoly_get_fmpz_mpoly(P, p, ctx);
    fmpz_mpoly_set_coeff_fmpz_ui(L, fmpq_denref(r), e, ctx);
    e[1] = 0;
    fmpz_t c;
    fmpz_init(c);
    fmpz_neg(c, fmpq_numref(r));
    fmpz_mpoly_set_coeff_fmpz_ui(L, c, e, ctx);
    fmpz_mpoly_divides(P, P, L, ctx);
    cb_bipoly_set_fmpz_mpoly(p, P, ctx);
    fmpz_clear(c);
    fmpz_mpoly_clear(L, ctx);
    fmpz_mpoly_clear(P, ctx);
}

static void sqfree_part(fmpz_poly_t out, const fmpz_poly_t p)
{
    if (fmpz_poly_degree(p) < 1) {
        fmpz_poly_one(out);
        return;
    }
    fmpz_poly_t g;
    fmpz_poly_init(g);
    fmpz_poly_derivative(g, p);
    fmpz_poly_gcd(g, p, g);
    fmpz_poly_div(out, p, g);
    fmpz_poly_clear(g);
}

/* Splits phi: h (squarefree, no content in t), rep (its repeated factors), cont and cont_rep
 * (the content in t and its repeated factors), then the polynomials the sweep needs. */
static void curve_prepare(cb_ctopo_curve_struct *C, fmpz_poly_t cont, fmpz_poly_t cont_rep,
                          int *repeated, const fmpz_mpoly_t phi, const fmpz_mpoly_ctx_t ctx)
{
    fmpz_mpoly_factor_t fac;
    fmpz_mpoly_t H, G;
    cb_bipoly_t f;
    fmpz_mpoly_factor_init(fac, ctx);
    fmpz_mpoly_init(H, ctx);
    fmpz_mpoly_init(G, ctx);
    cb_bipoly_init(f);
    fmpz_mpoly_factor_squarefree(fac, phi, ctx);
    fmpz_mpoly_one(H, ctx);
    fmpz_mpoly_one(G, ctx);
    fmpz_poly_one(cont);
    fmpz_poly_one(cont_rep);
    *repeated = 0;
    for (slong i = 0; i < fac->num; i++) {
        if (fmpz_mpoly_is_fmpz(fac->poly + i, ctx))
            continue;
        int rep = fmpz_cmp_ui(fac->exp + i, 1) > 0;
        *repeated |= rep;
        cb_bipoly_set_fmpz_mpoly(f, fac->poly + i, ctx);
        if (f->len == 1) {
            fmpz_poly_mul(cont, cont, f->c);
            if (rep)
                fmpz_poly_mul(cont_rep, cont_rep, f->c);
        } else {
            fmpz_mpoly_mul(H, H, fac->poly + i, ctx);
            if (rep)
                fmpz_mpoly_mul(G, G, fac->poly + i, ctx);
        }
    }
    cb_bipoly_set_fmpz_mpoly(C->h, H, ctx);
    cb_bipoly_set_fmpz_mpoly(C->rep, G, ctx);
    if (C->rep->len > 1)
        cb_bipoly_resultant_dt(C->rep_res, C->rep);

    /* Box sides t = t_i lying on the curve, and the boundary polynomials without them. */
    cb_bipoly_t hb;
    cb_bipoly_init(hb);
    for (int i = 0; i < 2; i++) {
        const fmpq *ti = i ? C->t1 : C->t0;
        cb_bipoly_eval_t_fmpq(C->bnd[i], C->h, ti);
        C->side_t[i] = fmpz_poly_is_zero(C->bnd[i]);
        if (C->side_t[i]) {
            cb_bipoly_set(hb, C->h);
            divide_linear_t(hb, ti, ctx);
            cb_bipoly_eval_t_fmpq(C->bnd[i], hb, ti);
        }
    }
    cb_bipoly_clear(hb);
    fmpz_poly_set(C->lc, C->h->c + C->h->len - 1);
    if (C->h->len > 1)
        cb_bipoly_resultant_dt(C->res, C->h);
    else
        fmpz_poly_one(C->res);

    cb_bipoly_clear(f);
    fmpz_mpoly_clear(G, ctx);
    fmpz_mpoly_clear(H, ctx);
    fmpz_mpoly_factor_clear(fac, ctx);
}

/* Precision for ball tests on h: h is evaluated where it is tiny, so the relative precision
 * needed grows with the size of its terms there — the coefficient bits, plus the degree times
 * the bits of the largest box coordinate, plus the bits of the number of terms — on top of the
 * margin opts->prec. */
static slong curve_prec(const cb_ctopo_curve_struct *C)
{
    slong bits = 0;
    for (slong j = 0; j < C->h->len; j++)
        bits = FLINT_MAX(bits, FLINT_ABS(fmpz_poly_max_bits(C->h->c + j)));
    slong ds = FLINT_MAX(cb_bipoly_deg_s(C->h), 0), dt = FLINT_MAX(C->h->len - 1, 0);
    slong mag = 0;
    const fmpq *corner[4] = {C->s0, C->s1, C->t0, C->t1};
    for (int i = 0; i < 4; i++) {
        /* bits of |corner| rounded up, 0 inside [-1, 1] */
        slong b = (slong)fmpz_bits(fmpq_numref(corner[i])) - (slong)fmpz_bits(fmpq_denref(corner[i])) + 1;
        mag = FLINT_MAX(mag, b);
    }
    return C->opts->prec + bits + (ds + dt) * mag + FLINT_BIT_COUNT((ulong)((ds + 1) * (dt + 1)));
}

/* ------------------------------------------------------------------------ critical lines --- */

static void line_init(cb_ctopo_line_struct *L)
{
    memset(L, 0, sizeof *L);
    fmpq_init(L->lo);
    fmpq_init(L->hi);
    fmpq_init(L->left);
    fmpq_init(L->right);
}

/* Largest 2^-e <= x (x > 0). */
static void dyadic_below(fmpq_t out, const fmpq_t x)
{
    fmpq_one(out);
    while (fmpq_cmp(out, x) > 0)
        fmpq_div_2exp(out, out, 1);
    fmpq_t d;
    fmpq_init(d);
    fmpq_mul_2exp(d, out, 1);
    while (fmpq_cmp(d, x) <= 0) {
        fmpq_set(out, d);
        fmpq_mul_2exp(d, d, 1);
    }
    fmpq_clear(d);
}

/* Is root k of cv exactly s0 or s1 (then it is that side's line)? */
static int root_is_side(const cb_roots_t cv, slong k, const cb_ctopo_curve_struct *C)
{
    const cb_root_interval_struct *iv = cv->root + k;
    return fmpq_equal(iv->lo, iv->hi) && (fmpq_equal(iv->lo, C->s0) || fmpq_equal(iv->lo, C->s1));
}

/* The critical lines: s0, the roots of disc strictly inside, s1. root_of[i] is the index in
 * cv of line i's value (or -1). Intervals are refined until they do not touch; a rational
 * line gets helping lines alpha -+ eps with eps a power of two at most a quarter of the gaps
 * to its neighbours' intervals, so no other critical value lies within eps of it. */
static void lines_build(cb_ctopo_t T, slong **root_of, const cb_ctopo_curve_struct *C,
                        cb_roots_t cv)
{
    slong n = 2;
    for (slong k = 0; k < cv->n; k++)
        n += !root_is_side(cv, k, C);
    T->line = flint_malloc((size_t)n * sizeof *T->line);
    *root_of = flint_malloc((size_t)n * sizeof **root_of);
    slong m = 0;
    for (slong k = -1; k <= cv->n; k++) {
        int first = k == -1, last = k == cv->n;
        if (!first && !last && root_is_side(cv, k, C))
            continue;
        cb_ctopo_line_struct *L = T->line + m;
        line_init(L);
        (*root_of)[m] = first || last ? -1 : k;
        if (first || last) {
            fmpq_set(L->lo, first ? C->s0 : C->s1);
            fmpq_set(L->hi, L->lo);
        } else {
            fmpq_set(L->lo, cv->root[k].lo);
            fmpq_set(L->hi, cv->root[k].hi);
        }
        L->has_left = !first;
        L->has_right = !last;
        m++;
    }
    T->n_lines = m;

    /* Separate touching neighbours (only irrational intervals can be shrunk; two exact
     * values are distinct). */
    fmpq_t w, gap, eps;
    fmpq_init(w);
    fmpq_init(gap);
    fmpq_init(eps);
    for (slong i = 0; i + 1 < m; i++) {
        cb_ctopo_line_struct *A = T->line + i, *B = T->line + i + 1;
        while (fmpq_cmp(A->hi, B->lo) >= 0) {
            slong ks[2] = {(*root_of)[i], (*root_of)[i + 1]};
            cb_ctopo_line_struct *Ls[2] = {A, B};
            for (int j = 0; j < 2; j++) {
                if (fmpq_equal(Ls[j]->lo, Ls[j]->hi))
                    continue;
                fmpq_sub(w, Ls[j]->hi, Ls[j]->lo);
                fmpq_div_2exp(w, w, 1);
                cb_roots_refine(cv, ks[j], w);
                fmpq_set(Ls[j]->lo, cv->root[ks[j]].lo);
                fmpq_set(Ls[j]->hi, cv->root[ks[j]].hi);
            }
        }
    }
    for (slong i = 0; i < m; i++) {
        cb_ctopo_line_struct *L = T->line + i;
        L->s = mid_d(L->lo, L->hi);
        if (!fmpq_equal(L->lo, L->hi)) {
            fmpq_set(L->left, L->lo);
            fmpq_set(L->right, L->hi);
            continue;
        }
        fmpq_sub(eps, C->s1, C->s0);
        if (i > 0) {
            fmpq_sub(gap, L->lo, T->line[i - 1].hi);
            if (fmpq_cmp(gap, eps) < 0)
                fmpq_set(eps, gap);
        }
        if (i + 1 < m) {
            fmpq_sub(gap, T->line[i + 1].lo, L->hi);
            if (fmpq_cmp(gap, eps) < 0)
                fmpq_set(eps, gap);
        }
        fmpq_div_2exp(eps, eps, 2);
        dyadic_below(gap, eps);
        fmpq_sub(L->left, L->lo, gap);
        fmpq_add(L->right, L->lo, gap);
    }
    fmpq_clear(eps);
    fmpq_clear(gap);
    fmpq_clear(w);
}

/* ------------------------------------------------------------------------ summary ---------- */

static slong uf_find(slong *parent, slong x)
{
    while (parent[x] != x) {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    return x;
}

static void summarise(cb_ctopo_t T)
{
    slong nv = T->n_vertices;
    slong *parent = flint_malloc((size_t)FLINT_MAX(nv, 1) * sizeof *parent);
    for (slong i = 0; i < nv; i++) {
        parent[i] = i;
        T->vertex[i].degree = 0;
    }
    for (slong e = 0; e < T->n_edges; e++) {
        slong a = uf_find(parent, T->edge[e].v0), b = uf_find(parent, T->edge[e].v1);
        parent[a] = b;
        T->vertex[T->edge[e].v0].degree++;
        T->vertex[T->edge[e].v1].degree++;
    }
    slong nc = 0;
    for (slong i = 0; i < nv; i++)
        if (uf_find(parent, i) == i)
            T->vertex[i].component = nc++;
    for (slong i = 0; i < nv; i++)
        T->vertex[i].component = T->vertex[uf_find(parent, i)].component;
    T->n_components = nc;

    /* Per component: touches a side, has an edge, all edges (or its point) tangential. */
    int *touches = flint_calloc((size_t)FLINT_MAX(nc, 1), sizeof(int));
    int *has_edge = flint_calloc((size_t)FLINT_MAX(nc, 1), sizeof(int));
    T->component_tangential = flint_malloc((size_t)FLINT_MAX(nc, 1) * sizeof(int));
    for (slong c = 0; c < nc; c++)
        T->component_tangential[c] = 1;
    /* A vertex with edges is tangential when all its edges are. */
    for (slong i = 0; i < nv; i++)
        if (T->vertex[i].degree > 0 && T->vertex[i].kind != CB_CTOPO_HELPING)
            T->vertex[i].tangential = 1;
    for (slong e = 0; e < T->n_edges; e++) {
        const cb_ctopo_edge_struct *E = T->edge + e;
        slong c = T->vertex[E->v0].component;
        has_edge[c] = 1;
        if (!E->tangential) {
            T->component_tangential[c] = 0;
            if (T->vertex[E->v0].kind != CB_CTOPO_HELPING)
                T->vertex[E->v0].tangential = 0;
            if (T->vertex[E->v1].kind != CB_CTOPO_HELPING)
                T->vertex[E->v1].tangential = 0;
        }
    }
    T->n_isolated = T->n_singular = T->n_loops = 0;
    for (slong i = 0; i < nv; i++) {
        const cb_ctopo_vertex_struct *v = T->vertex + i;
        if (v->sides)
            touches[v->component] = 1;
        if (v->singular)
            T->n_singular++;
        if (v->degree == 0) {
            T->n_isolated++;
            T->component_tangential[v->component] = v->tangential;
        }
    }
    for (slong c = 0; c < nc; c++)
        if (has_edge[c] && !touches[c])
            T->n_loops++;
    flint_free(has_edge);
    flint_free(touches);
    flint_free(parent);
}

/* ------------------------------------------------------------------------ the driver ------- */

cb_status cb_ctopo_compute(cb_ctopo_t T, const fmpz_mpoly_t phi, const fmpz_mpoly_ctx_t ctx,
                          const fmpq_t s0, const fmpq_t s1, const fmpq_t t0, const fmpq_t t1,
                          const cb_ctopo_opts *opts, cb_error *err)
{
    cb_ctopo_clear(T);
    if (fmpz_mpoly_ctx_nvars(ctx) != 2)
        return cb_error_set(err, CB_ERR_INVALID,
                            "curve topology: phi must have 2 variables (s, t), not %ld",
                            (long)fmpz_mpoly_ctx_nvars(ctx));
    if (fmpz_mpoly_is_zero(phi, ctx))
        return cb_error_set(err, CB_ERR_INVALID,
                            "curve topology: phi is the zero polynomial (every point a root)");
    if (fmpq_cmp(s0, s1) >= 0 || fmpq_cmp(t0, t1) >= 0)
        return cb_error_set(err, CB_ERR_INVALID,
                            "curve topology: empty box, need s0 < s1 and t0 < t1");
    if (opts->max_attempts < 1 || opts->max_depth < 1 || opts->prec < 32 ||
        opts->coord_bits < 1)
        return cb_error_set(err, CB_ERR_INVALID,
                            "curve topology: options need max_attempts, max_depth, "
                            "coord_bits >= 1 and prec >= 32");

    cb_ctopo_curve_struct C;
    curve_init(&C);
    fmpq_set(C.s0, s0);
    fmpq_set(C.s1, s1);
    fmpq_set(C.t0, t0);
    fmpq_set(C.t1, t1);
    C.opts = opts;
    fmpz_poly_t cont, cont_rep, D, q;
    fmpz_poly_init(cont);
    fmpz_poly_init(cont_rep);
    fmpz_poly_init(D);
    fmpz_poly_init(q);
    cb_roots_t cv;
    cb_roots_init(cv);
    slong *root_of = NULL;
    cb_ctopo_fibre_struct *fib = NULL;
    cb_status st = CB_OK;

    curve_prepare(&C, cont, cont_rep, &T->has_repeated_factor, phi, ctx);
    C.prec = curve_prec(&C);

    /* D = Res_t(h, h_t) lc h(s, t0) h(s, t1) cont, each factor made squarefree first. */
    sqfree_part(D, C.res);
    const fmpz_poly_struct *more[4] = {C.lc, C.bnd[0], C.bnd[1], cont};
    for (int i = 0; i < 4; i++) {
        sqfree_part(q, more[i]);
        fmpz_poly_mul(D, D, q);
    }
    st = cb_roots_isolate(cv, D, s0, s1, err);
    if (st != CB_OK)
        goto done;
    lines_build(T, &root_of, &C, cv);

    for (int i = 0; i < 2; i++)
        if (C.side_t[i])
            T->sides_on_curve |= i ? CB_CTOPO_SIDE_T1 : CB_CTOPO_SIDE_T0;
    fib = flint_malloc((size_t)T->n_lines * sizeof *fib);
    for (slong i = 0; i < T->n_lines; i++)
        cb_ctopo_fibre_init(fib + i);
    for (slong i = 0; i < T->n_lines && st == CB_OK; i++) {
        cb_ctopo_line_struct *L = T->line + i;
        if (fmpq_equal(L->lo, L->hi)) {
            fmpq_t v;
            fmpq_init(v);
            fmpz_poly_evaluate_fmpq(v, cont, L->lo);
            L->vertical = fmpq_is_zero(v);
            fmpz_poly_evaluate_fmpq(v, cont_rep, L->lo);
            L->vertical_tangential = fmpq_is_zero(v);
            fmpq_clear(v);
        } else {
            L->vertical = cb_ctopo_alg_vanishes(cont, cv->sqfree, L->lo, L->hi);
            L->vertical_tangential = cb_ctopo_alg_vanishes(cont_rep, cv->sqfree, L->lo, L->hi);
        }
        if (L->vertical && i == 0)
            T->sides_on_curve |= CB_CTOPO_SIDE_S0;
        if (L->vertical && i == T->n_lines - 1)
            T->sides_on_curve |= CB_CTOPO_SIDE_S1;
        st = cb_ctopo_fibre_analyse(fib + i, &C, cv, root_of[i], L, err);
    }
    if (st != CB_OK)
        goto done;

    /* Graph: helping vertices, fibre vertices, local edges, edges between lines. */
    fmpq_t w;
    fmpq_init(w);
    fmpz_one(fmpq_numref(w));
    fmpz_one_2exp(fmpq_denref(w), (ulong)opts->coord_bits);
    slong prev_right = -1, prev_n = 0;
    for (slong i = 0; i < T->n_lines && st == CB_OK; i++) {
        cb_ctopo_line_struct *L = T->line + i;
        cb_ctopo_fibre_struct *F = fib + i;
        if (!fmpq_equal(L->lo, L->hi)) {
            cb_roots_refine(cv, root_of[i], w);
            fmpq_set(L->lo, cv->root[root_of[i]].lo);
            fmpq_set(L->hi, cv->root[root_of[i]].hi);
            L->s = mid_d(L->lo, L->hi);
        }
        unsigned line_side = i == 0 ? CB_CTOPO_SIDE_S0 : i == T->n_lines - 1 ? CB_CTOPO_SIDE_S1 : 0;
        slong lv = helping_vertices(T, C.rep, C.t0, C.t1, F->left_roots, L->left,
                                    opts->coord_bits);
        if (F->left_roots->n != prev_n) {
            st = cb_error_set(err, CB_ERR_NUMERIC,
                              "curve topology: %ld branches leave the line s ~ %.17g but %ld "
                              "reach the next one (internal error)",
                              (long)prev_n, T->line[i - 1].s, (long)F->left_roots->n);
            break;
        }
        for (slong j = 0; j < prev_n; j++)
            edge_push(T, prev_right + j, lv + j, 0, T->vertex[lv + j].tangential);

        slong *fv = flint_malloc((size_t)FLINT_MAX(F->n_box, 1) * sizeof *fv);
        fmpz_poly_t f;
        fmpz_poly_init(f);
        if (fmpq_equal(L->lo, L->hi))
            cb_bipoly_eval_s_fmpq(f, C.h, L->lo);
        for (slong b = 0; b < F->n_box; b++) {
            cb_ctopo_fibre_box_struct *B = F->box + b;
            fv[b] = -1;
            if (!B->has_root)
                continue;
            /* A simple root over a rational alpha: refine exactly inside its box. */
            fmpq_t tl, th;
            fmpq_init(tl);
            fmpq_init(th);
            fmpq_set(tl, B->t_lo);
            fmpq_set(th, B->t_hi);
            if (fmpq_equal(L->lo, L->hi) && B->mult == 1 && !B->sides) {
                cb_roots_t rr;
                cb_roots_init(rr);
                if (cb_roots_isolate(rr, f, B->c, B->d, NULL) == CB_OK && rr->n == 1) {
                    cb_roots_refine(rr, 0, w);
                    fmpq_set(tl, rr->root[0].lo);
                    fmpq_set(th, rr->root[0].hi);
                }
                cb_roots_clear(rr);
            }
            int branches = B->n_left + B->n_right > 0;
            cb_ctopo_kind kind = !branches && !L->vertical ? CB_CTOPO_ISOLATED
                                : B->mult > 1             ? CB_CTOPO_CRITICAL
                                : (B->sides || line_side) ? CB_CTOPO_BOUNDARY
                                                          : CB_CTOPO_FIBRE;
            slong id = vertex_push(T, kind, L->lo, L->hi, tl, th, i);
            cb_ctopo_vertex_struct *v = T->vertex + id;
            v->s = L->s;
            v->t = mid_d(tl, th);
            fmpq_clear(tl);
            fmpq_clear(th);
            v->sides = B->sides | line_side;
            v->singular = B->singular || L->vertical;
            v->tangential = B->tangential;
            fv[b] = id;
            for (slong j = 0; j < B->n_left; j++)
                edge_push(T, lv + B->first_left + j, id, 0,
                          T->vertex[lv + B->first_left + j].tangential);
        }
        fmpz_poly_clear(f);
        slong rv = helping_vertices(T, C.rep, C.t0, C.t1, F->right_roots, L->right,
                                    opts->coord_bits);
        for (slong b = 0; b < F->n_box; b++) {
            const cb_ctopo_fibre_box_struct *B = F->box + b;
            for (slong j = 0; j < B->n_right; j++)
                edge_push(T, fv[b], rv + B->first_right + j, 0,
                          T->vertex[rv + B->first_right + j].tangential);
        }
        /* A vertical line joins every point on it, from t0 to t1. */
        if (L->vertical) {
            slong prev = -1;
            if (F->n_box == 0 || !(F->box[0].has_root && (F->box[0].sides & CB_CTOPO_SIDE_T0))) {
                prev = vertex_push(T, CB_CTOPO_BOUNDARY, L->lo, L->hi, C.t0, C.t0, i);
                T->vertex[prev].s = L->s;
                T->vertex[prev].t = fmpq_get_d(C.t0);
                T->vertex[prev].sides = CB_CTOPO_SIDE_T0 | line_side;
            }
            for (slong b = 0; b < F->n_box; b++) {
                if (fv[b] < 0)
                    continue;
                if (prev >= 0)
                    edge_push(T, prev, fv[b], 1, L->vertical_tangential);
                prev = fv[b];
            }
            if (!(T->vertex[prev].sides & CB_CTOPO_SIDE_T1)) {
                slong top = vertex_push(T, CB_CTOPO_BOUNDARY, L->lo, L->hi, C.t1, C.t1, i);
                T->vertex[top].s = L->s;
                T->vertex[top].t = fmpq_get_d(C.t1);
                T->vertex[top].sides = CB_CTOPO_SIDE_T1 | line_side;
                edge_push(T, prev, top, 1, L->vertical_tangential);
            }
        }
        flint_free(fv);
        prev_right = rv;
        prev_n = F->right_roots->n;
    }
    fmpq_clear(w);
    if (st == CB_OK)
        summarise(T);

done:
    if (fib) {
        for (slong i = 0; i < T->n_lines; i++)
            cb_ctopo_fibre_clear(fib + i);
        flint_free(fib);
    }
    flint_free(root_of);
    cb_roots_clear(cv);
    fmpz_poly_clear(q);
    fmpz_poly_clear(D);
    fmpz_poly_clear(cont_rep);
    fmpz_poly_clear(cont);
    if (st == CB_OK)
        cb_bipoly_swap(T->h, C.h);
    curve_clear(&C);
    if (st != CB_OK)
        cb_ctopo_clear(T);
    return st;
}
