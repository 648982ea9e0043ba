/* scenario.c — the shipped Boolean scenarios as loaded operands with reference volumes
 * (cb_model_scenario_* in models.h). */
#include <stdio.h>
#include <string.h>

#include "brep/mass.h"
#include "brep/prim.h"
#include "models/models.h"

/* The bracket scenarios, after the Cardan ones: a bolt through the hole of the horizontal
 * leg (coincident cylinders), and a rod lying in the inner corner (coincident with the fillet,
 * tangent to the two planes along the fillet's edges). */
enum { N_BRACKET = 2 };
static const char *const bracket_names[N_BRACKET] = {"bracket_bolt", "bracket_rod"};

double cb_bracket_cylinder_volume(const cb_bracket_cylinder *c)
{
    return 3.14159265358979323846 * c->radius * c->radius * c->length;
}

int cb_model_scenario_count(void)
{
    return 1 + 2 * cb_cardan_scenario_count() + 2 * N_BRACKET;
}

int cb_bracket_scenario_count(void)
{
    return N_BRACKET;
}

const char *cb_bracket_scenario_cylinder(cb_bracket_cylinder *c, int k)
{
    cb_bracket_params p;
    cb_bracket_params_default(&p);
    const cb_bracket_shape *b = &p.shape;
    memset(c, 0, sizeof *c);
    if (k == 0) {
        /* Through the hole, from a thickness below to two above the leg's bottom. */
        c->radius = b->hole_radius;
        c->length = 3 * b->thickness;
        c->origin[0] = b->hole_x;
        c->origin[2] = -b->thickness;
        c->axis[2] = 1;
        c->ref[1] = 1;
    } else {
        /* In the corner, on the fillet's axis, half a unit past the bracket on each side. */
        c->radius = b->fillet;
        c->length = b->width + 1;
        c->origin[0] = c->origin[2] = b->thickness + b->fillet;
        c->origin[1] = -0.5 * b->width - 0.5;
        c->axis[1] = 1;
        c->ref[0] = 1;
    }
    return bracket_names[k];
}

static cb_status load_bracket(cb_model_scenario *s, int k, int nurbs, cb_error *err)
{
    cb_bracket_params p;
    cb_bracket_params_default(&p);
    p.as_nurbs = nurbs;
    const cb_bracket_shape *b = &p.shape;
    cb_bracket_cylinder c;
    cb_bracket_scenario_cylinder(&c, k);
    cb_frame f;
    cb_status st = cb_model_bracket(&s->a, &p, err);
    if (!st)
        st = cb_frame_make(&f, c.origin, c.axis, c.ref, err);
    if (!st)
        st = cb_prim_cylinder(&s->b, &f, c.radius, c.length, nurbs, 0, err);
    if (!st)
        st = cb_topo_compute_pcurves(s->b, s->b->tol, err);
    if (st)
        return st;
    double va = cb_bracket_volume(b), vb = cb_bracket_cylinder_volume(&c);
    s->ref[0] = va + vb;
    s->ref[1] = 0;
    s->ref[2] = va;
    for (int j = 0; j < 3; j++)
        s->bar[j] = CB_SCENARIO_REL_BAR * s->ref[j] + CB_SCENARIO_ABS_BAR * (va + vb);
    s->source = "closed form";
    return CB_OK;
}

static cb_status load_birds(cb_model_scenario *s, cb_error *err)
{
    cb_hummingbird_params pa, pb;
    cb_hummingbird_pair(&pa, &pb);
    cb_status st = cb_model_hummingbird(&s->a, &pa, err);
    if (!st)
        st = cb_model_hummingbird(&s->b, &pb, err);
    if (!st)
        st = cb_topo_compute_pcurves(s->a, s->a->tol, err);
    if (!st)
        st = cb_topo_compute_pcurves(s->b, s->b->tol, err);
    cb_mass_props ma, mb;
    if (!st)
        st = cb_mass_body(&ma, s->a, CB_MASS_REL_TOL, NULL, err);
    if (!st)
        st = cb_mass_body(&mb, s->b, CB_MASS_REL_TOL, NULL, err);
    if (st)
        return st;
    const cb_overlap_estimate *e = &cb_hummingbird_pair_reference;
    s->ref[0] = ma.volume + mb.volume - e->volume_ab;
    s->ref[1] = e->volume_ab;
    s->ref[2] = ma.volume - e->volume_ab;
    for (int k = 0; k < 3; k++)
        s->bar[k] = 3 * e->sigma_ab;
    s->source = "estimate by vertical lines, 3 standard deviations";
    return CB_OK;
}

static cb_status load_cardan(cb_model_scenario *s, int k, int nurbs, cb_error *err)
{
    cb_cardan_scenario c;
    cb_cardan_volumes v;
    cb_status st = cb_cardan_scenario_get(&c, k, err);
    c.a.as_nurbs = c.b.as_nurbs = nurbs;
    if (!st)
        st = cb_cardan_scenario_volumes(&v, &c, err);
    if (!st)
        st = cb_model_cardan(&s->a, &c.a, err);
    if (!st)
        st = cb_model_cardan(&s->b, &c.b, err);
    if (st)
        return st;
    s->ref[0] = v.a_union_b;
    s->ref[1] = v.a_inter_b;
    s->ref[2] = v.a_minus_b;
    for (int j = 0; j < 3; j++)
        s->bar[j] = CB_SCENARIO_REL_BAR * s->ref[j] + CB_SCENARIO_ABS_BAR * (v.a + v.b);
    s->source = "closed form";
    return CB_OK;
}

cb_status cb_model_scenario_name(char *name, size_t n, int k, cb_error *err)
{
    int nc = cb_cardan_scenario_count(), count = cb_model_scenario_count();
    if (k < 0 || k >= count)
        return cb_error_set(err, CB_ERR_INVALID, "scenario %d: not in 0 .. %d", k, count - 1);
    if (k == 0) {
        snprintf(name, n, "hummingbirds");
        return CB_OK;
    }
    if (k > 2 * nc) {
        int j = k - 1 - 2 * nc;
        snprintf(name, n, "%s%s", bracket_names[j % N_BRACKET], j >= N_BRACKET ? "_nurbs" : "");
        return CB_OK;
    }
    cb_cardan_scenario c;
    cb_status st = cb_cardan_scenario_get(&c, (k - 1) % nc, err);
    if (!st)
        snprintf(name, n, "%s%s", c.name, k > nc ? "_nurbs" : "");
    return st;
}

cb_status cb_model_scenario_load(cb_model_scenario *s, int k, cb_error *err)
{
    memset(s, 0, sizeof *s);
    cb_status st = cb_model_scenario_name(s->name, sizeof s->name, k, err);
    if (st)
        return st;
    int nc = cb_cardan_scenario_count();
    if (k == 0)
        st = load_birds(s, err);
    else if (k <= 2 * nc)
        st = load_cardan(s, (k - 1) % nc, k > nc, err);
    else
        st = load_bracket(s, (k - 1 - 2 * nc) % N_BRACKET, k - 1 - 2 * nc >= N_BRACKET, err);
    if (st)
        cb_model_scenario_clear(s);
    return st;
}

void cb_model_scenario_clear(cb_model_scenario *s)
{
    cb_topo_body_free(s->a);
    cb_topo_body_free(s->b);
    memset(s, 0, sizeof *s);
}
