/* The cases of the Booleans issue, Colibri beside Open CASCADE (bench_bool_driver.h says what is
 * measured and how; usage: bench_bool [RUNS [OCCT_BOOL [JSON_OUT [SHARED]]]]).
 *
 * The cases, analytic and as B-splines (cb_analytic_to_nurbs nets): the Steinmetz bicylinder,
 * the tricylinder (the Steinmetz solid against the third cylinder), the lens of two unit
 * spheres, a unit sphere on a corner of a box, a torus cut by a box through its centre plane,
 * two boxes sharing a face, a sphere touching a box, a cylinder lying on a box, a cylinder in a
 * hole of its radius, with their closed forms; the Cardan cross into its base
 * (cb_cardan_scenario_volumes); the two hummingbirds (the shipped scenario, its reference an
 * independent estimate); and the universal joint of the shared models (fork against the cross
 * moved by (-100, 0, 0); no closed form: tests/test_bool_op.c checks its volume identities).
 * The closed forms' bars are those of the shipped scenarios: CB_SCENARIO_REL_BAR of the
 * reference plus CB_SCENARIO_ABS_BAR of V(A) + V(B). */
#define _DEFAULT_SOURCE /* wait4: the rusage of one child, not of all of them */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "bench/bench_bool_driver.h"
#include "brep/prim.h"
#include "io/step.h"
#include "models/models.h"

#define PI 3.14159265358979323846

/* The simple solids of the Booleans issue, each analytic and as B-splines, then the Cardan
 * cross into its base (analytic, B-spline), the hummingbirds and the universal joint. */
#define N_SIMPLE 9
#define N_CASES (2 * N_SIMPLE + 4)

static const char *const simple_names[N_SIMPLE] = {
    "steinmetz",         "tricylinder",          "lens",
    "sphere on a corner", "torus and box",        "boxes sharing a face",
    "sphere touching a box", "cylinder on a box", "cylinder in its hole"};

static cb_status cylinder(cb_topo_body **out, const double o[3], const double axis[3],
                          const double ref[3], double r, double h, int nurbs, cb_error *err)
{
    cb_frame f;
    cb_status st = cb_frame_make(&f, o, axis, ref, err);
    return st ? st : cb_prim_cylinder(out, &f, r, h, nurbs, 0, err);
}

static cb_status sphere(cb_topo_body **out, const double c[3], double r, int nurbs,
                        cb_error *err)
{
    const double z[3] = {0, 0, 1}, x[3] = {1, 0, 0};
    cb_frame f;
    cb_status st = cb_frame_make(&f, c, z, x, err);
    return st ? st : cb_prim_sphere(out, &f, r, nurbs, 0, err);
}

/* op of a and b into *out, an operand of a case (untimed). */
static cb_status boolean(cb_topo_body **out, cb_bool_op op, const cb_topo_body *a,
                         const cb_topo_body *b, cb_error *err)
{
    return cb_bool_run(out, NULL, op, a, b, NULL, NULL, err);
}

/* Operands and closed forms of simple case j. */
static cb_status simple_case(bench_bool_case *c, int j, int nurbs, cb_error *err)
{
    const double vi = 16.0 / 3, vc = 4 * PI, ball = 4 * PI / 3;
    const double x[3] = {1, 0, 0}, y[3] = {0, 1, 0}, z[3] = {0, 0, 1}, c0[3] = {0, 0, 0};
    const double ox[3] = {-2, 0, 0}, oy[3] = {0, -2, 0}, oz[3] = {0, 0, -2};
    const double lo[3] = {0, 0, 0}, hi[3] = {2, 2, 2}, op[3] = {1, 1, -1};
    cb_topo_body *t1 = NULL, *t2 = NULL;
    cb_status st = CB_OK;
    double *r = c->ref;
    switch (j) {
    case 0:
        st = cylinder(&c->a, ox, x, z, 1, 4, nurbs, err);
        if (!st)
            st = cylinder(&c->b, oy, y, z, 1, 4, nurbs, err);
        r[0] = 2 * vc - vi, r[1] = vi, r[2] = vc - vi;
        break;
    case 1: {
        const double tri = 8 * (2 - sqrt(2.0));
        st = cylinder(&t1, ox, x, z, 1, 4, nurbs, err);
        if (!st)
            st = cylinder(&t2, oy, y, z, 1, 4, nurbs, err);
        if (!st)
            st = boolean(&c->a, CB_BOOL_INTERSECTION, t1, t2, err);
        if (!st)
            st = cylinder(&c->b, oz, z, x, 1, 4, nurbs, err);
        r[0] = vi + vc - tri, r[1] = tri, r[2] = vi - tri;
        break;
    }
    case 2: {
        const double c1[3] = {1, 0, 0}, lens = 5 * PI / 12;
        st = sphere(&c->a, c0, 1, nurbs, err);
        if (!st)
            st = sphere(&c->b, c1, 1, nurbs, err);
        r[0] = 2 * ball - lens, r[1] = lens, r[2] = ball - lens;
        break;
    }
    case 3:
        st = cb_prim_box(&c->a, NULL, lo, hi, nurbs, 0, err);
        if (!st)
            st = sphere(&c->b, hi, 1, nurbs, err);
        r[0] = 8 + 7 * ball / 8, r[1] = ball / 8, r[2] = 8 - ball / 8;
        break;
    case 4: {
        const double tlo[3] = {-3, -3, -1}, thi[3] = {3, 3, 0}, half = PI * PI * 2 * 0.25;
        cb_frame f;
        st = cb_frame_make(&f, c0, z, x, err);
        if (!st)
            st = cb_prim_torus(&c->a, &f, 2, 0.5, nurbs, 0, err);
        if (!st)
            st = cb_prim_box(&c->b, NULL, tlo, thi, nurbs, 0, err);
        r[0] = 36 + half, r[1] = half, r[2] = half;
        break;
    }
    case 5: {
        const double lo2[3] = {2, 0, 0}, hi2[3] = {4, 2, 2};
        st = cb_prim_box(&c->a, NULL, lo, hi, nurbs, 0, err);
        if (!st)
            st = cb_prim_box(&c->b, NULL, lo2, hi2, nurbs, 0, err);
        r[0] = 16, r[1] = 0, r[2] = 8;
        break;
    }
    case 6: {
        const double top[3] = {1, 1, 3};
        st = cb_prim_box(&c->a, NULL, lo, hi, nurbs, 0, err);
        if (!st)
            st = sphere(&c->b, top, 1, nurbs, err);
        r[0] = 8 + ball, r[1] = 0, r[2] = 8;
        break;
    }
    case 7: {
        const double ol[3] = {-1, 1, 2.5};
        st = cb_prim_box(&c->a, NULL, lo, hi, nurbs, 0, err);
        if (!st)
            st = cylinder(&c->b, ol, x, z, 0.5, 4, nurbs, err);
        r[0] = 8 + PI, r[1] = 0, r[2] = 8;
        break;
    }
    default:
        st = cb_prim_box(&t1, NULL, lo, hi, nurbs, 0, err);
        if (!st)
            st = cylinder(&t2, op, z, x, 0.5, 4, nurbs, err);
        if (!st)
            st = boolean(&c->a, CB_BOOL_DIFFERENCE, t1, t2, err);
        if (!st)
            st = cylinder(&c->b, op, z, y, 0.5, 4, nurbs, err);
        r[0] = 8 + PI / 2, r[1] = 0, r[2] = 8 - PI / 2;
        break;
    }
    cb_topo_body_free(t1);
    cb_topo_body_free(t2);
    return st;
}

/* The universal joint: the fork against the cross moved by (-100, 0, 0). */
static cb_status ujoint_case(bench_bool_case *c, const char *shared, cb_error *err)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/models/ujoint_fork.step", shared);
    cb_status st = cb_step_read(&c->a, path, err);
    if (st)
        return st;
    snprintf(path, sizeof path, "%s/models/ujoint_cross.step", shared);
    if ((st = cb_step_read(&c->b, path, err)))
        return st;
    cb_xform t;
    const double shift[3] = {-100, 0, 0};
    cb_xform_translation(&t, shift);
    cb_topo_body_transform(c->b, &t);
    for (int k = 0; k < 3; k++)
        c->ref[k] = c->bar[k] = NAN;
    return CB_OK;
}

/* The Cardan cross into its base with the closed forms of cb_cardan_scenario_volumes. */
static cb_status cardan_case(bench_bool_case *c, int nurbs, cb_error *err)
{
    cb_cardan_scenario sc;
    cb_cardan_volumes v;
    cb_status st = cb_cardan_scenario_find(&sc, "cross_into_base", err);
    if (st)
        return st;
    sc.a.as_nurbs = sc.b.as_nurbs = nurbs;
    if ((st = cb_cardan_scenario_volumes(&v, &sc, err)) ||
        (st = cb_model_cardan(&c->a, &sc.a, err)) || (st = cb_model_cardan(&c->b, &sc.b, err)))
        return st;
    c->ref[0] = v.a_union_b, c->ref[1] = v.a_inter_b, c->ref[2] = v.a_minus_b;
    return CB_OK;
}

/* Case k of the suite. */
static cb_status build_case(bench_bool_case *c, int k, const char *shared, cb_error *err)
{
    cb_status st;
    if (k < 2 * N_SIMPLE) {
        snprintf(c->name, sizeof c->name, "%s%s", simple_names[k % N_SIMPLE],
                 k >= N_SIMPLE ? " NURBS" : "");
        st = simple_case(c, k % N_SIMPLE, k >= N_SIMPLE, err);
    } else if (k < 2 * N_SIMPLE + 2) {
        snprintf(c->name, sizeof c->name, "cross into base%s", k > 2 * N_SIMPLE ? " NURBS" : "");
        st = cardan_case(c, k > 2 * N_SIMPLE, err);
    } else if (k == 2 * N_SIMPLE + 2) {
        /* The shipped scenario 0, its reference an independent estimate. */
        return bench_bool_scenario_case(c, 0, err);
    } else {
        snprintf(c->name, sizeof c->name, "ujoint");
        return ujoint_case(c, shared, err);
    }
    if (st)
        return st;
    cb_mass_props ma, mb;
    if ((st = cb_mass_body(&ma, c->a, CB_MASS_REL_TOL, NULL, err)) ||
        (st = cb_mass_body(&mb, c->b, CB_MASS_REL_TOL, NULL, err)))
        return st;
    for (int j = 0; j < 3; j++)
        c->bar[j] = CB_SCENARIO_REL_BAR * c->ref[j] + CB_SCENARIO_ABS_BAR * (ma.volume + mb.volume);
    return CB_OK;
}

int main(int argc, char **argv)
{
    const bench_bool_suite suite = {"bench_bool", "Booleans of the Booleans issue", N_CASES,
                                    build_case};
    return bench_bool_main(&suite, argc, argv);
}
