/* Certified curve topology (ssi/curve_topo.h): designed curves in [0, 1]^2 with known topology,
 * the paper's Example 2 (appendix A) with phi = F(Q) from the implicitization, graph invariants,
 * subresultant identities, and error paths. */
#include <math.h>
#include <stdlib.h>

#include <arb.h>

#include "check.h"
#include "ssi/curve_topo.h"
#include "ssi/dixon.h"
#include "ssi/implicit.h"

typedef struct {
    const char *name;
    const char *phi; /* in s, t with integer coefficients */
    slong components, loops, isolated, singular;
    int tangential;       /* every component tangential (-1: do not check) */
    slong max_degree;     /* largest vertex degree expected */
    unsigned sides;       /* sides of the box on the curve */
} designed_curve;

static const designed_curve curves[] = {
    {"circle", "(4*s-2)^2+(4*t-2)^2-1", 1, 1, 0, 0, 0, 2, 0},
    {"two circles crossing twice", "((10*s-4)^2+(10*t-4)^2-9)*((10*s-6)^2+(10*t-5)^2-9)", 1, 1, 0,
     2, 0, 4, 0},
    {"two circles touching", "((10*s-3)^2+(10*t-5)^2-4)*((10*s-7)^2+(10*t-5)^2-4)", 1, 1, 0, 1,
     0, 4, 0},
    {"node (lemniscate)", "((4*s-2)^2+(4*t-2)^2)^2-((4*s-2)^2-(4*t-2)^2)", 1, 1, 0, 1, 0, 4, 0},
    {"cusp", "(4*t-2)^2-(4*s-2)^3", 1, 0, 0, 1, 0, 2, 0},
    {"isolated point", "(2*s-1)^2+(2*t-1)^2", 1, 0, 1, 1, 0, 0, 0},
    {"three isolated points",
     "((4*s-1)^2+(4*t-1)^2)*((2*s-1)^2+(4*t-3)^2)*((4*s-3)^2+(2*t-1)^2)", 3, 0, 3, 3, 0, 0, 0},
    {"isolated point at s = 1/sqrt(3)", "(3*s^2-1)^2+(2*t-1)^2", 1, 0, 1, 1, 0, 0, 0},
    {"squared circle", "((4*s-2)^2+(4*t-2)^2-1)^2", 1, 1, 0, 0, 1, 2, 0},
    {"line along the side s = s0", "s", 1, 0, 0, 0, 0, 1, CB_CTOPO_SIDE_S0},
    {"side t = t0 and a diagonal from its corner", "t*(t-s)", 1, 0, 0, 1, 0, 2,
     CB_CTOPO_SIDE_T0},
    {"two crossing lines", "(t-s)*(t+s-1)", 1, 0, 0, 1, 0, 4, 0},
    {"vertical line", "3*s-1", 1, 0, 0, 0, 0, 1, 0},
    {"vertical line at s = 1/sqrt(3)", "3*s^2-1", 1, 0, 0, 0, 0, 1, 0},
    {"vertical line through a circle", "(3*s-1)*((4*s-2)^2+(4*t-2)^2-1)", 1, 0, 0, 2, 0, 4, 0},
    {"tiny circle, radius 1e-3", "(1000*s-500)^2+(1000*t-500)^2-1", 1, 1, 0, 0, 0, 2, 0},
    {"two circles 1e-4 apart",
     "((10000*s-3000)^2+(10000*t-5000)^2-4000000)*((10000*s-7001)^2+(10000*t-5000)^2-4000000)",
     2, 2, 0, 0, 0, 2, 0},
    {"near miss (x-a)^2+(y-b)^2+1e-8", "100000000*((2*s-1)^2+(2*t-1)^2)+1", 0, 0, 0, 0, 0, 0, 0},
    {"circle crossing the box", "(2*s)^2+(2*t)^2-1", 1, 0, 0, 0, 0, 2, 0},
    {"parabola tangent to the side t = t0 from below", "t+(2*s-1)^2", 1, 0, 1, 0, 0, 0, 0},
    /* its critical fibre s = 1/sqrt(3) has a root of multiplicity 5 on the side t = 1: the
     * ball test of whether the gcd (1 - t)^4 of phi and phi_t has no root in the box (it has
     * one) must give up, not bisect towards t = 1 for hours */
    {"flat inflection on the side t = t1", "(3*s^2-1)-(1-t)^5", 1, 0, 0, 0, 0, 2, 0},
    /* the same with the root of the gcd 1e-3 beyond the side: no root in the box, but too
     * close to it for the ball test to prove that within its budget */
    {"flat inflection 1e-3 beyond the side t = t1", "1000000000000000*(3*s^2-1)-(1001-1000*t)^5",
     1, 0, 0, 0, 0, 2, 0},
};

static const double unit_box[4] = {0, 1, 0, 1};

/* A small parser for the designed curves (+, -, *, ^, parentheses, integers, s, t): FLINT
 * 2.9's fmpz_mpoly_set_str_pretty leaks memory, which LeakSanitizer would report. */
typedef struct {
    const char *p;
    const fmpz_mpoly_ctx_struct *ctx;
    int ok;
} parser;

static void parse_expr(fmpz_mpoly_t out, parser *ps);

static void parse_base(fmpz_mpoly_t out, parser *ps)
{
    char ch = *ps->p;
    if (ch == '(') {
        ps->p++;
        parse_expr(out, ps);
        ps->ok &= *ps->p == ')';
        ps->p++;
    } else if (ch == 's' || ch == 't') {
        fmpz_mpoly_gen(out, ch == 's' ? 0 : 1, ps->ctx);
        ps->p++;
    } else if (ch == '-') {
        ps->p++;
        parse_base(out, ps);
        fmpz_mpoly_neg(out, out, ps->ctx);
    } else if (ch >= '0' && ch <= '9') {
        fmpz_t v;
        fmpz_init(v);
        while (*ps->p >= '0' && *ps->p <= '9') {
            fmpz_mul_ui(v, v, 10);
            fmpz_add_ui(v, v, (ulong)(*ps->p++ - '0'));
        }
        fmpz_mpoly_set_fmpz(out, v, ps->ctx);
        fmpz_clear(v);
    } else {
        ps->ok = 0;
    }
}

static void parse_factor(fmpz_mpoly_t out, parser *ps)
{
    parse_base(out, ps);
    if (*ps->p == '^') {
        ps->p++;
        ulong e = strtoul(ps->p, (char **)&ps->p, 10);
        fmpz_mpoly_pow_ui(out, out, e, ps->ctx);
    }
}

static void parse_term(fmpz_mpoly_t out, parser *ps)
{
    fmpz_mpoly_t f;
    fmpz_mpoly_init(f, ps->ctx);
    parse_factor(out, ps);
    while (ps->ok && *ps->p == '*') {
        ps->p++;
        parse_factor(f, ps);
        fmpz_mpoly_mul(out, out, f, ps->ctx);
    }
    fmpz_mpoly_clear(f, ps->ctx);
}

static void parse_expr(fmpz_mpoly_t out, parser *ps)
{
    fmpz_mpoly_t f;
    fmpz_mpoly_init(f, ps->ctx);
    parse_term(out, ps);
    while (ps->ok && (*ps->p == '+' || *ps->p == '-')) {
        char op = *ps->p++;
        parse_term(f, ps);
        if (op == '+')
            fmpz_mpoly_add(out, out, f, ps->ctx);
        else
            fmpz_mpoly_sub(out, out, f, ps->ctx);
    }
    fmpz_mpoly_clear(f, ps->ctx);
}

/* 1 if str parsed completely. */
static int parse_poly(fmpz_mpoly_t out, const char *str, const fmpz_mpoly_ctx_t ctx)
{
    parser ps = {str, ctx, 1};
    parse_expr(out, &ps);
    return ps.ok && *ps.p == '\0';
}

/* Structural facts every topology graph must satisfy; box = {s0, s1, t0, t1}. */
static int graph_ok(const cb_ctopo_t T, const char *name, const double box[4])
{
    int ok = 1;
    slong deg_sum = 0;
    for (slong e = 0; e < T->n_edges; e++) {
        const cb_ctopo_edge_struct *E = T->edge + e;
        int valid = E->v0 >= 0 && E->v0 < T->n_vertices && E->v1 >= 0 &&
                    E->v1 < T->n_vertices && E->v0 != E->v1;
        CHECK(valid, "%s: edge %ld has ends %ld, %ld of %ld vertices", name, (long)e,
              (long)E->v0, (long)E->v1, (long)T->n_vertices);
        if (!valid)
            return 0;
        const cb_ctopo_vertex_struct *a = T->vertex + E->v0, *b = T->vertex + E->v1;
        int mono = E->vertical ? fmpq_equal(a->s_lo, b->s_lo) && fmpq_cmp(a->t_hi, b->t_lo) <= 0
                               : fmpq_cmp(a->s_hi, b->s_lo) <= 0 && a->s <= b->s &&
                                     !fmpq_equal(a->s_lo, b->s_hi);
        CHECK(mono, "%s: edge %ld from (%g, %g) to (%g, %g) not monotone", name, (long)e, a->s,
              a->t, b->s, b->t);
        ok &= mono;
    }
    for (slong i = 0; i < T->n_vertices; i++) {
        const cb_ctopo_vertex_struct *v = T->vertex + i;
        deg_sum += v->degree;
        int in_box = v->s >= box[0] - 1e-12 && v->s <= box[1] + 1e-12 &&
                     v->t >= box[2] - 1e-12 && v->t <= box[3] + 1e-12;
        CHECK(in_box, "%s: vertex %ld at (%g, %g) outside the box", name, (long)i, v->s, v->t);
        if (v->kind == CB_CTOPO_HELPING)
            CHECK(v->degree == 2, "%s: helping point %ld (%g, %g) has degree %ld", name, (long)i,
                  v->s, v->t, (long)v->degree);
        if (v->kind == CB_CTOPO_ISOLATED)
            CHECK(v->degree == 0, "%s: isolated point %ld has degree %ld", name, (long)i,
                  (long)v->degree);
        if (v->kind == CB_CTOPO_FIBRE && !T->line[v->line].vertical)
            CHECK(v->degree == 2, "%s: regular point %ld (%g, %g) has degree %ld", name, (long)i,
                  v->s, v->t, (long)v->degree);
        if (!v->singular && v->kind != CB_CTOPO_ISOLATED && !v->sides)
            CHECK(v->degree == 2, "%s: smooth interior point %ld (%g, %g) has degree %ld", name,
                  (long)i, v->s, v->t, (long)v->degree);
        CHECK(fmpq_cmp(v->s_lo, v->s_hi) <= 0 && fmpq_cmp(v->t_lo, v->t_hi) <= 0,
              "%s: vertex %ld has an empty box", name, (long)i);
    }
    CHECK(deg_sum == 2 * T->n_edges, "%s: degrees sum to %ld for %ld edges", name,
          (long)deg_sum, (long)T->n_edges);
    return ok;
}

static slong max_degree(const cb_ctopo_t T)
{
    slong m = 0;
    for (slong i = 0; i < T->n_vertices; i++)
        m = FLINT_MAX(m, T->vertex[i].degree);
    return m;
}

static void test_designed(void)
{
    fmpz_mpoly_ctx_t ctx;
    fmpz_mpoly_t phi;
    fmpq_t zero, one;
    cb_ctopo_opts opts;
    fmpz_mpoly_ctx_init(ctx, 2, ORD_LEX);
    fmpz_mpoly_init(phi, ctx);
    fmpq_init(zero);
    fmpq_init(one);
    fmpq_one(one);
    cb_ctopo_opts_default(&opts);
    for (size_t c = 0; c < sizeof curves / sizeof *curves; c++) {
        const designed_curve *d = curves + c;
        cb_ctopo_t T;
        cb_error err;
        cb_error_clear(&err);
        cb_ctopo_init(T);
        int parsed = parse_poly(phi, d->phi, ctx);
        CHECK(parsed, "%s: cannot parse %s", d->name, d->phi);
        cb_status st = cb_ctopo_compute(T, phi, ctx, zero, one, zero, one, &opts, &err);
        CHECK(st == CB_OK, "%s: status %s: %s", d->name, cb_status_name(st), err.msg);
        if (st == CB_OK) {
            printf("%-48s components %ld loops %ld isolated %ld singular %ld (lines %ld, "
                   "vertices %ld, edges %ld)\n",
                   d->name, (long)T->n_components, (long)T->n_loops, (long)T->n_isolated,
                   (long)T->n_singular, (long)T->n_lines, (long)T->n_vertices,
                   (long)T->n_edges);
            CHECK(T->n_components == d->components, "%s: %ld components, expected %ld",
                  d->name, (long)T->n_components, (long)d->components);
            CHECK(T->n_loops == d->loops, "%s: %ld loops, expected %ld", d->name,
                  (long)T->n_loops, (long)d->loops);
            CHECK(T->n_isolated == d->isolated, "%s: %ld isolated points, expected %ld",
                  d->name, (long)T->n_isolated, (long)d->isolated);
            CHECK(T->n_singular == d->singular, "%s: %ld singular points, expected %ld",
                  d->name, (long)T->n_singular, (long)d->singular);
            CHECK(max_degree(T) == d->max_degree, "%s: largest degree %ld, expected %ld",
                  d->name, (long)max_degree(T), (long)d->max_degree);
            CHECK(T->sides_on_curve == d->sides, "%s: sides on the curve %u, expected %u",
                  d->name, T->sides_on_curve, d->sides);
            for (slong k = 0; k < T->n_components; k++)
                CHECK(T->component_tangential[k] == d->tangential,
                      "%s: component %ld tangential %d, expected %d", d->name, (long)k,
                      T->component_tangential[k], d->tangential);
            CHECK(T->has_repeated_factor == d->tangential, "%s: repeated factor flag %d",
                  d->name, T->has_repeated_factor);
            graph_ok(T, d->name, unit_box);
        }
        cb_ctopo_clear(T);
    }
    fmpq_clear(one);
    fmpq_clear(zero);
    fmpz_mpoly_clear(phi, ctx);
    fmpz_mpoly_ctx_clear(ctx);
}

/* psc_0 is the resultant: compare with fmpz_mpoly_resultant (up to sign) on random h. */
static void test_subresultant(check_rng *rng)
{
    fmpz_mpoly_ctx_t ctx;
    fmpz_mpoly_t H, Ht, R;
    cb_bipoly_t h, r;
    fmpz_poly_t p;
    fmpz_mpoly_ctx_init(ctx, 2, ORD_LEX);
    fmpz_mpoly_init(H, ctx);
    fmpz_mpoly_init(Ht, ctx);
    fmpz_mpoly_init(R, ctx);
    cb_bipoly_init(h);
    cb_bipoly_init(r);
    fmpz_poly_init(p);
    for (int trial = 0; trial < 40; trial++) {
        slong ds = check_rng_int(rng, 0, 4), dt = check_rng_int(rng, 2, 5);
        fmpz_mpoly_zero(H, ctx);
        for (slong i = 0; i <= ds; i++)
            for (slong j = 0; j <= dt; j++) {
                ulong e[2] = {(ulong)i, (ulong)j};
                fmpz_t c;
                fmpz_init_set_si(c, check_rng_int(rng, -9, 9) + (j == dt && i == 0 ? 20 : 0));
                fmpz_mpoly_set_coeff_fmpz_ui(H, c, e, ctx);
                fmpz_clear(c);
            }
        fmpz_mpoly_derivative(Ht, H, 1, ctx);
        fmpz_mpoly_resultant(R, H, Ht, 1, ctx);
        cb_bipoly_set_fmpz_mpoly(h, H, ctx);
        cb_bipoly_set_fmpz_mpoly(r, R, ctx);
        cb_ctopo_sres_coeff(p, h, 0, 0);
        int same = r->len == 1 && fmpz_poly_equal(p, r->c);
        if (!same && r->len == 1) {
            fmpz_poly_neg(p, p);
            same = fmpz_poly_equal(p, r->c);
        }
        CHECK(same, "trial %d: psc_0 differs from the resultant (bidegree %ld, %ld)", trial,
              (long)ds, (long)dt);
        /* psc_j at a rational point: symbolic then evaluated equals the ball version. */
        slong j = check_rng_int(rng, 1, (int)dt - 1);
        cb_ctopo_sres_coeff(p, h, j, j);
        fmpq_t x, v;
        arb_t X, y;
        fmpq_init(x);
        fmpq_init(v);
        arb_init(X);
        arb_init(y);
        fmpq_set_si(x, check_rng_int(rng, -20, 20), 7);
        fmpz_poly_evaluate_fmpq(v, p, x);
        arb_set_fmpq(X, x, 256);
        cb_ctopo_sres_coeff_arb(y, h, j, j, X, 256);
        arb_t V;
        arb_init(V);
        arb_set_fmpq(V, v, 256);
        CHECK(arb_overlaps(y, V), "trial %d: psc_%ld ball and exact values disagree", trial,
              (long)j);
        arb_clear(V);
        arb_clear(y);
        arb_clear(X);
        fmpq_clear(v);
        fmpq_clear(x);
    }
    fmpz_poly_clear(p);
    cb_bipoly_clear(r);
    cb_bipoly_clear(h);
    fmpz_mpoly_clear(R, ctx);
    fmpz_mpoly_clear(Ht, ctx);
    fmpz_mpoly_clear(H, ctx);
    fmpz_mpoly_ctx_clear(ctx);
}

/* A signed integer of at most bits bits, every size equally likely up to bits. */
static void random_fmpz(fmpz_t c, check_rng *rng, int bits)
{
    fmpz_zero(c);
    for (int b = 0; b < bits; b += 64) {
        fmpz_mul_2exp(c, c, 64);
        fmpz_add_ui(c, c, check_rng_next(rng));
    }
    fmpz_fdiv_r_2exp(c, c, (ulong)check_rng_int(rng, 0, bits));
    if (check_rng_next(rng) & 1)
        fmpz_neg(c, c);
}

static void random_bipoly(cb_bipoly_struct *f, check_rng *rng, slong ds, slong dt, int bits,
                          const fmpz_mpoly_ctx_t ctx)
{
    fmpz_mpoly_t F;
    fmpz_t c;
    fmpz_mpoly_init(F, ctx);
    fmpz_init(c);
    for (slong i = 0; i <= ds; i++)
        for (slong j = 0; j <= dt; j++) {
            ulong e[2] = {(ulong)i, (ulong)j};
            random_fmpz(c, rng, bits);
            /* keep the bidegree (ds, dt) */
            if (j == dt && i == ds && fmpz_is_zero(c))
                fmpz_one(c);
            fmpz_mpoly_set_coeff_fmpz_ui(F, c, e, ctx);
        }
    cb_bipoly_set_fmpz_mpoly(f, F, ctx);
    fmpz_clear(c);
    fmpz_mpoly_clear(F, ctx);
}

/* The modular resultant equals FLINT's exact fmpz_mpoly_resultant, coefficient for
 * coefficient. */
static int resultant_matches(const cb_bipoly_struct *f, const cb_bipoly_struct *g,
                             const fmpz_mpoly_ctx_t ctx)
{
    fmpz_mpoly_t F, G, R;
    cb_bipoly_t r;
    fmpz_poly_t m;
    cb_error err;
    fmpz_mpoly_init(F, ctx);
    fmpz_mpoly_init(G, ctx);
    fmpz_mpoly_init(R, ctx);
    cb_bipoly_init(r);
    fmpz_poly_init(m);
    cb_bipoly_get_fmpz_mpoly(F, f, ctx);
    cb_bipoly_get_fmpz_mpoly(G, g, ctx);
    int ok = fmpz_mpoly_resultant(R, F, G, 1, ctx) &&
             cb_bipoly_resultant(m, f, g, &err) == CB_OK;
    cb_bipoly_set_fmpz_mpoly(r, R, ctx);
    ok = ok && (r->len == 0 ? fmpz_poly_is_zero(m) : r->len == 1 && fmpz_poly_equal(m, r->c));
    fmpz_poly_clear(m);
    cb_bipoly_clear(r);
    fmpz_mpoly_clear(R, ctx);
    fmpz_mpoly_clear(G, ctx);
    fmpz_mpoly_clear(F, ctx);
    return ok;
}

/* cb_bipoly_resultant against fmpz_mpoly_resultant: random pairs of several bidegrees and
 * coefficient sizes (signed), g = f_t as the topology uses it, leading coefficients in t that
 * vanish at s = 0, 1, 2, 3 (evaluation points to skip), common factors (zero resultant), and
 * degree 0 in t or s. cb_fmpz_poly_mat_det against fmpz_poly_mat_det on random matrices. */
static void test_modular(check_rng *rng)
{
    fmpz_mpoly_ctx_t ctx;
    cb_bipoly_t f, g, c;
    fmpz_mpoly_ctx_init(ctx, 2, ORD_LEX);
    cb_bipoly_init(f);
    cb_bipoly_init(g);
    cb_bipoly_init(c);
    static const int bits[] = {4, 16, 64, 200};
    for (int trial = 0; trial < 120; trial++) {
        int b = bits[trial % 4], kind = trial / 4 % 5;
        slong dsf = check_rng_int(rng, 0, 6), dtf = check_rng_int(rng, kind == 3 ? 0 : 1, 7);
        slong dsg = check_rng_int(rng, 0, 6), dtg = check_rng_int(rng, kind == 3 ? 0 : 1, 7);
        random_bipoly(f, rng, dsf, dtf, b, ctx);
        random_bipoly(g, rng, dsg, dtg, b, ctx);
        const char *what = "random";
        if (kind == 1) {
            what = "g = f_t";
            if (f->len > 1)
                cb_bipoly_derivative_t(g, f);
        } else if (kind == 2) {
            /* lc_t f = s (s - 1) (s - 2) (s - 3) times a random polynomial */
            what = "lc_t vanishing at s = 0..3";
            fmpz_poly_t q;
            fmpz_poly_init(q);
            for (slong k = 0; k < 4; k++) {
                fmpz_poly_set_coeff_si(q, 1, 1);
                fmpz_poly_set_coeff_si(q, 0, -k);
                fmpz_poly_mul(f->c + f->len - 1, f->c + f->len - 1, q);
                if (k < 2)
                    fmpz_poly_mul(g->c + g->len - 1, g->c + g->len - 1, q);
            }
            fmpz_poly_clear(q);
        } else if (kind == 4) {
            /* common factor of positive degree in t */
            what = "common factor";
            fmpz_mpoly_t F, G, C;
            fmpz_mpoly_init(F, ctx);
            fmpz_mpoly_init(G, ctx);
            fmpz_mpoly_init(C, ctx);
            random_bipoly(c, rng, check_rng_int(rng, 0, 3), check_rng_int(rng, 1, 3), b, ctx);
            cb_bipoly_get_fmpz_mpoly(F, f, ctx);
            cb_bipoly_get_fmpz_mpoly(G, g, ctx);
            cb_bipoly_get_fmpz_mpoly(C, c, ctx);
            fmpz_mpoly_mul(F, F, C, ctx);
            fmpz_mpoly_mul(G, G, C, ctx);
            cb_bipoly_set_fmpz_mpoly(f, F, ctx);
            cb_bipoly_set_fmpz_mpoly(g, G, ctx);
            fmpz_mpoly_clear(C, ctx);
            fmpz_mpoly_clear(G, ctx);
            fmpz_mpoly_clear(F, ctx);
        } else if (kind == 3)
            what = "degree 0 in t allowed";
        CHECK(resultant_matches(f, g, ctx), "trial %d (%s, %d bits): bidegrees (%ld, %ld), (%ld, %ld)",
              trial, what, b, (long)dsf, (long)dtf, (long)dsg, (long)dtg);
        if (kind == 4) {
            fmpz_poly_t r;
            fmpz_poly_init(r);
            CHECK(cb_bipoly_resultant(r, f, g, NULL) == CB_OK && fmpz_poly_is_zero(r),
                  "trial %d: common factor, resultant not zero", trial);
            fmpz_poly_clear(r);
        }
    }
    /* Zero polynomials, and constants in t. */
    random_bipoly(f, rng, 3, 4, 30, ctx);
    cb_bipoly_set(g, f);
    g->len = 0;
    CHECK(resultant_matches(f, g, ctx) && resultant_matches(g, f, ctx), "zero polynomial");
    random_bipoly(g, rng, 2, 0, 30, ctx);
    CHECK(resultant_matches(f, g, ctx) && resultant_matches(g, f, ctx), "constant in t");
    random_bipoly(f, rng, 3, 0, 30, ctx);
    CHECK(resultant_matches(f, g, ctx), "two constants in t");
    /* Not normalised: rejected. */
    random_bipoly(f, rng, 2, 3, 30, ctx);
    fmpz_poly_zero(f->c + f->len - 1);
    fmpz_poly_t r;
    cb_error err;
    fmpz_poly_init(r);
    CHECK(cb_bipoly_resultant(r, f, g, &err) == CB_ERR_INVALID, "zero leading coefficient accepted");

    /* Determinants: random matrices with zero entries, repeated rows (det 0), size 0. */
    fmpz_poly_mat_t A;
    fmpz_poly_t d;
    fmpz_poly_init(d);
    for (int trial = 0; trial < 60; trial++) {
        slong n = check_rng_int(rng, 0, 7);
        int b = bits[trial % 4];
        fmpz_poly_mat_init(A, n, n);
        fmpz_t x;
        fmpz_init(x);
        for (slong i = 0; i < n; i++)
            for (slong j = 0; j < n; j++) {
                if (check_rng_int(rng, 0, 4) == 0)
                    continue;
                slong deg = check_rng_int(rng, 0, 5);
                for (slong k = 0; k <= deg; k++) {
                    random_fmpz(x, rng, b);
                    fmpz_poly_set_coeff_fmpz(fmpz_poly_mat_entry(A, i, j), k, x);
                }
            }
        if (n >= 2 && trial % 6 == 0)
            for (slong j = 0; j < n; j++)
                fmpz_poly_set(fmpz_poly_mat_entry(A, n - 1, j), fmpz_poly_mat_entry(A, 0, j));
        fmpz_poly_mat_det(r, A);
        CHECK(cb_fmpz_poly_mat_det(d, A, &err) == CB_OK && fmpz_poly_equal(d, r),
              "trial %d: %ld x %ld determinant (%d bits) differs from fmpz_poly_mat_det", trial,
              (long)n, (long)n, b);
        fmpz_clear(x);
        fmpz_poly_mat_clear(A);
    }
    fmpz_poly_mat_init(A, 2, 3);
    CHECK(cb_fmpz_poly_mat_det(d, A, &err) == CB_ERR_INVALID, "2 x 3 determinant accepted");
    fmpz_poly_mat_clear(A);
    fmpz_poly_clear(d);
    fmpz_poly_clear(r);
    cb_bipoly_clear(c);
    cb_bipoly_clear(g);
    cb_bipoly_clear(f);
    fmpz_mpoly_ctx_clear(ctx);
}

/* Bad input is rejected; a fibre the method cannot certify is reported, never guessed. */
static void test_errors(void)
{
    fmpz_mpoly_ctx_t ctx;
    fmpz_mpoly_t phi;
    fmpq_t zero, one;
    cb_ctopo_opts opts;
    cb_ctopo_t T;
    cb_error err;
    fmpz_mpoly_ctx_init(ctx, 2, ORD_LEX);
    fmpz_mpoly_init(phi, ctx);
    fmpq_init(zero);
    fmpq_init(one);
    fmpq_one(one);
    cb_ctopo_opts_default(&opts);
    cb_ctopo_init(T);
    cb_status st = cb_ctopo_compute(T, phi, ctx, zero, one, zero, one, &opts, &err);
    CHECK(st == CB_ERR_INVALID, "zero phi: status %s", cb_status_name(st));
    parse_poly(phi, "s-t", ctx);
    st = cb_ctopo_compute(T, phi, ctx, one, zero, zero, one, &opts, &err);
    CHECK(st == CB_ERR_INVALID, "empty box: status %s", cb_status_name(st));
    /* Two isolated points over the same irrational s = 1/sqrt(3): two real multiple roots. */
    parse_poly(phi, "((3*s^2-1)^2+(4*t-1)^2)*((3*s^2-1)^2+(4*t-3)^2)", ctx);
    st = cb_ctopo_compute(T, phi, ctx, zero, one, zero, one, &opts, &err);
    const char *parts[] = {"generic position", NULL};
    CHECK(st == CB_ERR_UNSUPPORTED && check_msg_has(err.msg, parts),
          "non-generic irrational fibre: status %s: %s", cb_status_name(st), err.msg);
    CHECK(T->n_vertices == 0 && T->n_edges == 0, "a failed topology must be empty");
    /* The same over a rational s = 1/2 is exact: two isolated points. */
    parse_poly(phi, "((2*s-1)^2+(4*t-1)^2)*((2*s-1)^2+(4*t-3)^2)", ctx);
    st = cb_ctopo_compute(T, phi, ctx, zero, one, zero, one, &opts, &err);
    CHECK(st == CB_OK && T->n_isolated == 2 && T->n_components == 2,
          "two isolated points over s = 1/2: status %s, %ld isolated", cb_status_name(st),
          (long)T->n_isolated);
    cb_ctopo_clear(T);
    fmpq_clear(one);
    fmpq_clear(zero);
    fmpz_mpoly_clear(phi, ctx);
    fmpz_mpoly_ctx_clear(ctx);
}

/* Random curves: whatever the status, a returned graph satisfies the invariants, and the
 * number of branches between critical lines never changes along an edge chain. */
static void test_random(check_rng *rng)
{
    fmpz_mpoly_ctx_t ctx;
    fmpz_mpoly_t phi;
    fmpq_t zero, one;
    cb_ctopo_opts opts;
    fmpz_mpoly_ctx_init(ctx, 2, ORD_LEX);
    fmpz_mpoly_init(phi, ctx);
    fmpq_init(zero);
    fmpq_init(one);
    fmpq_one(one);
    cb_ctopo_opts_default(&opts);
    slong ok = 0, unsupported = 0;
    for (int trial = 0; trial < 30; trial++) {
        fmpz_mpoly_zero(phi, ctx);
        slong d = check_rng_int(rng, 2, 4);
        for (slong i = 0; i <= d; i++)
            for (slong j = 0; j <= d; j++) {
                ulong e[2] = {(ulong)i, (ulong)j};
                fmpz_t c;
                fmpz_init_set_si(c, check_rng_int(rng, -30, 30));
                fmpz_mpoly_set_coeff_fmpz_ui(phi, c, e, ctx);
                fmpz_clear(c);
            }
        if (fmpz_mpoly_is_zero(phi, ctx))
            continue;
        cb_ctopo_t T;
        cb_error err;
        cb_ctopo_init(T);
        cb_status st = cb_ctopo_compute(T, phi, ctx, zero, one, zero, one, &opts, &err);
        char name[64];
        snprintf(name, sizeof name, "random trial %d", trial);
        CHECK(st == CB_OK || st == CB_ERR_UNSUPPORTED, "%s: status %s: %s", name,
              cb_status_name(st), err.msg);
        if (st == CB_OK) {
            ok++;
            graph_ok(T, name, unit_box);
            slong ends = 0;
            for (slong i = 0; i < T->n_vertices; i++)
                ends += T->vertex[i].degree;
            CHECK(ends == 2 * T->n_edges, "%s: degree sum", name);
        } else {
            unsupported++;
            printf("%s: %s\n", name, err.msg);
        }
        cb_ctopo_clear(T);
    }
    CHECK(ok >= 25, "only %ld of 30 random curves certified (%ld unsupported)", (long)ok,
          (long)unsupported);
    fmpq_clear(one);
    fmpq_clear(zero);
    fmpz_mpoly_clear(phi, ctx);
    fmpz_mpoly_ctx_clear(ctx);
}

/* x as a double, for printing and tolerance checks. */
static double q_d(const fmpq_t x) { return fmpq_get_d(x); }

/* Roots of the univariate p in [lo, hi], refined to width 2^-50, as doubles (at most 8). */
static slong roots_d(double *out, const fmpz_poly_t p, const fmpq_t lo, const fmpq_t hi)
{
    cb_roots_t R;
    fmpq_t w;
    cb_roots_init(R);
    fmpq_init(w);
    fmpq_set_si(w, 1, 1);
    fmpq_div_2exp(w, w, 50);
    slong n = -1;
    if (cb_roots_isolate(R, p, lo, hi, NULL) == CB_OK && R->n <= 8) {
        n = R->n;
        for (slong i = 0; i < n; i++) {
            cb_roots_refine(R, i, w);
            out[i] = 0.5 * (q_d(R->root[i].lo) + q_d(R->root[i].hi));
        }
    }
    fmpq_clear(w);
    cb_roots_clear(R);
    return n;
}

/* Does the sorted list got[0 .. n) equal want[0 .. m) to tol? */
static int same_list(const double *got, slong n, const double *want, slong m, double tol)
{
    if (n != m)
        return 0;
    for (slong i = 0; i < n; i++)
        if (fabs(got[i] - want[i]) > tol)
            return 0;
    return 1;
}

/* Appendix A, Example 2: P from Example 1, Q(s, t) = [2st^2 + 2s, -s^2t^3 + s^2 - 3t^3 + 3,
 * 2s^3t + 6t, s^2t^2 + s^2 + t^2 + 1] on [-1, 1] x [0, 2]; phi = F(Q) exactly (ssi/implicit.h,
 * as in test_ssi_dixon.c). Checks: the s-critical values (roots of Res_t(phi, phi_t) in
 * [-1, 1]) against the paper's isolating intervals; the paper's helping points, recomputed from
 * our phi at the paper's own s-values (its interval ends, and -+1e-6 for the rational alpha2);
 * the helping points of our topology that do not depend on eps or on how narrow the interval of
 * alpha is (the branches away from the folds at t = 1); and the topology counts. */
static void test_example2(void)
{
    static const struct {
        int q, i, j;
        double c;
    } pt[] = {{0, 3, 0, -32}, {0, 1, 2, 96}, {0, 2, 0, 48}, {0, 1, 1, -96}, {0, 0, 2, -48},
              {0, 1, 0, 6},   {0, 0, 1, 48}, {0, 0, 0, -11}, {1, 2, 1, 96}, {1, 0, 3, -32},
              {1, 2, 0, -48}, {1, 1, 1, -96}, {1, 0, 2, 48}, {1, 1, 0, 48}, {1, 0, 1, 6},
              {1, 0, 0, -11}, {2, 2, 0, 24}, {2, 0, 2, -24}, {2, 1, 0, -24}, {2, 0, 1, 24},
              {3, 0, 0, 2}},
      qt[] = {{0, 1, 2, 2}, {0, 1, 0, 2}, {1, 2, 3, -1}, {1, 2, 0, 1}, {1, 0, 3, -3},
              {1, 0, 0, 3}, {2, 3, 1, 2}, {2, 0, 1, 6}, {3, 2, 2, 1}, {3, 2, 0, 1},
              {3, 0, 2, 1}, {3, 0, 0, 1}};
    double hp[64] = {0}, hq[64] = {0};
    for (size_t k = 0; k < sizeof pt / sizeof *pt; k++)
        hp[pt[k].q * 16 + pt[k].i * 4 + pt[k].j] = pt[k].c;
    for (size_t k = 0; k < sizeof qt / sizeof *qt; k++)
        hq[qt[k].q * 16 + qt[k].i * 4 + qt[k].j] = qt[k].c;
    const double pbox[4] = {0, 1, 0, 1}, qbox[4] = {-1, 1, 0, 2};
    cb_dixon_patch_t P, Q;
    cb_dixon_pencil_t D;
    cb_implicit_t F;
    cb_phi_t ph;
    cb_error err;
    cb_dixon_patch_init(P);
    cb_dixon_patch_init(Q);
    cb_dixon_pencil_init(D);
    cb_implicit_init(F);
    cb_phi_init(ph);
    int ok = cb_dixon_patch_set_power(P, 3, 3, hp, pbox, &err) == CB_OK &&
             cb_dixon_patch_set_power(Q, 3, 3, hq, qbox, &err) == CB_OK &&
             cb_dixon_pencil_set(D, P, &err) == CB_OK &&
             cb_implicit_from_dixon(F, D, P, &err) == CB_OK &&
             cb_phi_compute(ph, F, Q, &err) == CB_OK;
    CHECK(ok, "example 2: phi = F(Q): %s", err.msg);
    if (!ok)
        goto out_phi;

    fmpz_mpoly_ctx_t ctx;
    fmpz_mpoly_t phi;
    cb_bipoly_t pb;
    fmpz_poly_t res;
    fmpq_t s0, s1, t0, t1, a, w;
    fmpz_poly_t f;
    fmpz_mpoly_ctx_init(ctx, 2, ORD_LEX);
    fmpz_mpoly_init(phi, ctx);
    cb_bipoly_init(pb);
    fmpz_poly_init(res);
    fmpq_init(s0);
    fmpq_init(s1);
    fmpq_init(t0);
    fmpq_init(t1);
    fmpq_init(a);
    fmpq_init(w);
    fmpz_poly_init(f);
    for (slong i = 0; i <= ph->ds; i++)
        for (slong j = 0; j <= ph->dt; j++) {
            ulong e[2] = {(ulong)i, (ulong)j};
            fmpz_mpoly_set_coeff_fmpz_ui(phi, ph->c + i * (ph->dt + 1) + j, e, ctx);
        }
    fmpq_set_si(s0, -1, 1);
    fmpq_set_si(s1, 1, 1);
    fmpq_set_si(t0, 0, 1);
    fmpq_set_si(t1, 2, 1);

    /* s-critical values: Res_t(phi, phi_t) in [-1, 1], exactly three; alpha2 = 0 exactly. */
    cb_bipoly_set_fmpz_mpoly(pb, phi, ctx);
    cb_bipoly_resultant_dt(res, pb);
    cb_roots_t cv;
    cb_roots_init(cv);
    fmpq_set_si(w, 1, 1);
    fmpq_div_2exp(w, w, 50);
    CHECK(!fmpz_poly_is_zero(res) && cb_roots_isolate(cv, res, s0, s1, &err) == CB_OK,
          "example 2: resultant roots");
    /* Four distinct real roots: the paper's three and one at s ~ -0.921961226 of multiplicity
     * 4 (no sign change, invisible to a floating solver), over which the multiple roots of
     * phi(s, .) are complex: no real critical point, checked on the topology below. */
    CHECK(cv->n == 4, "example 2: %ld real roots of the resultant in [-1, 1], expected 4",
          (long)cv->n);
    if (cv->n == 4) {
        fmpz_poly_t dr;
        fmpz_poly_init(dr);
        fmpz_poly_derivative(dr, res);
        cb_roots_refine(cv, 0, w);
        CHECK(fabs(q_d(cv->root[0].lo) + 0.921961226081) < 1e-10 &&
                  cb_ctopo_alg_vanishes(dr, cv->sqfree, cv->root[0].lo, cv->root[0].hi),
              "example 2: extra root %.12f not the multiple root at -0.921961226081",
              q_d(cv->root[0].lo));
        fmpz_poly_clear(dr);
    }
    /* The paper's intervals, widened by 1e-10 (agreement to 1e-10). */
    const double pap[3][2] = {{-942370651714277.0 / 4503599627370496.0,
                               -15077930427428431.0 / 72057594037927936.0},
                              {0, 0},
                              {3860892779556277.0 / 18014398509481984.0,
                               15443571118225109.0 / 72057594037927936.0}};
    for (slong k = 0; k < 3 && cv->n == 4; k++) {
        const cb_root_interval_struct *iv = cv->root + k + 1;
        if (k == 1) {
            CHECK(fmpq_is_zero(iv->lo) && fmpq_is_zero(iv->hi),
                  "example 2: alpha2 not the exact rational 0: [%g, %g]", q_d(iv->lo),
                  q_d(iv->hi));
            continue;
        }
        cb_roots_refine(cv, k + 1, w);
        double lo = q_d(iv->lo), hi = q_d(iv->hi);
        printf("example 2: alpha%ld in [%.17g, %.17g]\n", (long)k + 1, lo, hi);
        CHECK(lo >= pap[k][0] - 1e-10 && hi <= pap[k][1] + 1e-10,
              "example 2: alpha%ld in [%.17g, %.17g], paper [%.17g, %.17g]", (long)k + 1, lo, hi,
              pap[k][0], pap[k][1]);
    }

    /* The paper's helping points from our phi at the paper's s-values, to 1e-8. */
    static const double help[6][4] = {{0.4824088532, 1.655782000},
                                      {0.5915023911, 0.5915169779, 1.496790140, 1.496826202},
                                      {0.4773526276, 0.9999999967, 1.000000003, 1.665001610},
                                      {0.4824088532, 0.9999999994, 1.000000001, 1.655782000},
                                      {0.5915016720, 0.5915176969, 1.496790139, 1.496826203},
                                      {0.4773526276, 1.665001610}};
    static const slong n_help[6] = {2, 4, 4, 4, 4, 2};
    const slong sl[6][2] = {{-942370651714277, 52}, {-1, 0}, {3860892779556277, 54},
                            {-15077930427428431, 56}, {1, 0}, {15443571118225109, 56}};
    cb_bipoly_t hb;
    cb_bipoly_init(hb);
    cb_bipoly_set_fmpz_mpoly(hb, phi, ctx);
    for (int i = 0; i < 6; i++) {
        if (i == 1 || i == 4) {
            fmpq_set_si(a, sl[i][0], 1000000); /* -+ eps, eps = 1e-6 */
        } else {
            fmpz_set_si(fmpq_numref(a), sl[i][0]);
            fmpz_one_2exp(fmpq_denref(a), (ulong)sl[i][1]);
        }
        double got[8];
        cb_bipoly_eval_s_fmpq(f, hb, a);
        slong n = roots_d(got, f, t0, t1);
        if (i == 1 || i == 4) {
            /* At -+1e-6 the pairs of our exact roots are 1.5e-6 apart where the paper prints
             * 1.46e-5 and 1.60e-5 (its values look like eps ~ 1e-5, and are not symmetric
             * though phi's roots at -+eps agree to 1e-10): the eps-dependent points are not
             * comparable. Their pair midpoints are (O(eps^2)): the t of the two nodes. */
            const double *hv = help[i];
            double want[2] = {0.5 * (hv[0] + hv[1]), 0.5 * (hv[2] + hv[3])};
            double mid[2] = {n == 4 ? 0.5 * (got[0] + got[1]) : 0,
                             n == 4 ? 0.5 * (got[2] + got[3]) : 0};
            printf("example 2: s = %g: helping points %.10f %.10f %.10f %.10f\n", q_d(a),
                   got[0], got[1], got[2], got[3]);
            CHECK(same_list(mid, n == 4 ? 2 : 0, want, 2, 1e-8),
                  "example 2: pair midpoints at s = %g: %.10f %.10f, paper %.10f %.10f",
                  q_d(a), mid[0], mid[1], want[0], want[1]);
            continue;
        }
        CHECK(same_list(got, n, help[i], n_help[i], 1e-8),
              "example 2: %s helping points at s = %.10g: %ld roots, first %.10f",
              i < 3 ? "left" : "right", q_d(a), (long)n, n > 0 ? got[0] : 0.0);
    }
    cb_bipoly_clear(hb);

    /* The topology. */
    cb_ctopo_opts opts;
    cb_ctopo_t T;
    cb_ctopo_opts_default(&opts);
    cb_ctopo_init(T);
    cb_status st = cb_ctopo_compute(T, phi, ctx, s0, s1, t0, t1, &opts, &err);
    CHECK(st == CB_OK, "example 2 topology: %s: %s", cb_status_name(st), err.msg);
    if (st == CB_OK) {
        printf("example 2: lines %ld, components %ld, loops %ld, isolated %ld, singular %ld "
               "(vertices %ld, edges %ld)\n",
               (long)T->n_lines, (long)T->n_components, (long)T->n_loops, (long)T->n_isolated,
               (long)T->n_singular, (long)T->n_vertices, (long)T->n_edges);
        graph_ok(T, "example 2", qbox);
        /* Our helping points next to alpha1 and alpha3 away from the fold at t = 1: at
         * alpha1 the branches through 0.4824088532 and 1.655782000, at alpha3 through
         * 0.4773526276 and 1.665001610 (their t moves by ~1e-16 over alpha's interval). */
        static const double far[2][2] = {{0.4824088532, 1.655782000},
                                         {0.4773526276, 1.665001610}};
        for (int k = 0; k < 2; k++) {
            double s_alpha = k ? 0.2143226030 : -0.2092483191;
            slong found[2] = {0, 0};
            for (slong i = 0; i < T->n_vertices; i++) {
                const cb_ctopo_vertex_struct *v = T->vertex + i;
                if (v->kind != CB_CTOPO_HELPING || fabs(v->s - s_alpha) > 1e-9)
                    continue;
                for (int j = 0; j < 2; j++)
                    found[j] += fabs(v->t - far[k][j]) < 1e-8;
            }
            CHECK(found[0] == 2 && found[1] == 2,
                  "example 2: helping points at alpha%d: %ld and %ld of 2 found", 2 * k + 1,
                  (long)found[0], (long)found[1]);
        }
        /* Fig. 14: two arcs crossing the box from s = -1 to s = 1 (near t = 0.48 and 1.66)
         * and a loop born at alpha1 (fold at t = 1) and closing at alpha3 (fold at t = 1)
         * that crosses both arcs at s = alpha2 = 0, in the two nodes (t ~ 0.5915097 and
         * 1.4968082, degree 4): one component touching the sides, no loop of its own, two
         * singular points. The critical points are exactly over alpha1, alpha2, alpha3. */
        CHECK(T->n_components == 1 && T->n_loops == 0 && T->n_isolated == 0 &&
                  T->n_singular == 2,
              "example 2: components %ld loops %ld isolated %ld singular %ld, expected 1 0 0 2",
              (long)T->n_components, (long)T->n_loops, (long)T->n_isolated,
              (long)T->n_singular);
        slong folds = 0, nodes = 0, other = 0;
        for (slong i = 0; i < T->n_vertices; i++) {
            const cb_ctopo_vertex_struct *v = T->vertex + i;
            if (v->kind != CB_CTOPO_CRITICAL)
                continue;
            const cb_ctopo_line_struct *L = T->line + v->line;
            int fold = !v->singular && v->degree == 2 && fabs(v->t - 1) < 1e-2 &&
                       (fabs(L->s + 0.2092483191) < 1e-9 || fabs(L->s - 0.2143226030) < 1e-9);
            int node = v->singular && v->degree == 4 && fmpq_is_zero(L->lo) &&
                       fmpq_is_zero(L->hi) &&
                       (fabs(v->t - 0.5915097) < 1e-2 || fabs(v->t - 1.4968082) < 1e-2);
            folds += fold;
            nodes += node;
            other += !fold && !node;
        }
        CHECK(folds == 2 && nodes == 2 && other == 0,
              "example 2: critical points: %ld folds, %ld nodes, %ld others; expected 2, 2, 0",
              (long)folds, (long)nodes, (long)other);
    }
    cb_ctopo_clear(T);
    cb_roots_clear(cv);
    fmpz_poly_clear(f);
    fmpq_clear(w);
    fmpq_clear(a);
    fmpq_clear(t1);
    fmpq_clear(t0);
    fmpq_clear(s1);
    fmpq_clear(s0);
    fmpz_poly_clear(res);
    cb_bipoly_clear(pb);
    fmpz_mpoly_clear(phi, ctx);
    fmpz_mpoly_ctx_clear(ctx);
out_phi:
    cb_phi_clear(ph);
    cb_implicit_clear(F);
    cb_dixon_pencil_clear(D);
    cb_dixon_patch_clear(Q);
    cb_dixon_patch_clear(P);
}

int main(void)
{
    check_rng rng = {20240607};
    test_modular(&rng);
    test_designed();
    test_example2();
    test_subresultant(&rng);
    test_errors();
    test_random(&rng);
    return check_report("test_ssi_topo");
}
