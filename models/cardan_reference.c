/* The reference table of the Cardan-joint parts and scenarios as JSON (models.h). */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>

#include "models/models.h"

typedef struct {
    char *s;
    size_t n, cap;
    int failed;
} text;

static void put(text *t, const char *fmt, ...)
{
    if (t->failed)
        return;
    va_list ap;
    va_start(ap, fmt);
    int need = vsnprintf(NULL, 0, fmt, ap);
    va_end(ap);
    if (t->n + (size_t)need + 1 > t->cap) {
        size_t cap = 2 * (t->n + (size_t)need + 1);
        char *s = realloc(t->s, cap);
        if (!s) {
            t->failed = 1;
            return;
        }
        t->s = s;
        t->cap = cap;
    }
    va_start(ap, fmt);
    vsnprintf(t->s + t->n, t->cap - t->n, fmt, ap);
    va_end(ap);
    t->n += (size_t)need;
}

static const char *part_name(const cb_cardan_params *p)
{
    return p->kind == CB_CARDAN_CROSS ? "cross" : "yoke";
}

static void put_pose(text *t, const char *tag, const cb_cardan_params *p)
{
    const cb_model_pose *q = &p->pose;
    put(t,
        "      \"%s\": {\"part\": \"%s\", \"axis\": [%.17g, %.17g, %.17g], \"angle_deg\": %.17g, "
        "\"translate\": [%.17g, %.17g, %.17g]},\n",
        tag, part_name(p), q->axis[0], q->axis[1], q->axis[2], q->angle_deg, q->translate[0],
        q->translate[1], q->translate[2]);
}

/* The bracket (default shape) and its scenarios: B a solid cylinder that only touches it. */
static void put_bracket(text *t)
{
    cb_bracket_params p;
    cb_bracket_params_default(&p);
    const cb_bracket_shape *b = &p.shape;
    double va = cb_bracket_volume(b);
    put(t,
        "  \"bracket\": {\"length\": %.17g, \"height\": %.17g, \"thickness\": %.17g, \"width\": "
        "%.17g, \"fillet\": %.17g, \"hole_radius\": %.17g, \"hole_x\": %.17g, \"hole_z\": %.17g, "
        "\"faces\": 11, \"edges\": 27, \"vertices\": 18, \"volume\": %.17g},\n"
        "  \"bracket_scenarios\": [\n",
        b->length, b->height, b->thickness, b->width, b->fillet, b->hole_radius, b->hole_x,
        b->hole_z, va);
    int n = cb_bracket_scenario_count();
    for (int k = 0; k < n; k++) {
        cb_bracket_cylinder c;
        const char *name = cb_bracket_scenario_cylinder(&c, k);
        double vb = cb_bracket_cylinder_volume(&c);
        put(t,
            "    {\"name\": \"%s\", \"b_cylinder\": {\"origin\": [%.17g, %.17g, %.17g], "
            "\"axis\": [%.17g, %.17g, %.17g], \"radius\": %.17g, \"length\": %.17g},\n"
            "     \"volume_a\": %.17g, \"volume_b\": %.17g, \"volume_a_union_b\": %.17g, "
            "\"volume_a_inter_b\": 0, \"volume_a_minus_b\": %.17g, \"volume_b_minus_a\": %.17g}%s\n",
            name, c.origin[0], c.origin[1], c.origin[2], c.axis[0], c.axis[1], c.axis[2],
            c.radius, c.length, va, vb, va + vb, va, vb, k + 1 < n ? "," : "");
    }
    put(t, "  ],\n");
}

/* The two hummingbirds: B's pose and the stored estimate (one standard deviation each). */
static void put_birds(text *t)
{
    cb_hummingbird_params a, b;
    cb_hummingbird_pair(&a, &b);
    const cb_overlap_estimate *e = &cb_hummingbird_pair_reference;
    put(t,
        "  \"hummingbirds\": {\"b_translate\": [%.17g, %.17g, %.17g], \"grid\": %d, "
        "\"volume_a\": %.17g, \"sigma_a\": %.3g, \"volume_b\": %.17g, \"sigma_b\": %.3g, "
        "\"volume_a_inter_b\": %.17g, \"sigma_a_inter_b\": %.3g}\n",
        b.translate[0], b.translate[1], b.translate[2], CB_HUMMINGBIRD_PAIR_GRID, e->volume_a,
        e->sigma_a, e->volume_b, e->sigma_b, e->volume_ab, e->sigma_ab);
}

cb_status cb_cardan_reference_json(char **out, cb_error *err)
{
    *out = NULL;
    text t = {NULL, 0, 0, 0};
    cb_cardan_params c, y;
    double vc, vy;
    cb_cardan_params_default(&c, CB_CARDAN_CROSS);
    cb_cardan_params_default(&y, CB_CARDAN_YOKE);
    cb_status st = cb_model_cardan_volume(&vc, &c, err);
    if (!st)
        st = cb_model_cardan_volume(&vy, &y, err);
    if (st)
        return st;
    const cb_cross_shape *cs = &c.cross;
    const cb_yoke_shape *ys = &y.yoke;
    put(&t, "{\n  \"about\": \"Shipped models and Boolean scenarios: reference volumes from "
            "closed forms, and for the two hummingbirds from an estimate by vertical lines "
            "(models/README.md), model units\",\n  \"parts\": {\n");
    put(&t,
        "    \"cross\": {\"half_size\": %.17g, \"arm_radius\": %.17g, \"arm_reach\": %.17g, "
        "\"faces\": 14, \"edges\": 24, \"vertices\": 16, \"volume\": %.17g},\n",
        cs->half_size, cs->arm_radius, cs->arm_reach, vc);
    put(&t,
        "    \"yoke\": {\"half_span\": %.17g, \"gap\": %.17g, \"base_height\": %.17g, \"height\": "
        "%.17g, \"width\": %.17g, \"bore_radius\": %.17g, \"bore_height\": %.17g, "
        "\"shaft_radius\": %.17g, \"shaft_length\": %.17g, \"fillet_radius\": %.17g, \"faces\": "
        "%d, \"edges\": %d, \"vertices\": %d, \"volume\": %.17g}\n  },\n  \"scenarios\": [\n",
        ys->half_span, ys->gap, ys->base_height, ys->height, ys->width, ys->bore_radius,
        ys->bore_height, ys->shaft_radius, ys->shaft_length, ys->fillet_radius,
        ys->fillet_radius > 0 ? 16 : 14, ys->fillet_radius > 0 ? 39 : 33,
        ys->fillet_radius > 0 ? 26 : 22, vy);
    int n = cb_cardan_scenario_count();
    for (int k = 0; k < n && !st; k++) {
        cb_cardan_scenario s;
        cb_cardan_volumes v;
        st = cb_cardan_scenario_get(&s, k, err);
        if (!st)
            st = cb_cardan_scenario_volumes(&v, &s, err);
        if (st)
            break;
        put(&t, "    {\n      \"name\": \"%s\",\n      \"contact\": \"%s\",\n", s.name, s.contact);
        put(&t, "      \"closed_form\": \"%s\",\n", s.closed_form);
        put_pose(&t, "a", &s.a);
        put_pose(&t, "b", &s.b);
        put(&t,
            "      \"volume_a\": %.17g,\n      \"volume_b\": %.17g,\n      \"volume_a_union_b\": "
            "%.17g,\n      \"volume_a_inter_b\": %.17g,\n      \"volume_a_minus_b\": %.17g,\n"
            "      \"volume_b_minus_a\": %.17g\n    }%s\n",
            v.a, v.b, v.a_union_b, v.a_inter_b, v.a_minus_b, v.b_minus_a, k + 1 < n ? "," : "");
    }
    put(&t, "  ],\n");
    put_bracket(&t);
    put_birds(&t);
    put(&t, "}\n");
    if (!st && t.failed)
        st = cb_error_set(err, CB_ERR_NOMEM, "cardan: out of memory writing the reference table");
    if (st) {
        free(t.s);
        return st;
    }
    *out = t.s;
    return CB_OK;
}
