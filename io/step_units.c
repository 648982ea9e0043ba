/* Units, uncertainty and assembly placement of the representation that holds a solid.
 *
 * Lengths are kept in the file's unit (the body records its size in millimetres), because
 * scaling would have to touch the parameter spaces of pcurves on planes but not on periodic
 * surfaces; angles, which only enter the analytic geometry through the cone's semi-angle, are
 * converted to radians. */
#include <math.h>
#include <string.h>

#include "io/step_internal.h"

enum { MAX_UNIT_DEPTH = 8, MAX_ASSEMBLY_DEPTH = 64 };

/* The list of items (args[1]) of a representation part holds a reference to id. */
static int rep_part_holds(const step_file *f, const step_part *p, long id)
{
    const step_node *list = &f->nodes[p->args];
    if (list->n != 3)
        return 0;
    const step_node *items = step_elem(list, 1);
    if (items->kind != STEP_LIST)
        return 0;
    const step_node *x = items + 1;
    for (int k = 0; k < items->n; k++, x = step_next(x))
        if (x->kind == STEP_REF && x->v.ref == id)
            return 1;
    return 0;
}

static int ends_with(const char *s, int len, const char *suffix)
{
    int n = (int)strlen(suffix);
    return len >= n && !memcmp(s + len - n, suffix, (size_t)n);
}

/* The representation (any *_REPRESENTATION but the 2D DEFINITIONAL_REPRESENTATION) whose items
 * hold id; its part in *part. */
static const step_rec *rep_holding(const step_file *f, long id, const step_part **part)
{
    for (int k = 0; k < f->n_recs; k++) {
        const step_rec *r = &f->recs[k];
        for (int j = 0; j < r->n_parts; j++) {
            const step_part *p = &f->parts[r->part0 + j];
            if (p->type != STEP_T_DEFINITIONAL_REPRESENTATION &&
                ends_with(f->buf + p->name_off, p->name_len, "REPRESENTATION") &&
                rep_part_holds(f, p, id)) {
                *part = p;
                return r;
            }
        }
    }
    return NULL;
}

static const struct {
    const char *name;
    double factor;
} SI_PREFIXES[] = {{"EXA", 1e18},  {"PETA", 1e15},  {"TERA", 1e12},   {"GIGA", 1e9},
                   {"MEGA", 1e6},  {"KILO", 1e3},   {"HECTO", 1e2},   {"DECA", 1e1},
                   {"DECI", 1e-1}, {"CENTI", 1e-2}, {"MILLI", 1e-3},  {"MICRO", 1e-6},
                   {"NANO", 1e-9}, {"PICO", 1e-12}, {"FEMTO", 1e-15}, {"ATTO", 1e-18}};

/* The value and unit of a measure with unit m: the MEASURE_WITH_UNIT(value, unit) part of a
 * complex instance ((LENGTH_MEASURE_WITH_UNIT() MEASURE_WITH_UNIT(...)
 * UNCERTAINTY_MEASURE_WITH_UNIT(name, description))), or the first two of the parameters of a
 * simple LENGTH_, PLANE_ANGLE_ or UNCERTAINTY_MEASURE_WITH_UNIT, which inherit them. */
static cb_status measure_with_unit(step_file *f, const step_rec *m, double *value,
                                   const step_rec **unit)
{
    static const struct {
        step_type t;
        int n;
    } forms[] = {{STEP_T_MEASURE_WITH_UNIT, 2},
                 {STEP_T_LENGTH_MEASURE_WITH_UNIT, 2},
                 {STEP_T_PLANE_ANGLE_MEASURE_WITH_UNIT, 2},
                 {STEP_T_UNCERTAINTY_MEASURE_WITH_UNIT, 4}};
    const step_part *p = NULL;
    int n = 0;
    for (size_t k = 0; k < sizeof forms / sizeof *forms && !p; k++) {
        const step_part *q = step_part_of(f, m, forms[k].t);
        /* in a complex instance the subtype parts hold only their own attributes */
        if (q && f->nodes[q->args].n == forms[k].n) {
            p = q;
            n = forms[k].n;
        }
    }
    if (!p)
        return step_fail(f, m, NULL, CB_ERR_INVALID,
                         "a measure with unit (value_component, unit_component) expected");
    const step_node *a = step_args(f, m, p, n);
    cb_status st;
    if (!a)
        return f->err->status;
    if ((st = step_get_real(f, m, a, "value_component", value)) ||
        (st = step_get_ref(f, m, step_next(a), "unit_component", unit)))
        return st;
    return CB_OK;
}

/* Size of the length unit u in millimetres (angle = 0) or of the angle unit in radians. */
static cb_status unit_factor(step_file *f, const step_rec *u, int angle, int depth, double *out)
{
    if (depth > MAX_UNIT_DEPTH)
        return step_fail(f, u, NULL, CB_ERR_INVALID,
                         "unit conversions nested deeper than %d "
                         "(cyclic?)",
                         MAX_UNIT_DEPTH);
    const step_part *p = step_part_of(f, u, STEP_T_SI_UNIT);
    if (p) {
        const step_node *list = &f->nodes[p->args];
        if (list->n < 2)
            return step_fail(f, u, list, CB_ERR_PARSE, "SI_UNIT needs a prefix and a name");
        const step_node *prefix = step_elem(list, list->n - 2), *name = step_next(prefix);
        double scale = 1.0;
        if (prefix->kind == STEP_ENUM) {
            size_t k = 0;
            while (k < sizeof SI_PREFIXES / sizeof *SI_PREFIXES &&
                   !step_is_enum(f, prefix, SI_PREFIXES[k].name))
                k++;
            if (k == sizeof SI_PREFIXES / sizeof *SI_PREFIXES)
                return step_fail(f, u, prefix, CB_ERR_INVALID, "unknown SI prefix");
            scale = SI_PREFIXES[k].factor;
        } else if (prefix->kind != STEP_UNSET) {
            return step_fail(f, u, prefix, CB_ERR_PARSE, "SI prefix: an enumeration or $ expected");
        }
        if (!angle && step_is_enum(f, name, "METRE"))
            *out = 1000.0 * scale;
        else if (angle && step_is_enum(f, name, "RADIAN"))
            *out = scale;
        else
            return step_fail(f, u, name, CB_ERR_UNSUPPORTED, "SI unit not supported for a %s",
                             angle ? "plane angle" : "length");
        return CB_OK;
    }
    if ((p = step_part_of(f, u, STEP_T_CONVERSION_BASED_UNIT))) {
        const step_node *a = step_args(f, u, p, 2);
        const step_rec *m, *base;
        cb_status st;
        if (!a)
            return f->err->status;
        if ((st = step_get_ref(f, u, step_next(a), "conversion_factor", &m)))
            return st;
        double value, base_factor;
        if ((st = measure_with_unit(f, m, &value, &base)) ||
            (st = unit_factor(f, base, angle, depth + 1, &base_factor)))
            return st;
        *out = value * base_factor;
        if (!(*out > 0) || !isfinite(*out))
            return step_fail(f, u, NULL, CB_ERR_INVALID, "conversion factor %g is not positive",
                             *out);
        return CB_OK;
    }
    return step_fail(f, u, NULL, CB_ERR_UNSUPPORTED, "unit kind not supported");
}

cb_status step_units_for(step_file *f, const step_rec *item)
{
    f->length_mm = 1.0;
    f->angle_rad = 1.0;
    f->uncertainty = 1e-6;
    const step_part *rp;
    const step_rec *rep = rep_holding(f, item->id, &rp), *ctx;
    if (!rep)
        return CB_OK;
    cb_status st =
        step_get_ref(f, rep, step_elem(&f->nodes[rp->args], 2), "context_of_items", &ctx);
    if (st)
        return st;
    const step_part *units = step_part_of(f, ctx, STEP_T_GLOBAL_UNIT_ASSIGNED_CONTEXT);
    const step_node *a;
    if (units) {
        if (!(a = step_args(f, ctx, units, 1)) || (st = step_get_list(f, ctx, a, "units", 1, 64)))
            return f->err->status;
        const step_node *x = a + 1;
        for (int k = 0; k < a->n; k++, x = step_next(x)) {
            const step_rec *u;
            if ((st = step_get_ref(f, ctx, x, "unit", &u)))
                return st;
            if (step_part_of(f, u, STEP_T_LENGTH_UNIT))
                st = unit_factor(f, u, 0, 0, &f->length_mm);
            else if (step_part_of(f, u, STEP_T_PLANE_ANGLE_UNIT))
                st = unit_factor(f, u, 1, 0, &f->angle_rad);
            if (st)
                return st;
        }
    }
    const step_part *unc = step_part_of(f, ctx, STEP_T_GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT);
    if (unc) {
        if (!(a = step_args(f, ctx, unc, 1)) ||
            (st = step_get_list(f, ctx, a, "uncertainty", 0, 64)))
            return f->err->status;
        const step_node *x = a + 1;
        for (int k = 0; k < a->n; k++, x = step_next(x)) {
            const step_rec *m, *u;
            double value, mm;
            if ((st = step_get_ref(f, ctx, x, "uncertainty", &m)))
                return st;
            if (!step_part_of(f, m, STEP_T_UNCERTAINTY_MEASURE_WITH_UNIT))
                continue;
            if ((st = measure_with_unit(f, m, &value, &u)))
                return st;
            if (!step_part_of(f, u, STEP_T_LENGTH_UNIT))
                continue;
            if ((st = unit_factor(f, u, 0, 0, &mm)))
                return st;
            if (!(value > 0) || !isfinite(value))
                return step_fail(f, m, NULL, CB_ERR_INVALID, "uncertainty %g is not positive",
                                 value);
            f->uncertainty = value * mm / f->length_mm;
        }
    }
    return CB_OK;
}

/* ---------------------------------------------------------------- assembly placement ------- */

/* The motion taking local coordinates of the placement to world: l -> o + R l. */
static void frame_xform(cb_xform *x, const cb_frame *fr)
{
    for (int i = 0; i < 3; i++) {
        x->r[i][0] = fr->x[i];
        x->r[i][1] = fr->y[i];
        x->r[i][2] = fr->z[i];
        x->t[i] = fr->o[i];
    }
}

static void xform_inverse(cb_xform *out, const cb_xform *x)
{
    cb_xform r;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            r.r[i][j] = x->r[j][i];
    for (int i = 0; i < 3; i++)
        r.t[i] = -(r.r[i][0] * x->t[0] + r.r[i][1] * x->t[1] + r.r[i][2] * x->t[2]);
    *out = r;
}

/* ITEM_DEFINED_TRANSFORMATION(name, description, item_1, item_2): the motion taking the
 * placement item_1 (in the child) onto item_2 (in the parent). */
static cb_status item_transform(step_file *f, const step_rec *t, cb_xform *x)
{
    const step_part *p = step_part_of(f, t, STEP_T_ITEM_DEFINED_TRANSFORMATION);
    if (!p)
        return step_fail(f, t, NULL, CB_ERR_UNSUPPORTED,
                         "only ITEM_DEFINED_TRANSFORMATION placements are supported");
    const step_node *a = step_args(f, t, p, 4);
    if (!a)
        return f->err->status;
    cb_frame fr[2];
    a = step_next(step_next(a));
    for (int k = 0; k < 2; k++, a = step_next(a)) {
        const step_rec *q;
        cb_status st = step_get_ref(f, t, a, k ? "transform_item_2" : "transform_item_1", &q);
        if (!st)
            st = step_frame(f, q, 3, &fr[k]);
        if (st)
            return st;
    }
    cb_xform f1, f2;
    frame_xform(&f1, &fr[0]);
    frame_xform(&f2, &fr[1]);
    xform_inverse(&f1, &f1);
    cb_xform_compose(x, &f2, &f1);
    return CB_OK;
}

/* A representation relationship touching rep (not to a visited one): the other end in *next
 * and, if it carries one, the transformation in *x (*moved = 1). Relationships go from child
 * (rep_1) to parent (rep_2); untransformed ones (linking a shape representation to its B-rep
 * representation) are followed either way, since writers differ in their order. */
static cb_status next_rep(step_file *f, long rep, const long *visited, int n_visited, long *next,
                          cb_xform *x, int *moved)
{
    for (int k = 0; k < f->n_recs; k++) {
        const step_rec *r = &f->recs[k];
        const step_part *p = step_part_of(f, r, STEP_T_REPRESENTATION_RELATIONSHIP);
        if (!p)
            p = step_part_of(f, r, STEP_T_SHAPE_REPRESENTATION_RELATIONSHIP);
        if (!p || f->nodes[p->args].n != 4)
            continue;
        const step_node *r1 = step_elem(&f->nodes[p->args], 2), *r2 = step_next(r1);
        if (r1->kind != STEP_REF || r2->kind != STEP_REF)
            continue;
        const step_part *wt =
            step_part_of(f, r, STEP_T_REPRESENTATION_RELATIONSHIP_WITH_TRANSFORMATION);
        long other;
        if (r1->v.ref == rep)
            other = r2->v.ref;
        else if (r2->v.ref == rep && !wt)
            other = r1->v.ref;
        else
            continue;
        int seen = 0;
        for (int j = 0; j < n_visited; j++)
            seen |= visited[j] == other;
        if (seen)
            continue;
        *next = other;
        *moved = 0;
        if (wt) {
            const step_node *a = step_args(f, r, wt, 1);
            const step_rec *t;
            cb_status st;
            if (!a)
                return f->err->status;
            if ((st = step_get_ref(f, r, a, "transformation_operator", &t)) ||
                (st = item_transform(f, t, x)))
                return st;
            *moved = 1;
        }
        return CB_OK;
    }
    *next = 0;
    return CB_OK;
}

cb_status step_placement_for(step_file *f, const step_rec *item, cb_xform *x)
{
    cb_xform_identity(x);
    const step_part *rp;
    const step_rec *rep = rep_holding(f, item->id, &rp);
    if (!rep)
        return CB_OK;
    long visited[MAX_ASSEMBLY_DEPTH], cur = rep->id;
    for (int n = 0;; n++) {
        if (n == MAX_ASSEMBLY_DEPTH)
            return step_fail(f, rep, NULL, CB_ERR_INVALID,
                             "assembly tree deeper than %d representations", MAX_ASSEMBLY_DEPTH);
        visited[n] = cur;
        long next;
        int moved = 0;
        cb_xform t;
        cb_status st = next_rep(f, cur, visited, n + 1, &next, &t, &moved);
        if (st)
            return st;
        if (!next)
            return CB_OK;
        if (moved)
            cb_xform_compose(x, &t, x);
        cur = next;
    }
}
