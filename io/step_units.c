/* Units, uncertainty and assembly placement of the representation that holds a solid.
 *
 * Lengths are kept in the file's unit (the body records its size in millimetres), because
 * scaling would have to touch the parameter spaces of pcurves on planes but not on periodic
 * surfaces; angles, which only enter the analytic geometry through the cone's semi-angle, are
 * converted to radians. */
#include <math.h>
#include <stdlib.h>
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

/* The placement that takes frame fr[0] onto frame fr[1] (child coordinates to parent
 * coordinates, as both an ITEM_DEFINED_TRANSFORMATION and a MAPPED_ITEM give it). */
static void frames_xform(cb_xform *x, const cb_frame fr[2])
{
    cb_xform f1, f2;
    frame_xform(&f1, &fr[0]);
    frame_xform(&f2, &fr[1]);
    xform_inverse(&f1, &f1);
    cb_xform_compose(x, &f2, &f1);
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
    frames_xform(x, fr);
    return CB_OK;
}

/* One link of the assembly tree: the representation `child` placed in `parent` by x (child
 * coordinates to parent coordinates), or, when !moved, two representations of one shape. */
struct step_link {
    long child, parent;
    int moved;
    cb_xform x;
};

enum { MAX_PLACEMENTS = 100000, MAX_COMPONENT = 4096 };

static cb_status add_link(step_file *f, int *cap, long child, long parent, int moved,
                          const cb_xform *x)
{
    if (f->n_links == *cap) {
        int c = *cap ? 2 * *cap : 64;
        struct step_link *l = realloc(f->links, (size_t)c * sizeof *l);
        if (!l)
            return cb_error_set(f->err, CB_ERR_NOMEM, "%s: out of memory", f->path);
        f->links = l;
        *cap = c;
    }
    struct step_link *l = &f->links[f->n_links++];
    l->child = child;
    l->parent = parent;
    l->moved = moved;
    if (x)
        l->x = *x;
    else
        cb_xform_identity(&l->x);
    return CB_OK;
}

/* MAPPED_ITEM(name, mapping_source, mapping_target): the mapped representation of
 * REPRESENTATION_MAP(mapping_origin, mapped_representation) and the motion taking
 * mapping_origin onto mapping_target. */
static cb_status mapped_item(step_file *f, const step_rec *m, long *rep, cb_xform *x)
{
    const step_node *a = step_args(f, m, step_part_of(f, m, STEP_T_MAPPED_ITEM), 3);
    const step_rec *src, *origin, *target, *mapped;
    cb_status st;
    if (!a)
        return f->err->status;
    if ((st = step_get_ref(f, m, step_next(a), "mapping_source", &src)) ||
        (st = step_get_ref(f, m, step_next(step_next(a)), "mapping_target", &target)))
        return st;
    const step_part *mp = step_part_of(f, src, STEP_T_REPRESENTATION_MAP);
    if (!mp)
        return step_fail(f, src, NULL, CB_ERR_INVALID,
                         "REPRESENTATION_MAP expected for the mapping source");
    const step_node *ma = step_args(f, src, mp, 2);
    if (!ma)
        return f->err->status;
    if ((st = step_get_ref(f, src, ma, "mapping_origin", &origin)) ||
        (st = step_get_ref(f, src, step_next(ma), "mapped_representation", &mapped)))
        return st;
    if (!step_part_of(f, target, STEP_T_AXIS2_PLACEMENT_3D))
        return step_fail(f, target, NULL, CB_ERR_UNSUPPORTED,
                         "only AXIS2_PLACEMENT_3D mapping targets are supported (MAPPED_ITEM "
                         "#%ld)",
                         m->id);
    cb_frame fr[2];
    if ((st = step_frame(f, origin, 3, &fr[0])) || (st = step_frame(f, target, 3, &fr[1])))
        return st;
    frames_xform(x, fr);
    *rep = mapped->id;
    return CB_OK;
}

/* The record the i-th parameter of part p references, or NULL. */
static const step_rec *ref_arg(const step_file *f, const step_part *p, int i)
{
    const step_node *list = &f->nodes[p->args];
    if (!p || i >= list->n)
        return NULL;
    const step_node *x = step_elem(list, i);
    return x->kind == STEP_REF ? step_find(f, x->v.ref) : NULL;
}

/* The product definition and representation of each SHAPE_DEFINITION_REPRESENTATION (through
 * its PRODUCT_DEFINITION_SHAPE), as pairs pd[2k], rep[2k + 1]. */
static long *shape_definitions(const step_file *f, int *n)
{
    long *pairs = NULL;
    int cap = 0;
    *n = 0;
    for (int k = 0; k < f->n_recs; k++) {
        const step_rec *r = &f->recs[k];
        const step_part *p = step_part_of(f, r, STEP_T_SHAPE_DEFINITION_REPRESENTATION);
        const step_rec *pds = p ? ref_arg(f, p, 0) : NULL, *rep = p ? ref_arg(f, p, 1) : NULL;
        const step_part *pp = pds ? step_part_of(f, pds, STEP_T_PRODUCT_DEFINITION_SHAPE) : NULL;
        const step_rec *pd = pp ? ref_arg(f, pp, 2) : NULL;
        if (!pd || !rep)
            continue;
        if (*n == cap) {
            cap = cap ? 2 * cap : 64;
            long *q = realloc(pairs, (size_t)cap * 2 * sizeof *q);
            if (!q) {
                free(pairs);
                *n = -1;
                return NULL;
            }
            pairs = q;
        }
        pairs[2 * *n] = pd->id;
        pairs[2 * *n + 1] = rep->id;
        (*n)++;
    }
    return pairs;
}

static int defines(const long *pairs, int n, long pd, long rep)
{
    for (int k = 0; k < n; k++)
        if (pairs[2 * k] == pd && pairs[2 * k + 1] == rep)
            return 1;
    return 0;
}

/* 1 when the representation relationship rel, placed by a CONTEXT_DEPENDENT_SHAPE_REPRESENTATION
 * for an assembly usage (NEXT_ASSEMBLY_USAGE_OCCURRENCE: relating the parent product
 * definition, related the child), names the parent's representation as rep_1 and the child's
 * as rep_2: some writers do, where ISO 10303-214 puts the child first. Their
 * ITEM_DEFINED_TRANSFORMATION then takes a frame of the parent (item_1, in rep_1) to one of
 * the child, so the child's placement is its inverse (as Open CASCADE reads them too). */
static int reversed_usage(const step_file *f, const step_rec *cdsr, const long *pairs, int n,
                          long *rel_id)
{
    const step_part *p = step_part_of(f, cdsr, STEP_T_CONTEXT_DEPENDENT_SHAPE_REPRESENTATION);
    const step_rec *rel = ref_arg(f, p, 0), *pds = ref_arg(f, p, 1);
    const step_part *pp = pds ? step_part_of(f, pds, STEP_T_PRODUCT_DEFINITION_SHAPE) : NULL;
    const step_rec *usage = pp ? ref_arg(f, pp, 2) : NULL;
    const step_part *up = usage ? &f->parts[usage->part0] : NULL;
    const step_part *rp = rel ? step_part_of(f, rel, STEP_T_REPRESENTATION_RELATIONSHIP) : NULL;
    if (!rp && rel)
        rp = step_part_of(f, rel, STEP_T_SHAPE_REPRESENTATION_RELATIONSHIP);
    if (!up || !rp || f->nodes[up->args].n < 5 || f->nodes[rp->args].n != 4)
        return 0;
    const step_rec *parent = ref_arg(f, up, 3), *child = ref_arg(f, up, 4);
    const step_rec *r1 = ref_arg(f, rp, 2), *r2 = ref_arg(f, rp, 3);
    if (!parent || !child || !r1 || !r2)
        return 0;
    *rel_id = rel->id;
    int swapped = defines(pairs, n, parent->id, r1->id) || defines(pairs, n, child->id, r2->id);
    int straight = defines(pairs, n, child->id, r1->id) || defines(pairs, n, parent->id, r2->id);
    return swapped && !straight;
}

/* The links record r makes: a representation relationship, or the MAPPED_ITEMs among the items
 * of a shape representation. rev: the relationships written parent first (reversed_usage). */
static cb_status gather_link(step_file *f, const step_rec *r, const long *rev, int n_rev,
                             int *cap)
{
    cb_status st;
    {
        const step_part *p = step_part_of(f, r, STEP_T_REPRESENTATION_RELATIONSHIP);
        if (!p)
            p = step_part_of(f, r, STEP_T_SHAPE_REPRESENTATION_RELATIONSHIP);
        if (p && f->nodes[p->args].n == 4) {
            const step_node *r1 = step_elem(&f->nodes[p->args], 2), *r2 = step_next(r1);
            if (r1->kind != STEP_REF || r2->kind != STEP_REF)
                return CB_OK;
            const step_part *wt =
                step_part_of(f, r, STEP_T_REPRESENTATION_RELATIONSHIP_WITH_TRANSFORMATION);
            cb_xform x;
            if (wt) {
                const step_node *a = step_args(f, r, wt, 1);
                const step_rec *t;
                if (!a)
                    return f->err->status;
                if ((st = step_get_ref(f, r, a, "transformation_operator", &t)) ||
                    (st = item_transform(f, t, &x)))
                    return st;
            }
            int swap = 0;
            for (int j = 0; j < n_rev && !swap; j++)
                swap = rev[j] == r->id;
            if (swap)
                xform_inverse(&x, &x);
            return add_link(f, cap, swap ? r2->v.ref : r1->v.ref, swap ? r1->v.ref : r2->v.ref,
                            wt != NULL, wt ? &x : NULL);
        }
        /* MAPPED_ITEMs among the items of a shape representation */
        for (int j = 0; j < r->n_parts; j++) {
            const step_part *q = &f->parts[r->part0 + j];
            const step_node *list = &f->nodes[q->args];
            if (q->type == STEP_T_DEFINITIONAL_REPRESENTATION ||
                !ends_with(f->buf + q->name_off, q->name_len, "SHAPE_REPRESENTATION") ||
                list->n != 3)
                continue;
            const step_node *items = step_elem(list, 1), *x = items + 1;
            if (items->kind != STEP_LIST)
                continue;
            for (int i = 0; i < items->n; i++, x = step_next(x)) {
                const step_rec *m = x->kind == STEP_REF ? step_find(f, x->v.ref) : NULL;
                long child = 0;
                cb_xform mx;
                if (!m || m->complex || step_rec_type(f, m) != STEP_T_MAPPED_ITEM)
                    continue;
                if ((st = mapped_item(f, m, &child, &mx)) ||
                    (st = add_link(f, cap, child, r->id, 1, &mx)))
                    return st;
            }
        }
    }
    return CB_OK;
}

/* Gathers the links of the assembly tree (step_placements_for) once per file. */
static cb_status gather_links(step_file *f)
{
    int cap = 0, n_pairs, n_rev = 0, cap_rev = 0;
    long *pairs = shape_definitions(f, &n_pairs), *rev = NULL;
    if (n_pairs < 0)
        return cb_error_set(f->err, CB_ERR_NOMEM, "%s: out of memory", f->path);
    for (int k = 0; k < f->n_recs; k++) {
        long id;
        if (!step_part_of(f, &f->recs[k], STEP_T_CONTEXT_DEPENDENT_SHAPE_REPRESENTATION) ||
            !reversed_usage(f, &f->recs[k], pairs, n_pairs, &id))
            continue;
        if (n_rev == cap_rev) {
            cap_rev = cap_rev ? 2 * cap_rev : 16;
            long *q = realloc(rev, (size_t)cap_rev * sizeof *q);
            if (!q) {
                free(rev);
                free(pairs);
                return cb_error_set(f->err, CB_ERR_NOMEM, "%s: out of memory", f->path);
            }
            rev = q;
        }
        rev[n_rev++] = id;
    }
    free(pairs);
    cb_status st = CB_OK;
    for (int k = 0; k < f->n_recs && !st; k++)
        st = gather_link(f, &f->recs[k], rev, n_rev, &cap);
    free(rev);
    if (!st)
        f->links_ready = 1;
    return st;
}

typedef struct {
    cb_xform *x;
    int n, cap;
} placement_list;

static int xform_equal(const cb_xform *a, const cb_xform *b)
{
    return !memcmp(a->r, b->r, sizeof a->r) && !memcmp(a->t, b->t, sizeof a->t);
}

/* The representations joined to rep by links without a transformation, rep included. */
static cb_status component(step_file *f, long rep, long *members, int *n)
{
    members[0] = rep;
    *n = 1;
    for (int i = 0; i < *n; i++)
        for (int k = 0; k < f->n_links; k++) {
            const struct step_link *l = &f->links[k];
            if (l->moved || (l->child != members[i] && l->parent != members[i]))
                continue;
            long other = l->child == members[i] ? l->parent : l->child;
            int seen = 0;
            for (int j = 0; j < *n && !seen; j++)
                seen = members[j] == other;
            if (seen)
                continue;
            if (*n == MAX_COMPONENT)
                return cb_error_set(f->err, CB_ERR_INVALID,
                                    "%s: more than %d representations joined as one shape",
                                    f->path, MAX_COMPONENT);
            members[(*n)++] = other;
        }
    return CB_OK;
}

/* Appends to out every placement of rep's shape in the roots, each composed with acc (rep
 * coordinates to world is placement o acc). path holds the representations of the shapes
 * above, for cycles. */
static cb_status walk(step_file *f, const step_rec *at, long rep, const cb_xform *acc,
                      long *path, int depth, placement_list *out)
{
    if (depth == MAX_ASSEMBLY_DEPTH)
        return step_fail(f, at, NULL, CB_ERR_INVALID,
                         "assembly tree deeper than %d representations (cyclic?)",
                         MAX_ASSEMBLY_DEPTH);
    long *members = malloc(MAX_COMPONENT * sizeof *members);
    int n_members;
    if (!members)
        return cb_error_set(f->err, CB_ERR_NOMEM, "%s: out of memory", f->path);
    cb_status st = component(f, rep, members, &n_members);
    path[depth] = rep;
    int exits = 0;
    for (int k = 0; !st && k < f->n_links; k++) {
        const struct step_link *l = &f->links[k];
        if (!l->moved)
            continue;
        int in = 0;
        for (int j = 0; j < n_members && !in; j++)
            in = members[j] == l->child;
        if (!in)
            continue;
        /* a parent joined to a shape already on the path closes a cycle: skip it */
        int cyc = 0;
        for (int j = 0; j <= depth && !cyc; j++)
            cyc = path[j] == l->parent;
        for (int j = 0; j < n_members && !cyc; j++)
            cyc = members[j] == l->parent;
        if (cyc)
            continue;
        exits++;
        cb_xform x;
        cb_xform_compose(&x, &l->x, acc);
        st = walk(f, at, l->parent, &x, path, depth + 1, out);
    }
    free(members);
    if (st || exits)
        return st;
    for (int k = 0; k < out->n; k++)
        if (xform_equal(&out->x[k], acc))
            return CB_OK;
    if (out->n == MAX_PLACEMENTS)
        return step_fail(f, at, NULL, CB_ERR_INVALID, "more than %d instances in the assembly",
                         MAX_PLACEMENTS);
    if (out->n == out->cap) {
        int c = out->cap ? 2 * out->cap : 8;
        cb_xform *x = realloc(out->x, (size_t)c * sizeof *x);
        if (!x)
            return cb_error_set(f->err, CB_ERR_NOMEM, "%s: out of memory", f->path);
        out->x = x;
        out->cap = c;
    }
    out->x[out->n++] = *acc;
    return CB_OK;
}

static int linked(const step_file *f, long rep)
{
    for (int k = 0; k < f->n_links; k++)
        if (f->links[k].child == rep || f->links[k].parent == rep)
            return 1;
    return 0;
}

cb_status step_placements_for(step_file *f, const step_rec *item, cb_xform **out, int *n)
{
    *out = NULL;
    *n = 0;
    placement_list list = {NULL, 0, 0};
    cb_xform id;
    cb_xform_identity(&id);
    cb_status st = CB_OK;
    /* Every representation holding the item that the assembly tree links (one that is joined
     * to nothing, such as a shape aspect's representation of a part's solid for its
     * validation properties, places nothing); the first holding it when none is linked. */
    const step_rec *first = NULL;
    int walked = 0;
    long path[MAX_ASSEMBLY_DEPTH];
    for (int k = 0; k < f->n_recs && !st; k++) {
        const step_rec *r = &f->recs[k];
        int holds = 0;
        for (int j = 0; j < r->n_parts && !holds; j++) {
            const step_part *p = &f->parts[r->part0 + j];
            holds = p->type != STEP_T_DEFINITIONAL_REPRESENTATION &&
                    ends_with(f->buf + p->name_off, p->name_len, "REPRESENTATION") &&
                    rep_part_holds(f, p, item->id);
        }
        if (!holds)
            continue;
        if (!first)
            first = r;
        if (!f->links_ready && (st = gather_links(f)))
            break;
        if (linked(f, r->id)) {
            st = walk(f, r, r->id, &id, path, 0, &list);
            walked = 1;
        }
    }
    if (!st && !walked && first)
        st = walk(f, first, first->id, &id, path, 0, &list);
    if (!st && !list.n) {
        list.x = malloc(sizeof *list.x);
        if (!list.x)
            return cb_error_set(f->err, CB_ERR_NOMEM, "%s: out of memory", f->path);
        list.x[0] = id;
        list.n = 1;
    }
    if (st) {
        free(list.x);
        return st;
    }
    *out = list.x;
    *n = list.n;
    return CB_OK;
}
