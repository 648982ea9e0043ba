/* Geometry entities: points, directions, placements, curves and surfaces. */
#include <math.h>
#include <string.h>

#include "io/step_internal.h"

/* Coordinates beyond this are taken as corrupt rather than as geometry: squaring them would
 * overflow long before any real model reaches them. */
static const double MAX_COORD = 1e100;

/* The single part of a simple instance of type t, or an error naming what was expected. */
static const step_node *simple_args(step_file *f, const step_rec *r, step_type t, int n,
                                    const char *role)
{
    const step_part *p = step_part_of(f, r, t);
    if (!p) {
        step_fail(f, r, NULL, CB_ERR_INVALID, "%s expected for the %s", step_type_name(t), role);
        return NULL;
    }
    return step_args(f, r, p, n);
}

static cb_status coords(step_file *f, const step_rec *r, step_type t, int dim, double v[3])
{
    const step_node *a = simple_args(f, r, t, 2, t == STEP_T_DIRECTION ? "direction" : "point");
    if (!a)
        return f->err->status;
    const step_node *list = step_next(a);
    cb_status st = step_get_list(f, r, list, "coordinates", dim, dim);
    if (st)
        return st;
    v[2] = 0.0;
    const step_node *x = list + 1;
    for (int k = 0; k < dim; k++, x = step_next(x)) {
        if ((st = step_get_real(f, r, x, "coordinate", &v[k])))
            return st;
        if (fabs(v[k]) > MAX_COORD)
            return step_fail(f, r, x, CB_ERR_INVALID, "coordinate %d is %g, beyond %g", k + 1, v[k],
                             MAX_COORD);
    }
    return CB_OK;
}

cb_status step_point(step_file *f, const step_rec *r, int dim, double p[3])
{
    return coords(f, r, STEP_T_CARTESIAN_POINT, dim, p);
}

cb_status step_direction(step_file *f, const step_rec *r, int dim, double d[3])
{
    cb_status st = coords(f, r, STEP_T_DIRECTION, dim, d);
    if (!st && cb_vec3_norm(d) == 0.0)
        return step_fail(f, r, NULL, CB_ERR_INVALID, "zero direction");
    return st;
}

/* Reads the referenced point or direction of attribute x (NULL when x is $ and optional). */
static cb_status ref_coords(step_file *f, const step_rec *r, const step_node *x, const char *what,
                            int dim, int direction, double v[3], int *given)
{
    if (given) {
        *given = x->kind != STEP_UNSET;
        if (!*given)
            return CB_OK;
    }
    const step_rec *q;
    cb_status st = step_get_ref(f, r, x, what, &q);
    if (st)
        return st;
    return direction ? step_direction(f, q, dim, v) : step_point(f, q, dim, v);
}

cb_status step_frame(step_file *f, const step_rec *r, int dim, cb_frame *out)
{
    step_type t = dim == 3 ? STEP_T_AXIS2_PLACEMENT_3D : STEP_T_AXIS2_PLACEMENT_2D;
    const step_node *a = simple_args(f, r, t, dim == 3 ? 4 : 3, "placement");
    if (!a)
        return f->err->status;
    double o[3], z[3] = {0, 0, 1}, x[3] = {1, 0, 0};
    int has_z = 0, has_x = 0;
    cb_status st = ref_coords(f, r, step_next(a), "location", dim, 0, o, NULL);
    a = step_next(step_next(a));
    if (!st && dim == 3) {
        st = ref_coords(f, r, a, "axis", 3, 1, z, &has_z);
        a = step_next(a);
    }
    if (!st)
        st = ref_coords(f, r, a, "ref_direction", dim, 1, x, &has_x);
    if (st)
        return st;
    /* ISO 10303-42 first_proj_axis: without a reference direction, world x unless the axis is
     * along it. */
    if (!has_x && fabs(z[0]) > 0 && z[1] == 0 && z[2] == 0) {
        x[0] = 0;
        x[1] = 1;
    }
    if ((st = cb_frame_make(out, o, z, x, f->err)))
        return step_fail_prefix(f, r, f->err);
    return CB_OK;
}

/* A placement attribute that may be 2D or 3D (a conic's position). */
static cb_status placement(step_file *f, const step_rec *r, const step_node *x, int dim,
                           cb_frame *out)
{
    const step_rec *q;
    cb_status st = step_get_ref(f, r, x, "position", &q);
    if (st)
        return st;
    return step_frame(f, q, dim, out);
}

static cb_status positive(step_file *f, const step_rec *r, const step_node *x, const char *what,
                          double *out)
{
    cb_status st = step_get_real(f, r, x, what, out);
    if (!st && !(*out > 0 && *out <= MAX_COORD))
        return step_fail(f, r, x, CB_ERR_INVALID, "%s is %g, must be positive", what, *out);
    return st;
}

/* ---------------------------------------------------------------- curves ------------------- */

static cb_status line(step_file *f, const step_rec *r, int dim, cb_topo_curve *c)
{
    const step_node *a = simple_args(f, r, STEP_T_LINE, 3, "line");
    double o[3], d[3];
    const step_rec *vec;
    cb_status st;
    if (!a)
        return f->err->status;
    if ((st = ref_coords(f, r, step_next(a), "pnt", dim, 0, o, NULL)) ||
        (st = step_get_ref(f, r, step_next(step_next(a)), "dir", &vec)))
        return st;
    const step_node *va = simple_args(f, vec, STEP_T_VECTOR, 3, "line direction");
    if (!va)
        return f->err->status;
    if ((st = ref_coords(f, vec, step_next(va), "orientation", dim, 1, d, NULL)) ||
        (st = positive(f, vec, step_next(step_next(va)), "magnitude", &c->r1)))
        return st;
    if ((st = cb_frame_make(&c->frame, o, d, NULL, f->err)))
        return step_fail_prefix(f, r, f->err);
    c->kind = CB_CURVE_LINE;
    return CB_OK;
}

static cb_status conic(step_file *f, const step_rec *r, int dim, step_type t, cb_topo_curve *c)
{
    int ellipse = t == STEP_T_ELLIPSE;
    const step_node *a = simple_args(f, r, t, ellipse ? 4 : 3, "curve");
    if (!a)
        return f->err->status;
    const step_node *x = step_next(a);
    cb_status st = placement(f, r, x, dim, &c->frame);
    x = step_next(x);
    if (!st)
        st = positive(f, r, x, ellipse ? "semi_axis_1" : "radius", &c->r1);
    if (!st && ellipse)
        st = positive(f, r, step_next(x), "semi_axis_2", &c->r2);
    if (st)
        return st;
    c->kind = ellipse ? CB_CURVE_ELLIPSE : CB_CURVE_CIRCLE;
    if (!ellipse)
        c->r2 = c->r1;
    return CB_OK;
}

/* Runs c backwards over the same points: a line or conic by turning its frame half round its
 * x axis (y and z negated: C(t) becomes the former C(-t)), a B-spline by reversal. */
static cb_status reverse_curve(step_file *f, const step_rec *r, cb_topo_curve *c)
{
    if (c->kind == CB_CURVE_NURBS) {
        cb_status st = cb_nurbs_curve_reverse(c->nurbs, c->nurbs, f->err);
        return st ? step_fail_prefix(f, r, f->err) : CB_OK;
    }
    for (int i = 0; i < 3; i++) {
        c->frame.y[i] = -c->frame.y[i];
        c->frame.z[i] = -c->frame.z[i];
    }
    return CB_OK;
}

/* One trimming select of a TRIMMED_CURVE (a set of a CARTESIAN_POINT and/or a
 * PARAMETER_VALUE): *has_pt, *has_t say which it gives. */
static cb_status trim_select(step_file *f, const step_rec *r, const step_node *set, int dim,
                             const char *what, double pt[3], int *has_pt, double *t, int *has_t)
{
    cb_status st = step_get_list(f, r, set, what, 1, 2);
    if (st)
        return st;
    *has_pt = *has_t = 0;
    const step_node *x = set + 1;
    for (int k = 0; k < set->n; k++, x = step_next(x)) {
        if (x->kind == STEP_REF) {
            const step_rec *q;
            if ((st = step_get_ref(f, r, x, what, &q)) || (st = step_point(f, q, dim, pt)))
                return st;
            *has_pt = 1;
        } else {
            if ((st = step_get_real(f, r, x, what, t)))
                return st;
            *has_t = 1;
        }
    }
    return CB_OK;
}

/* TRIMMED_CURVE(name, basis_curve, trim_1, trim_2, sense_agreement, master_representation):
 * the basis curve, reversed where the sense disagrees. Edges take their range from their
 * vertices, so the trims only bound the basis curves that need a range to have a finite exact
 * form (PARABOLA, HYPERBOLA): by the parameters where both are given (unless the master
 * representation is CARTESIAN and both points are given), else by the points. */
static cb_status trimmed(step_file *f, const step_rec *r, int dim, cb_topo_curve *c)
{
    const step_node *a = step_args(f, r, &f->parts[r->part0], 6);
    const step_rec *basis;
    cb_status st;
    int sense;
    if (!a)
        return f->err->status;
    const step_node *x = step_next(a);
    if ((st = step_get_ref(f, r, x, "basis_curve", &basis)))
        return st;
    double pt[2][3], t[2];
    int has_pt[2], has_t[2];
    x = step_next(x);
    for (int k = 0; k < 2; k++, x = step_next(x))
        if ((st = trim_select(f, r, x, dim, k ? "trim_2" : "trim_1", pt[k], &has_pt[k], &t[k],
                              &has_t[k])))
            return st;
    if ((st = step_get_bool(f, r, x, "sense_agreement", &sense)))
        return st;
    int cartesian = step_is_enum(f, step_next(x), "CARTESIAN");
    int saved_kind = f->bound_kind, saved_edge = f->bound_from_edge;
    double saved_pt[2][3], saved_t[2];
    memcpy(saved_pt, f->bound_pt, sizeof saved_pt);
    memcpy(saved_t, f->bound_t, sizeof saved_t);
    if (has_t[0] && has_t[1] && !(cartesian && has_pt[0] && has_pt[1])) {
        f->bound_kind = 2;
        f->bound_t[0] = t[0];
        f->bound_t[1] = t[1];
        f->bound_from_edge = 0;
    } else if (has_pt[0] && has_pt[1]) {
        f->bound_kind = 1;
        memcpy(f->bound_pt, pt, sizeof pt);
        f->bound_from_edge = 0;
    }
    st = step_curve(f, basis, dim, c);
    f->bound_kind = saved_kind;
    f->bound_from_edge = saved_edge;
    memcpy(f->bound_pt, saved_pt, sizeof saved_pt);
    memcpy(f->bound_t, saved_t, sizeof saved_t);
    if (!st && !sense)
        st = reverse_curve(f, r, c);
    return st;
}

/* PARABOLA(name, position, focal_dist) and HYPERBOLA(name, position, semi_axis,
 * semi_imag_axis): exact rational quadratics (brep/analytic.h) over the range in f->bound_*
 * (the parameters of the ends, found in closed form from points: t = y / 2 focal on the
 * parabola, asinh(y / b) on the hyperbola, y the coordinate along the position's y axis). */
static cb_status open_conic(step_file *f, const step_rec *r, int dim, step_type t,
                            cb_topo_curve *c)
{
    int hyp = t == STEP_T_HYPERBOLA;
    const step_node *a = step_args(f, r, &f->parts[r->part0], hyp ? 4 : 3);
    cb_frame fr;
    double p1, p2 = 0;
    if (!a)
        return f->err->status;
    const step_node *x = step_next(a);
    cb_status st = placement(f, r, x, dim, &fr);
    x = step_next(x);
    if (!st)
        st = positive(f, r, x, hyp ? "semi_axis" : "focal_dist", &p1);
    if (!st && hyp)
        st = positive(f, r, step_next(x), "semi_imag_axis", &p2);
    if (st)
        return st;
    if (!f->bound_kind)
        return step_fail(f, r, NULL, CB_ERR_UNSUPPORTED,
                         "an unbounded %s that no TRIMMED_CURVE or edge bounds",
                         hyp ? "hyperbola" : "parabola");
    double range[2];
    for (int k = 0; k < 2; k++) {
        if (f->bound_kind == 2) {
            range[k] = f->bound_t[k];
            continue;
        }
        double l[3];
        cb_frame_to_local(l, &fr, f->bound_pt[k]);
        range[k] = hyp ? asinh(l[1] / p2) : l[1] / (2 * p1);
    }
    if (f->bound_from_edge)
        f->bound_used = 1;
    if (range[0] > range[1]) {
        double s = range[0];
        range[0] = range[1];
        range[1] = s;
    }
    if (!(range[1] > range[0]))
        return step_fail(f, r, NULL, CB_ERR_INVALID, "%s bounded to the single parameter %.17g",
                         hyp ? "hyperbola" : "parabola", range[0]);
    st = hyp ? cb_nurbs_curve_hyperbola(c->nurbs, fr.o, fr.x, fr.y, p1, p2, range[0], range[1],
                                        f->err)
             : cb_nurbs_curve_parabola(c->nurbs, fr.o, fr.x, fr.y, p1, range[0], range[1], f->err);
    if (st)
        return step_fail_prefix(f, r, f->err);
    c->kind = CB_CURVE_NURBS;
    return CB_OK;
}

static cb_status curve_body(step_file *f, const step_rec *r, int dim, cb_topo_curve *c)
{
    step_type t = step_rec_type(f, r);
    if (step_part_of(f, r, STEP_T_B_SPLINE_CURVE_WITH_KNOTS) ||
        step_part_of(f, r, STEP_T_B_SPLINE_CURVE) || step_part_of(f, r, STEP_T_UNIFORM_CURVE) ||
        step_part_of(f, r, STEP_T_QUASI_UNIFORM_CURVE) || step_part_of(f, r, STEP_T_BEZIER_CURVE)) {
        cb_status st = step_bspline_curve(f, r, dim, c->nurbs);
        if (!st)
            c->kind = CB_CURVE_NURBS;
        return st;
    }
    if (r->complex)
        t = STEP_T_OTHER;
    switch (t) {
    case STEP_T_LINE: return line(f, r, dim, c);
    case STEP_T_CIRCLE:
    case STEP_T_ELLIPSE: return conic(f, r, dim, t, c);
    case STEP_T_PARABOLA:
    case STEP_T_HYPERBOLA: return open_conic(f, r, dim, t, c);
    case STEP_T_TRIMMED_CURVE: return trimmed(f, r, dim, c);
    case STEP_T_SURFACE_CURVE:
    case STEP_T_SEAM_CURVE:
    case STEP_T_INTERSECTION_CURVE: {
        const step_rec *q;
        const step_node *a = step_args(f, r, &f->parts[r->part0], 4);
        if (!a)
            return f->err->status;
        cb_status st = step_get_ref(f, r, step_next(a), "curve_3d", &q);
        return st ? st : step_curve(f, q, dim, c);
    }
    default: return step_fail(f, r, NULL, CB_ERR_UNSUPPORTED, "curve type not supported");
    }
}

cb_status step_curve(step_file *f, const step_rec *r, int dim, cb_topo_curve *out)
{
    cb_status st = step_enter(f, r);
    if (st)
        return st;
    cb_topo_curve c;
    cb_topo_curve_init(&c);
    st = curve_body(f, r, dim, &c);
    step_leave(f, r);
    if (st) {
        cb_topo_curve_clear(&c);
        return st;
    }
    cb_topo_curve_clear(out);
    *out = c;
    return CB_OK;
}

/* ---------------------------------------------------------------- surfaces ----------------- */

static cb_status elementary(step_file *f, const step_rec *r, step_type t, cb_topo_surface *s)
{
    /* A DEGENERATE_TOROIDAL_SURFACE is a torus whose major radius is below its minor one
     * (a spindle torus), its fifth argument select_outer saying which of its parts the faces
     * on it use; the parametrisation is the torus's (ISO 10303-42) and the faces' bounds pick
     * the part, so it is read as the TOROIDAL_SURFACE of its first four. */
    int torus = t == STEP_T_TOROIDAL_SURFACE || t == STEP_T_DEGENERATE_TOROIDAL_SURFACE;
    int nargs = t == STEP_T_PLANE                            ? 2
                : t == STEP_T_DEGENERATE_TOROIDAL_SURFACE    ? 5
                : t == STEP_T_CONICAL_SURFACE || torus       ? 4
                                                             : 3;
    const step_node *a = step_args(f, r, &f->parts[r->part0], nargs);
    if (!a)
        return f->err->status;
    cb_frame fr;
    double v1 = 0, v2 = 0;
    const step_node *x = step_next(a);
    cb_status st = placement(f, r, x, 3, &fr);
    x = step_next(x);
    if (!st && nargs >= 3)
        st = step_get_real(f, r, x, torus ? "major_radius" : "radius", &v1);
    if (!st && nargs >= 4)
        st = step_get_real(f, r, step_next(x),
                           t == STEP_T_CONICAL_SURFACE ? "semi_angle" : "minor_radius", &v2);
    if (st)
        return st;
    cb_analytic_surface *an = &s->analytic;
    switch (t) {
    case STEP_T_PLANE: st = cb_analytic_plane(an, &fr, f->err); break;
    case STEP_T_CYLINDRICAL_SURFACE: st = cb_analytic_cylinder(an, &fr, v1, f->err); break;
    case STEP_T_CONICAL_SURFACE:
        st = cb_analytic_cone(an, &fr, v1, v2 * f->angle_rad, f->err);
        break;
    case STEP_T_SPHERICAL_SURFACE: st = cb_analytic_sphere(an, &fr, v1, f->err); break;
    default: st = cb_analytic_torus(an, &fr, v1, v2, f->err); break;
    }
    if (st)
        return step_fail_prefix(f, r, f->err);
    s->kind = CB_SURFACE_ANALYTIC;
    return CB_OK;
}

/* SURFACE_OF_REVOLUTION and SURFACE_OF_LINEAR_EXTRUSION: the profile and the axis. */
static cb_status swept(step_file *f, const step_rec *r, step_type t, cb_topo_surface *s)
{
    const step_node *a = step_args(f, r, &f->parts[r->part0], 3);
    const step_rec *q, *ax;
    cb_status st;
    if (!a)
        return f->err->status;
    if ((st = step_get_ref(f, r, step_next(a), "swept_curve", &q)) ||
        (st = step_curve(f, q, 3, &s->profile)) ||
        (st = step_get_ref(f, r, step_next(step_next(a)),
                           t == STEP_T_SURFACE_OF_REVOLUTION ? "axis_position" : "extrusion_axis",
                           &ax)))
        return st;
    if (t == STEP_T_SURFACE_OF_LINEAR_EXTRUSION) {
        const step_node *va = simple_args(f, ax, STEP_T_VECTOR, 3, "extrusion axis");
        double d[3], m;
        if (!va)
            return f->err->status;
        if ((st = ref_coords(f, ax, step_next(va), "orientation", 3, 1, d, NULL)) ||
            (st = positive(f, ax, step_next(step_next(va)), "magnitude", &m)))
            return st;
        cb_vec3_normalize(d);
        for (int k = 0; k < 3; k++)
            s->dir[k] = m * d[k];
        s->kind = CB_SURFACE_EXTRUSION;
        return CB_OK;
    }
    const step_node *pa = simple_args(f, ax, STEP_T_AXIS1_PLACEMENT, 3, "axis of revolution");
    double o[3], z[3] = {0, 0, 1};
    int has_z;
    if (!pa)
        return f->err->status;
    if ((st = ref_coords(f, ax, step_next(pa), "location", 3, 0, o, NULL)) ||
        (st = ref_coords(f, ax, step_next(step_next(pa)), "axis", 3, 1, z, &has_z)))
        return st;
    if ((st = cb_frame_make(&s->frame, o, z, NULL, f->err)))
        return step_fail_prefix(f, ax, f->err);
    s->kind = CB_SURFACE_REVOLUTION;
    return CB_OK;
}

static cb_status surface_body(step_file *f, const step_rec *r, cb_topo_surface *s)
{
    if (step_part_of(f, r, STEP_T_B_SPLINE_SURFACE_WITH_KNOTS) ||
        step_part_of(f, r, STEP_T_B_SPLINE_SURFACE) ||
        step_part_of(f, r, STEP_T_UNIFORM_SURFACE) ||
        step_part_of(f, r, STEP_T_QUASI_UNIFORM_SURFACE) ||
        step_part_of(f, r, STEP_T_BEZIER_SURFACE)) {
        cb_status st = step_bspline_surface(f, r, s->nurbs);
        if (!st)
            s->kind = CB_SURFACE_NURBS;
        return st;
    }
    step_type t = r->complex ? STEP_T_OTHER : step_rec_type(f, r);
    switch (t) {
    case STEP_T_PLANE:
    case STEP_T_CYLINDRICAL_SURFACE:
    case STEP_T_CONICAL_SURFACE:
    case STEP_T_SPHERICAL_SURFACE:
    case STEP_T_TOROIDAL_SURFACE:
    case STEP_T_DEGENERATE_TOROIDAL_SURFACE: return elementary(f, r, t, s);
    case STEP_T_SURFACE_OF_REVOLUTION:
    case STEP_T_SURFACE_OF_LINEAR_EXTRUSION: return swept(f, r, t, s);
    default: return step_fail(f, r, NULL, CB_ERR_UNSUPPORTED, "surface type not supported");
    }
}

cb_status step_surface(step_file *f, const step_rec *r, cb_topo_surface *out)
{
    cb_status st = step_enter(f, r);
    if (st)
        return st;
    cb_topo_surface s;
    cb_topo_surface_init(&s);
    st = surface_body(f, r, &s);
    step_leave(f, r);
    if (st) {
        cb_topo_surface_clear(&s);
        return st;
    }
    cb_topo_surface_clear(out);
    *out = s;
    return CB_OK;
}
