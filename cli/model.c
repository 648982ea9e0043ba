/* colibri model: build one of the shipped models and write it as STEP. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brep/topo.h"
#include "cli/commands.h"
#include "io/step_write.h"
#include "models/models.h"

static const char MODEL_USAGE[] =
    "usage: colibri model NAME -o FILE.step [--scale S] [--rotate AX AY AZ DEG]\n"
    "                         [--translate X Y Z] [--wing-angle DEG]\n"
    "\n"
    "Builds a model, checks it with the topology validator and writes it as one closed solid in\n"
    "a STEP AP214 file. Prints its counts and the validation.\n"
    "\n"
    "models:\n"
    "  hummingbird  a freeform bird (body, head and beak, two wings, tail) of 312 bicubic\n"
    "               B-spline faces of 6 x 6 control points, as in Yang, Jia, Yan (ACM TOG 2023)\n"
    "               Fig. 12; about 2.9 long and 2.9 across the wings at scale 1, x forward,\n"
    "               y to the left wing, z up\n"
    "\n"
    "options (the pose is p -> R (S p) + T: scale, then rotation, then translation):\n"
    "  -o FILE              the STEP file to write (required)\n"
    "  --scale S            size factor, S > 0 (default 1)\n"
    "  --rotate AX AY AZ DEG  rotation by DEG degrees about the axis (AX, AY, AZ) through the\n"
    "                       origin (default none)\n"
    "  --translate X Y Z    translation (default none)\n"
    "  --wing-angle DEG     hummingbird: wings raised DEG degrees, in [-30, 50] (default 20)\n"
    "\n"
    "Exit status: 0 the model was written and is valid, 1 it could not be built or fails\n"
    "validation, 2 bad usage (including an output file that cannot be written).\n"
    "\n"
    "example (the two overlapping birds of the Boolean scenario):\n"
    "  colibri model hummingbird -o bird_a.step\n"
    "  colibri model hummingbird -o bird_b.step --rotate 0.2 0.3 1 40 --translate 0.4 0.25 0.15 "
    "--wing-angle 5\n";

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

/* Builds, validates and writes the hummingbird; exit status as cb_cli_model. */
static int write_hummingbird(const char *path, const cb_hummingbird_params *p)
{
    cb_error err;
    cb_error_clear(&err);
    cb_topo_body *b;
    cb_status st = cb_model_hummingbird(&b, p, &err);
    if (st) {
        fprintf(stderr, "colibri: %s\n", err.msg);
        return st == CB_ERR_INVALID ? 2 : 1;
    }
    cb_topo_report r;
    cb_topo_report_init(&r);
    int code = 0;
    if ((st = cb_topo_validate(&r, b, b->tol, 9, &err))) {
        fprintf(stderr, "colibri: %s\n", err.msg);
        code = 1;
    } else if ((st = cb_step_write(b, path, "hummingbird", &err))) {
        fprintf(stderr, "colibri: %s\n", err.msg);
        code = st == CB_ERR_IO ? 2 : 1;
    } else {
        printf("%s: hummingbird: 1 solid, %d faces, %d edges, %d vertices (bicubic B-splines, "
               "6 x 6 control points)\n",
               path, b->n_faces, b->n_edges, b->n_vertices);
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
    cb_topo_body_free(b);
    return code;
}

int cb_cli_model(int argc, char **argv)
{
    const char *name = NULL, *path = NULL;
    cb_hummingbird_params p;
    cb_hummingbird_params_default(&p);
    for (int k = 1; k < argc; k++) {
        const char *a = argv[k];
        if (!strcmp(a, "--help")) {
            fputs(MODEL_USAGE, stdout);
            return 0;
        }
        int bad = 0;
        if (!strcmp(a, "-o") && k + 1 < argc) {
            path = argv[++k];
        } else if (!strcmp(a, "--scale")) {
            bad = parse_numbers(&p.scale, 1, argc, argv, k) || !(p.scale > 0);
            k += 1;
        } else if (!strcmp(a, "--rotate")) {
            double v[4];
            bad = parse_numbers(v, 4, argc, argv, k);
            if (!bad) {
                memcpy(p.axis, v, sizeof p.axis);
                p.angle_deg = v[3];
                bad = v[3] != 0 && !(cb_vec3_norm(p.axis) > 0);
            }
            k += 4;
        } else if (!strcmp(a, "--translate")) {
            bad = parse_numbers(p.translate, 3, argc, argv, k);
            k += 3;
        } else if (!strcmp(a, "--wing-angle")) {
            bad = parse_numbers(&p.wing_angle_deg, 1, argc, argv, k);
            k += 1;
        } else if (a[0] == '-' || name) {
            fputs(MODEL_USAGE, stderr);
            return 2;
        } else {
            name = a;
        }
        if (bad) {
            fprintf(stderr, "colibri: %s: bad or missing values (see colibri model --help)\n", a);
            return 2;
        }
    }
    if (!name || !path) {
        fputs(MODEL_USAGE, stderr);
        return 2;
    }
    if (strcmp(name, "hummingbird")) {
        fprintf(stderr, "colibri: unknown model '%s' (known: hummingbird)\n", name);
        return 2;
    }
    return write_hummingbird(path, &p);
}
