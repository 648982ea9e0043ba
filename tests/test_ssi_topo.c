/* Certified curve topology (ssi/topo.c): designed curves in [0, 1]^2 with known topology, graph
 * invariants, subresultant identities, and error paths. */
#include <math.h>
#include <stdlib.h>

#include <arb.h>

#include "check.h"
#include "ssi/curve_topo.h"

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
};

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

/* Structural facts every topology graph must satisfy. */
static int graph_ok(const cb_ctopo_t T, const char *name)
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
        int in_box = v->s >= -1e-12 && v->s <= 1 + 1e-12 && v->t >= -1e-12 && v->t <= 1 + 1e-12;
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
            graph_ok(T, d->name);
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
            graph_ok(T, name);
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

int main(void)
{
    check_rng rng = {20240607};
    test_designed();
    test_subresultant(&rng);
    test_errors();
    test_random(&rng);
    return check_report("test_ssi_topo");
}
