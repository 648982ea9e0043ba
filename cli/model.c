/* colibri model: build one of the shipped models and write it as STEP. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brep/geom.h"
#include "brep/topo.h"
#include "cli/commands.h"
#include "io/step_write.h"
#include "models/models.h"

static const char MODEL_USAGE[] =
    "usage: colibri model NAME -o FILE.step [options]\n"
    "       colibri model hummingbird -o FILE.step [--scale S] [--rotate AX AY AZ DEG]\n"
    "                         [--translate X Y Z] [--wing-angle DEG]\n"
    "       colibri model cardan cross|yoke -o FILE.step [--nurbs] [--rotate AX AY AZ DEG]\n"
    "                         [--translate X Y Z] [--fillet F]\n"
    "       colibri model cardan SCENARIO -o A.step --out-b B.step [--nurbs]\n"
    "       colibri model hummingbird-pair -o A.step --out-b B.step\n"
    "       colibri model hummingbird-pair --estimate N [--threads T]\n"
    "       colibri model cardan --list\n"
    "       colibri model bracket -o FILE.step [--nurbs] [--rotate AX AY AZ DEG]\n"
    "                         [--translate X Y Z]\n"
    "       colibri model --reference\n"
    "\n"
    "Builds a model, checks it with the topology validator and writes it as one closed solid in\n"
    "a STEP AP214 file. Prints its counts and the validation.\n"
    "\n"
    "models:\n"
    "  hummingbird  a freeform bird (body, head and beak, two wings, tail) of 312 bicubic\n"
    "               B-spline faces of 6 x 6 control points, as in Yang, Jia, Yan (ACM TOG 2023)\n"
    "               Fig. 12; about 2.9 long and 2.9 across the wings at scale 1, x forward,\n"
    "               y to the left wing, z up\n"
    "  bracket      an L-shaped bracket, 4 long, 3 high, 2 wide, 1/2 thick, its inner corner\n"
    "               blended by a fillet of radius 1/2, a hole of radius 0.3 through each leg;\n"
    "               11 faces (the bracket scenarios of colibri demo put a bolt in a hole and a\n"
    "               rod in the corner)\n"
    "  hummingbird-pair  the two birds of the Boolean scenario (Fig. 12): A as built, B moved\n"
    "               by (0.25, 0.08, 0.05); --estimate N prints V(A), V(B) and V(A n B)\n"
    "               estimated by N x N vertical lines through both (no Boolean involved;\n"
    "               models/README.md), each with its standard deviation\n"
    "  cardan       the parts of a Cardan (universal) joint, as in the paper's Fig. 13, of\n"
    "               planes and circular cylinders (models/README.md):\n"
    "    cross      the cube [-1, 1]^3 with four arms of radius 3/8 along +-x and +-y reaching\n"
    "               3 from the centre; 14 faces\n"
    "    yoke       a U-shaped fork, 5 wide (x), 4 deep (y), 4 high (z), its inner corners\n"
    "               rounded (radius 1/2), a bore of radius 3/8 through each arm along x at\n"
    "               height 3, and a shaft of radius 1 down to z = -2; 16 faces (14 with\n"
    "               --fillet 0)\n"
    "    SCENARIO   two posed parts A and B of a named Boolean scenario, written to two files;\n"
    "               prints the six reference volumes (A, B, A u B, A n B, A - B, B - A) from\n"
    "               closed forms. Scenarios: cross_in_yoke, cross_on_base, cross_into_base,\n"
    "               cross_through_yoke, two_crosses, crosses_stacked (--list says what each\n"
    "               one tests)\n"
    "\n"
    "options (the pose is p -> R (S p) + T: scale, then rotation, then translation):\n"
    "  -o FILE              the STEP file to write (required; a scenario's part A)\n"
    "  --out-b FILE         cardan scenario: the STEP file for part B (required there)\n"
    "  --scale S            hummingbird: size factor, S > 0 (default 1)\n"
    "  --rotate AX AY AZ DEG  rotation by DEG degrees about the axis (AX, AY, AZ) through the\n"
    "                       origin (default none)\n"
    "  --translate X Y Z    translation (default none)\n"
    "  --wing-angle DEG     hummingbird: wings raised DEG degrees, in [-30, 50] (default 20)\n"
    "  --nurbs              cardan: every face an exact rational B-spline (default: analytic\n"
    "                       planes and cylinders)\n"
    "  --fillet F           cardan yoke: radius of the inner fillets, 0 <= F < 3/2 (default\n"
    "                       1/2; 0: sharp corners)\n"
    "  --list               cardan: list the scenarios with their contacts\n"
    "  --estimate N         hummingbird-pair: the volume estimate on an N x N grid (N even)\n"
    "  --threads T          threads for --estimate (default 0: all hardware threads)\n"
    "  --reference          print the reference table of the shipped models and scenarios as JSON\n"
    "                       (the text of models/reference.json)\n"
    "\n"
    "Cardan parts also print their volume from its closed form (model units^3). A scenario's\n"
    "parts keep the default shapes and poses its closed forms were derived for: no --rotate,\n"
    "--translate or --fillet there.\n"
    "\n"
    "Exit status: 0 the model was written and is valid, 1 it could not be built or fails\n"
    "validation, 2 bad usage (unknown model, part or scenario, bad numbers, an output file that\n"
    "cannot be written).\n"
    "\n"
    "examples:\n"
    "  the two overlapping birds of the Boolean scenario:\n"
    "    colibri model hummingbird -o bird_a.step\n"
    "    colibri model hummingbird -o bird_b.step --rotate 0.2 0.3 1 40 --translate 0.4 0.25 "
    "0.15 --wing-angle 5\n"
    "  a yoke with B-spline faces, turned and moved, and a sharp-cornered one:\n"
    "    colibri model cardan yoke -o yoke.step --nurbs --rotate 0 0 1 30 --translate 0 0 1\n"
    "    colibri model cardan yoke -o sharp.step --fillet 0\n"
    "  the cross tilted into the yoke, and every scenario:\n"
    "    colibri model cardan cross_through_yoke -o yoke.step --out-b cross.step\n"
    "    colibri model cardan --list\n";

/* Options as given; which ones appear is kept to refuse those that do not apply. */
typedef struct {
    const char *name, *part, *path, *path_b;
    double scale, wing_angle_deg, fillet;
    cb_model_pose pose;
    int has_scale, has_wing, has_rotate, has_translate, has_fillet, nurbs, list, reference;
    int estimate, threads;
} model_args;

/* Parses argv[k + 1 .. k + n] as finite numbers into v; 0 on success. */
static int parse_numbers(double *v, int n, int argc, char **argv, int k)
{
    if (k + n >= argc)
        return -1;
    for (int i = 0; i < n; i++) {
        char *end;
        v[i] = strtod(argv[k + 1 + i], &end);
        if (end == argv[k + 1 + i] || *end || !isfinite(v[i]))
            return -1;
    }
    return 0;
}

/* Fills a from argv; 0 on success, else the exit status (usage printed). */
static int parse_args(model_args *a, int argc, char **argv)
{
    memset(a, 0, sizeof *a);
    a->pose.axis[2] = 1;
    for (int k = 1; k < argc; k++) {
        const char *s = argv[k];
        int bad = 0;
        if (!strcmp(s, "-o") && k + 1 < argc) {
            a->path = argv[++k];
        } else if (!strcmp(s, "--out-b") && k + 1 < argc) {
            a->path_b = argv[++k];
        } else if (!strcmp(s, "--scale")) {
            bad = parse_numbers(&a->scale, 1, argc, argv, k) || !(a->scale > 0);
            a->has_scale = 1;
            k += 1;
        } else if (!strcmp(s, "--rotate")) {
            double v[4];
            bad = parse_numbers(v, 4, argc, argv, k);
            if (!bad) {
                memcpy(a->pose.axis, v, sizeof a->pose.axis);
                a->pose.angle_deg = v[3];
                bad = v[3] != 0 && !(cb_vec3_norm(a->pose.axis) > 0);
            }
            a->has_rotate = 1;
            k += 4;
        } else if (!strcmp(s, "--translate")) {
            bad = parse_numbers(a->pose.translate, 3, argc, argv, k);
            a->has_translate = 1;
            k += 3;
        } else if (!strcmp(s, "--wing-angle")) {
            bad = parse_numbers(&a->wing_angle_deg, 1, argc, argv, k);
            a->has_wing = 1;
            k += 1;
        } else if (!strcmp(s, "--fillet")) {
            bad = parse_numbers(&a->fillet, 1, argc, argv, k);
            a->has_fillet = 1;
            k += 1;
        } else if (!strcmp(s, "--nurbs")) {
            a->nurbs = 1;
        } else if (!strcmp(s, "--list")) {
            a->list = 1;
        } else if (!strcmp(s, "--reference")) {
            a->reference = 1;
        } else if (!strcmp(s, "--estimate")) {
            double v;
            bad = parse_numbers(&v, 1, argc, argv, k) || v != floor(v) || v < 2 || v > 20000 ||
                  fmod(v, 2) != 0;
            a->estimate = bad ? 0 : (int)v;
            k += 1;
        } else if (!strcmp(s, "--threads") && k + 1 < argc) {
            if (cb_cli_threads_arg(&a->threads, argv[++k]))
                return 2;
        } else if (s[0] == '-' || a->part) {
            fputs(MODEL_USAGE, stderr);
            return 2;
        } else if (a->name) {
            a->part = s;
        } else {
            a->name = s;
        }
        if (bad) {
            fprintf(stderr, "colibri: %s: bad or missing values (see colibri model --help)\n", s);
            return 2;
        }
    }
    return 0;
}

/* Refuses an option given for a model it does not apply to; 0 if it was not given. */
static int refuse(int given, const char *option, const char *where)
{
    if (!given)
        return 0;
    fprintf(stderr, "colibri: %s does not apply to %s (see colibri model --help)\n", option,
            where);
    return 2;
}

/* Validates b, writes it to path and prints what it is (label: "hummingbird", "cardan yoke",
 * ...; faces: what the faces are); exit status as cb_cli_model. */
static int validate_and_write(const char *path, cb_topo_body *b, const char *label,
                              const char *step_name, const char *faces)
{
    cb_error err;
    cb_error_clear(&err);
    cb_topo_report r;
    cb_topo_report_init(&r);
    int code = 0;
    cb_status st;
    if ((st = cb_topo_validate(&r, b, b->tol, 9, &err))) {
        fprintf(stderr, "colibri: %s\n", err.msg);
        code = 1;
    } else if ((st = cb_step_write(b, path, step_name, &err))) {
        fprintf(stderr, "colibri: %s\n", err.msg);
        code = st == CB_ERR_IO ? 2 : 1;
    } else {
        printf("%s: %s: 1 solid, %d faces, %d edges, %d vertices (%s)\n", path, label,
               b->n_faces, b->n_edges, b->n_vertices, faces);
        printf("largest deviations: edge-surface %.3g, loop gap %.3g, edge-vertex %.3g\n",
               r.max_edge_surface, r.max_loop_gap, r.max_edge_vertex);
        if (!r.n)
            printf("validation (tolerance %g): valid\n", b->tol);
        else
            printf("validation (tolerance %g): %d problems, first: %s\n", b->tol,
                   r.n + r.dropped, r.items[0]);
        code = r.n ? 1 : 0;
    }
    cb_topo_report_clear(&r);
    return code;
}

/* Exit status of a failed generator: 2 for parameters out of range, else 1. */
static int build_failed(cb_status st, const cb_error *err)
{
    fprintf(stderr, "colibri: %s\n", err->msg);
    return st == CB_ERR_INVALID ? 2 : 1;
}

static int write_hummingbird(const model_args *a)
{
    cb_hummingbird_params p;
    cb_hummingbird_params_default(&p);
    if (a->has_scale)
        p.scale = a->scale;
    if (a->has_wing)
        p.wing_angle_deg = a->wing_angle_deg;
    memcpy(p.axis, a->pose.axis, sizeof p.axis);
    p.angle_deg = a->pose.angle_deg;
    memcpy(p.translate, a->pose.translate, sizeof p.translate);
    cb_error err;
    cb_error_clear(&err);
    cb_topo_body *b;
    cb_status st = cb_model_hummingbird(&b, &p, &err);
    if (st)
        return build_failed(st, &err);
    int code = validate_and_write(a->path, b, "hummingbird", "hummingbird",
                                  "bicubic B-splines, 6 x 6 control points");
    cb_topo_body_free(b);
    return code;
}

/* The two birds of cb_hummingbird_pair: written to a->path and a->path_b, and/or their
 * volume estimate printed. */
static int model_pair(const model_args *a)
{
    if ((!a->path) != (!a->path_b) || (!a->path && !a->estimate)) {
        fputs(MODEL_USAGE, stderr);
        return 2;
    }
    cb_hummingbird_params p[2];
    cb_hummingbird_pair(p, p + 1);
    cb_error err;
    cb_error_clear(&err);
    cb_topo_body *b[2] = {NULL, NULL};
    cb_status st = CB_OK;
    for (int k = 0; k < 2 && !st; k++)
        st = cb_model_hummingbird(b + k, p + k, &err);
    int code = st ? build_failed(st, &err) : 0;
    for (int k = 0; k < 2 && a->path && !code; k++)
        code = validate_and_write(k ? a->path_b : a->path, b[k],
                                  k ? "hummingbird (B)" : "hummingbird (A)", "hummingbird",
                                  "bicubic B-splines, 6 x 6 control points");
    for (int k = 0; k < 2 && a->estimate && !code && !st; k++)
        st = cb_topo_compute_pcurves(b[k], b[k]->tol, &err);
    cb_overlap_estimate e;
    if (a->estimate && !code && !st)
        st = cb_model_overlap_estimate(&e, b[0], b[1], a->estimate, a->threads, &err);
    if (st && !code) {
        fprintf(stderr, "colibri: %s\n", err.msg);
        code = 1;
    }
    if (a->estimate && !code) {
        printf("estimate on %d x %d vertical lines (%ld followed, %ld drawn again):\n",
               a->estimate, a->estimate, e.lines, e.retries);
        printf("V(A)     %.10g +- %.3g (one standard deviation)\n", e.volume_a, e.sigma_a);
        printf("V(B)     %.10g +- %.3g\n", e.volume_b, e.sigma_b);
        printf("V(A n B) %.10g +- %.3g\n", e.volume_ab, e.sigma_ab);
    }
    cb_topo_body_free(b[0]);
    cb_topo_body_free(b[1]);
    return code;
}

/* The bracket in the pose asked for, validated and written, with its closed-form volume. */
static int write_bracket(const model_args *a)
{
    cb_bracket_params p;
    cb_bracket_params_default(&p);
    p.as_nurbs = a->nurbs;
    p.pose = a->pose;
    cb_error err;
    cb_error_clear(&err);
    cb_topo_body *b;
    cb_status st = cb_model_bracket(&b, &p, &err);
    if (st)
        return build_failed(st, &err);
    int code = validate_and_write(a->path, b, "bracket", "bracket",
                                  p.as_nurbs ? "rational B-splines" : "planes and cylinders");
    if (code != 2)
        printf("volume (closed form): %.17g (model units^3)\n", cb_bracket_volume(&p.shape));
    cb_topo_body_free(b);
    return code;
}

static const char *kind_name(cb_cardan_kind k) { return k == CB_CARDAN_CROSS ? "cross" : "yoke"; }

/* Builds, validates and writes one Cardan part (role: "" or " (A)", " (B)"). */
static int write_cardan_part(const char *path, const cb_cardan_params *p, const char *role)
{
    cb_error err;
    cb_error_clear(&err);
    double volume;
    cb_status st = cb_model_cardan_volume(&volume, p, &err);
    if (st)
        return build_failed(st, &err);
    cb_topo_body *b;
    if ((st = cb_model_cardan(&b, p, &err)))
        return build_failed(st, &err);
    char label[64], step_name[64];
    snprintf(label, sizeof label, "cardan %s%s", kind_name(p->kind), role);
    snprintf(step_name, sizeof step_name, "cardan_%s", kind_name(p->kind));
    int code = validate_and_write(path, b, label, step_name,
                                  p->as_nurbs ? "rational B-splines" : "planes and cylinders");
    if (code != 2)
        printf("volume (closed form): %.17g (model units^3)\n", volume);
    cb_topo_body_free(b);
    return code;
}

/* The names cardan accepts, for messages. */
static void print_cardan_names(FILE *out)
{
    fputs("parts: cross, yoke; scenarios:", out);
    for (int k = 0; k < cb_cardan_scenario_count(); k++) {
        cb_cardan_scenario s;
        cb_error err;
        if (!cb_cardan_scenario_get(&s, k, &err))
            fprintf(out, "%s %s", k ? "," : "", s.name);
    }
}

static int list_scenarios(void)
{
    for (int k = 0; k < cb_cardan_scenario_count(); k++) {
        cb_cardan_scenario s;
        cb_error err;
        cb_error_clear(&err);
        if (cb_cardan_scenario_get(&s, k, &err)) {
            fprintf(stderr, "colibri: %s\n", err.msg);
            return 1;
        }
        printf("%-19s A %s, B %s: %s\n", s.name, kind_name(s.a.kind), kind_name(s.b.kind),
               s.contact);
    }
    return 0;
}

static int write_scenario(const model_args *a, const cb_cardan_scenario *s0)
{
    int code;
    if ((code = refuse(a->has_rotate, "--rotate", "a scenario (its poses are fixed)")) ||
        (code = refuse(a->has_translate, "--translate", "a scenario (its poses are fixed)")) ||
        (code = refuse(a->has_fillet, "--fillet", "a scenario (its shapes are fixed)")))
        return code;
    if (!a->path_b) {
        fprintf(stderr, "colibri: scenario %s: --out-b FILE is needed for part B\n", s0->name);
        return 2;
    }
    cb_cardan_scenario s = *s0;
    s.a.as_nurbs = s.b.as_nurbs = a->nurbs;
    cb_cardan_volumes v;
    cb_error err;
    cb_error_clear(&err);
    cb_status st = cb_cardan_scenario_volumes(&v, &s, &err);
    if (st)
        return build_failed(st, &err);
    printf("scenario %s: %s\n", s.name, s.contact);
    int ca = write_cardan_part(a->path, &s.a, " (A)");
    if (ca == 2)
        return 2;
    int cb = write_cardan_part(a->path_b, &s.b, " (B)");
    if (cb == 2)
        return 2;
    printf("reference volumes (closed forms, model units^3; %s):\n", s.closed_form);
    printf("  A      %.17g\n  B      %.17g\n  A u B  %.17g\n  A n B  %.17g\n  A - B  %.17g\n"
           "  B - A  %.17g\n",
           v.a, v.b, v.a_union_b, v.a_inter_b, v.a_minus_b, v.b_minus_a);
    return ca || cb ? 1 : 0;
}

static int model_cardan(const model_args *a)
{
    int code;
    if ((code = refuse(a->has_scale, "--scale", "cardan")) ||
        (code = refuse(a->has_wing, "--wing-angle", "cardan")))
        return code;
    if (a->list) {
        if (a->part || a->path || a->path_b || a->nurbs || a->has_rotate || a->has_translate ||
            a->has_fillet) {
            fputs(MODEL_USAGE, stderr);
            return 2;
        }
        return list_scenarios();
    }
    if (!a->part || !a->path) {
        fputs("colibri: cardan needs a part or scenario and -o FILE (", stderr);
        print_cardan_names(stderr);
        fputs("; see colibri model --help)\n", stderr);
        return 2;
    }
    cb_cardan_kind kind;
    if (!strcmp(a->part, "cross") || !strcmp(a->part, "yoke")) {
        kind = !strcmp(a->part, "cross") ? CB_CARDAN_CROSS : CB_CARDAN_YOKE;
    } else {
        cb_cardan_scenario s;
        cb_error err;
        cb_error_clear(&err);
        if (cb_cardan_scenario_find(&s, a->part, &err)) {
            fprintf(stderr, "colibri: unknown cardan part or scenario '%s' (", a->part);
            print_cardan_names(stderr);
            fputs(")\n", stderr);
            return 2;
        }
        return write_scenario(a, &s);
    }
    if ((code = refuse(a->path_b != NULL, "--out-b", "a single part")) ||
        (code = refuse(a->has_fillet && kind == CB_CARDAN_CROSS, "--fillet", "the cross")))
        return code;
    cb_cardan_params p;
    cb_cardan_params_default(&p, kind);
    p.pose = a->pose;
    p.as_nurbs = a->nurbs;
    if (a->has_fillet)
        p.yoke.fillet_radius = a->fillet;
    cb_error err;
    cb_error_clear(&err);
    cb_status st = cb_cardan_params_check(&p, &err);
    if (st)
        return build_failed(st, &err);
    return write_cardan_part(a->path, &p, "");
}

static int print_reference(void)
{
    char *json = NULL;
    cb_error err;
    cb_error_clear(&err);
    if (cb_cardan_reference_json(&json, &err)) {
        fprintf(stderr, "colibri: %s\n", err.msg);
        return 1;
    }
    fputs(json, stdout);
    free(json);
    return 0;
}

int cb_cli_model(int argc, char **argv)
{
    for (int k = 1; k < argc; k++)
        if (!strcmp(argv[k], "--help")) {
            fputs(MODEL_USAGE, stdout);
            return 0;
        }
    model_args a;
    int code = parse_args(&a, argc, argv);
    if (code)
        return code;
    if (a.reference) {
        int only = !a.path && !a.path_b && !a.part && !a.list && !a.nurbs && !a.has_scale &&
                   !a.has_wing && !a.has_rotate && !a.has_translate && !a.has_fillet &&
                   (!a.name || !strcmp(a.name, "cardan"));
        if (!only) {
            fputs(MODEL_USAGE, stderr);
            return 2;
        }
        return print_reference();
    }
    int pair = a.name && !strcmp(a.name, "hummingbird-pair");
    if (!pair && ((code = refuse(a.estimate > 0, "--estimate", "this model")) ||
                  (code = refuse(a.threads != 0, "--threads", "this model"))))
        return code;
    if (a.name && !strcmp(a.name, "cardan"))
        return model_cardan(&a);
    if (pair) {
        const char *where = "hummingbird-pair (its shapes and poses are fixed)";
        if ((code = refuse(a.nurbs, "--nurbs", where)) ||
            (code = refuse(a.has_fillet, "--fillet", where)) ||
            (code = refuse(a.list, "--list", where)) ||
            (code = refuse(a.has_scale, "--scale", where)) ||
            (code = refuse(a.has_wing, "--wing-angle", where)) ||
            (code = refuse(a.has_rotate, "--rotate", where)) ||
            (code = refuse(a.has_translate, "--translate", where)) ||
            (code = refuse(a.part != NULL, a.part, where)))
            return code;
        return model_pair(&a);
    }
    if (!a.name || !a.path || a.part) {
        fputs(MODEL_USAGE, stderr);
        return 2;
    }
    if (!strcmp(a.name, "bracket")) {
        if ((code = refuse(a.has_scale, "--scale", "bracket")) ||
            (code = refuse(a.has_wing, "--wing-angle", "bracket")) ||
            (code = refuse(a.has_fillet, "--fillet", "bracket")) ||
            (code = refuse(a.path_b != NULL, "--out-b", "bracket")) ||
            (code = refuse(a.list, "--list", "bracket")))
            return code;
        return write_bracket(&a);
    }
    if (strcmp(a.name, "hummingbird")) {
        fprintf(stderr,
                "colibri: unknown model '%s' (known: hummingbird, hummingbird-pair, cardan, "
                "bracket)\n",
                a.name);
        return 2;
    }
    if ((code = refuse(a.nurbs, "--nurbs", "hummingbird")) ||
        (code = refuse(a.has_fillet, "--fillet", "hummingbird")) ||
        (code = refuse(a.path_b != NULL, "--out-b", "hummingbird")) ||
        (code = refuse(a.list, "--list", "hummingbird")))
        return code;
    return write_hummingbird(&a);
}
