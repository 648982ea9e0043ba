/* Cardan-joint parts (models.h): parameters, closed-form volumes, the named scenarios. */
#include <math.h>
#include <string.h>

#include "brep/geom.h"
#include "models/cardan_internal.h"

static const double pi = 3.14159265358979323846;

void cb_cardan_params_default(cb_cardan_params *p, cb_cardan_kind kind)
{
    memset(p, 0, sizeof *p);
    p->kind = kind;
    p->cross = (cb_cross_shape){1, 0.375, 3};
    p->yoke = (cb_yoke_shape){2.5, 1.5, 1, 4, 4, 0.375, 3, 1, 2, 0.5};
    p->pose.axis[2] = 1;
}

/* Fails unless lo < x < hi (a bound given as NAN is not checked). */
static cb_status in_range(double x, double lo, double hi, const char *part, const char *name,
                          cb_error *err)
{
    if (!isfinite(x) || (!isnan(lo) && !(x > lo)) || (!isnan(hi) && !(x < hi)))
        return cb_error_set(err, CB_ERR_INVALID, "%s: %s %.17g must be finite and in (%g, %g)",
                            part, name, x, isnan(lo) ? -HUGE_VAL : lo, isnan(hi) ? HUGE_VAL : hi);
    return CB_OK;
}

cb_status cb_cardan_params_check(const cb_cardan_params *p, cb_error *err)
{
    cb_status st = CB_OK;
    const char *part = p->kind == CB_CARDAN_CROSS ? "cross" : "yoke";
    if (p->kind == CB_CARDAN_CROSS) {
        const cb_cross_shape *c = &p->cross;
        if (!st)
            st = in_range(c->half_size, 0, NAN, part, "half size a", err);
        if (!st)
            st = in_range(c->arm_radius, 0, c->half_size, part, "arm radius r", err);
        if (!st)
            st = in_range(c->arm_reach, c->half_size, NAN, part, "arm reach L", err);
    } else if (p->kind == CB_CARDAN_YOKE) {
        const cb_yoke_shape *y = &p->yoke;
        if (!st)
            st = in_range(y->half_span, 0, NAN, part, "half span B", err);
        if (!st)
            st = in_range(y->gap, 0, y->half_span, part, "gap g", err);
        if (!st)
            st = in_range(y->base_height, 0, NAN, part, "base height t", err);
        if (!st)
            st = in_range(y->height, y->base_height, NAN, part, "height H", err);
        if (!st && !(isfinite(y->fillet_radius) && y->fillet_radius >= 0 &&
                     y->fillet_radius < y->gap &&
                     y->base_height + y->fillet_radius < y->height))
            st = cb_error_set(err, CB_ERR_INVALID,
                              "%s: fillet radius f %.17g must be finite, >= 0, below the gap g "
                              "and below H - t",
                              part, y->fillet_radius);
        if (!st)
            st = in_range(y->width, 0, NAN, part, "width w", err);
        if (!st)
            st = in_range(y->bore_radius, 0, 0.5 * y->width, part, "bore radius rb", err);
        if (!st)
            st = in_range(y->bore_height, y->base_height + y->fillet_radius + y->bore_radius,
                          y->height - y->bore_radius, part, "bore height hb", err);
        if (!st)
            st = in_range(y->shaft_radius, 0, fmin(y->half_span, 0.5 * y->width), part,
                          "shaft radius rs", err);
        if (!st)
            st = in_range(y->shaft_length, 0, NAN, part, "shaft length ls", err);
    } else {
        return cb_error_set(err, CB_ERR_INVALID, "cardan: unknown part kind %d", (int)p->kind);
    }
    if (st)
        return st;
    const cb_model_pose *q = &p->pose;
    for (int i = 0; i < 3; i++)
        if (!isfinite(q->axis[i]) || !isfinite(q->translate[i]))
            return cb_error_set(err, CB_ERR_INVALID, "%s: pose axis or translation not finite",
                                part);
    if (!isfinite(q->angle_deg))
        return cb_error_set(err, CB_ERR_INVALID, "%s: pose angle not finite", part);
    if (q->angle_deg != 0 && !(cb_vec3_norm(q->axis) > 0))
        return cb_error_set(err, CB_ERR_INVALID, "%s: pose rotation axis is zero", part);
    if (!isfinite(p->tol))
        return cb_error_set(err, CB_ERR_INVALID, "%s: tolerance %g is not finite", part, p->tol);
    return CB_OK;
}

cb_status cb_model_cardan(cb_topo_body **out, const cb_cardan_params *p, cb_error *err)
{
    *out = NULL;
    cb_status st = cb_cardan_params_check(p, err);
    if (st)
        return st;
    return p->kind == CB_CARDAN_CROSS ? cb_cardan_build_cross(out, p, err)
                                      : cb_cardan_build_yoke(out, p, err);
}

static double cross_volume(const cb_cross_shape *c)
{
    double a = c->half_size, r = c->arm_radius;
    return 8 * a * a * a + 4 * pi * r * r * (c->arm_reach - a);
}

static double yoke_volume(const cb_yoke_shape *y)
{
    double s = y->half_span - y->gap;
    double f = y->fillet_radius;
    double profile = 2 * y->half_span * y->base_height + 2 * s * (y->height - y->base_height) +
                     2 * (1 - pi / 4) * f * f;
    return y->width * profile + pi * y->shaft_radius * y->shaft_radius * y->shaft_length -
           2 * pi * y->bore_radius * y->bore_radius * s;
}

cb_status cb_model_cardan_volume(double *volume, const cb_cardan_params *p, cb_error *err)
{
    cb_status st = cb_cardan_params_check(p, err);
    if (st)
        return st;
    *volume = p->kind == CB_CARDAN_CROSS ? cross_volume(&p->cross) : yoke_volume(&p->yoke);
    return CB_OK;
}

/* ---------------------------------------------------------------- scenarios ---------------- */

enum {
    CROSS_IN_YOKE,
    CROSS_ON_BASE,
    CROSS_INTO_BASE,
    CROSS_THROUGH_YOKE,
    TWO_CROSSES,
    CROSSES_STACKED,
    N_SCENARIOS
};

static const char *const scenario_name[N_SCENARIOS] = {
    "cross_in_yoke", "cross_on_base", "cross_into_base", "cross_through_yoke", "two_crosses",
    "crosses_stacked"};

static const char *const scenario_contact[N_SCENARIOS] = {
    "the cross's x arms coaxial in the yoke's bores with equal radius: coincident cylindrical "
    "faces, A n B empty",
    "the cross's -y arm lying on the yoke base's top plane: a cylinder tangent to a plane along "
    "a line, A n B empty",
    "the cross's -y arm sunk 1/4 into the yoke base: a cylinder cutting a plane along two "
    "parallel lines, its cap inside the base",
    "the cross on the bore axis turned 60 degrees about it: the -y arm enters the base "
    "obliquely (an ellipse), the x arms stay coaxial in the bores",
    "two crosses at the origin, B turned 45 degrees about z: cube against cube, each cube "
    "against the other's arms",
    "B raised by 2 r: the x and y arms of A and B tangent along lines (parallel cylinders), the "
    "cube faces at x = +-a and y = +-a coplanar and overlapping, their arm circles tangent"};

static const char *const scenario_closed_form[N_SCENARIOS] = {
    "A n B = 0",
    "A n B = 0",
    ("A n B = (r^2 acos((r - d)/r) - (r - d) sqrt(r^2 - (r - d)^2)) (w/2 - y_c + L), d = 1/4, "
     "y_c = 7/2"),
    "A n B = pi r^2 (L - (hb - t) / sin 60deg)",
    "A n B = 16 a^3 (sqrt 2 - 1) + 8 (a (sqrt 2 - 1) pi r^2 - 4 r^3 / 3)",
    "A n B = 4 a^2 (2 a - 2 r)"};

/* Depth of the cross_into_base arm in the base, and the y of the crosses on the base. */
static const double SINK = 0.25, BASE_Y = 3.5;

int cb_cardan_scenario_count(void) { return N_SCENARIOS; }

cb_status cb_cardan_scenario_get(cb_cardan_scenario *s, int k, cb_error *err)
{
    if (k < 0 || k >= N_SCENARIOS)
        return cb_error_set(err, CB_ERR_INVALID, "cardan: scenario %d out of range [0, %d)", k,
                            N_SCENARIOS);
    s->name = scenario_name[k];
    s->contact = scenario_contact[k];
    s->closed_form = scenario_closed_form[k];
    int crosses = k == TWO_CROSSES || k == CROSSES_STACKED;
    cb_cardan_params_default(&s->a, crosses ? CB_CARDAN_CROSS : CB_CARDAN_YOKE);
    cb_cardan_params_default(&s->b, CB_CARDAN_CROSS);
    const cb_yoke_shape *y = &s->a.yoke;
    const double r = s->b.cross.arm_radius;
    cb_model_pose *q = &s->b.pose;
    switch (k) {
    case CROSS_IN_YOKE: q->translate[2] = y->bore_height; break;
    case CROSS_ON_BASE:
    case CROSS_INTO_BASE:
        q->translate[1] = BASE_Y;
        q->translate[2] = y->base_height + r - (k == CROSS_INTO_BASE ? SINK : 0);
        break;
    case CROSS_THROUGH_YOKE:
        q->axis[0] = 1;
        q->axis[2] = 0;
        q->angle_deg = 60;
        q->translate[2] = y->bore_height;
        break;
    case TWO_CROSSES: q->angle_deg = 45; break;
    default: q->translate[2] = 2 * r; break;
    }
    return CB_OK;
}

cb_status cb_cardan_scenario_find(cb_cardan_scenario *s, const char *name, cb_error *err)
{
    for (int k = 0; name && k < N_SCENARIOS; k++)
        if (!strcmp(name, scenario_name[k]))
            return cb_cardan_scenario_get(s, k, err);
    return cb_error_set(err, CB_ERR_INVALID,
                        "cardan: unknown scenario '%s' (known: cross_in_yoke, cross_on_base, "
                        "cross_into_base, cross_through_yoke, two_crosses, crosses_stacked)",
                        name ? name : "(null)");
}

static int same_part(const cb_cardan_params *x, const cb_cardan_params *y)
{
    if (x->kind != y->kind || memcmp(&x->pose, &y->pose, sizeof x->pose))
        return 0;
    return x->kind == CB_CARDAN_CROSS ? !memcmp(&x->cross, &y->cross, sizeof x->cross)
                                      : !memcmp(&x->yoke, &y->yoke, sizeof x->yoke);
}

/* Volume of A n B by the closed forms of models/README.md. */
static double inter_volume(int k, const cb_cardan_scenario *s)
{
    const cb_yoke_shape *y = &s->a.yoke;
    const double a = s->b.cross.half_size, r = s->b.cross.arm_radius, L = s->b.cross.arm_reach;
    switch (k) {
    case CROSS_INTO_BASE: {
        /* The circular segment below the chord at depth SINK, times the arm's run over the
         * base. */
        double h = r - SINK;
        double segment = r * r * acos(h / r) - h * sqrt(r * r - h * h);
        return segment * (0.5 * y->width - (BASE_Y - L));
    }
    case CROSS_THROUGH_YOKE: {
        /* A cylinder between a cross-section and an oblique plane holds pi r^2 times its
         * axial length at the axis. */
        double theta = s->b.pose.angle_deg * pi / 180;
        return pi * r * r * (L - (y->bore_height - y->base_height) / sin(theta));
    }
    case TWO_CROSSES: {
        /* The cubes meet in a regular octagonal prism; each arm runs c - |y| into the other
         * cube (|x| + |y| <= a sqrt 2), c = a (sqrt 2 - 1), over its disc. */
        double c = a * (sqrt(2.0) - 1);
        return 2 * a * 8 * a * a * (sqrt(2.0) - 1) + 8 * (c * pi * r * r - 4 * r * r * r / 3);
    }
    case CROSSES_STACKED: return 4 * a * a * (2 * a - 2 * r);
    default: return 0;
    }
}

cb_status cb_cardan_scenario_volumes(cb_cardan_volumes *v, const cb_cardan_scenario *s,
                                     cb_error *err)
{
    cb_cardan_scenario ref;
    cb_status st = cb_cardan_scenario_find(&ref, s->name, err);
    if (st)
        return st;
    if (!same_part(&s->a, &ref.a) || !same_part(&s->b, &ref.b))
        return cb_error_set(err, CB_ERR_INVALID,
                            "cardan: scenario %s: parts differ from the ones its volumes were "
                            "derived for",
                            s->name);
    int k = 0;
    while (strcmp(scenario_name[k], s->name))
        k++;
    if ((st = cb_model_cardan_volume(&v->a, &s->a, err)) ||
        (st = cb_model_cardan_volume(&v->b, &s->b, err)))
        return st;
    v->a_inter_b = inter_volume(k, s);
    v->a_union_b = v->a + v->b - v->a_inter_b;
    v->a_minus_b = v->a - v->a_inter_b;
    v->b_minus_a = v->b - v->a_inter_b;
    return CB_OK;
}
