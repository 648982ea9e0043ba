/* colibri info: load a model and print what it holds. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "brep/nurbs.h"
#include "brep/topo.h"
#include "cli/commands.h"
#include "io/bpt.h"
#include "io/step.h"
#include "io/json.h"

static const char INFO_USAGE[] =
    "usage: colibri info FILE [--json] [--tol T]\n"
    "\n"
    "Loads a model and prints what it holds.\n"
    "Formats, by extension:\n"
    "  .step, .stp  STEP B-rep: counts of solids, shells, faces, edges, vertices, surface\n"
    "               types, the bounding box of the edges (in the file's length unit), and a\n"
    "               topology validation (closed shells, closed loops, edges on their faces)\n"
    "  .bpt         Bezier patch text (e.g. the Newell teapot): patches, degrees, points\n"
    "\n"
    "options:\n"
    "  --json   print one JSON object instead of text; for STEP it has the keys solids,\n"
    "           shells, faces, edges, vertices, surface_types (name -> count), bbox\n"
    "           ([xmin, ymin, zmin, xmax, ymax, zmax]), unit_mm, tolerance, valid, problems\n"
    "           (list of strings), the largest deviations measured, edges_tol_raised,\n"
    "           edges_over_cap, max_edge_tol and edge_tol_cap\n"
    "  --tol T  validation tolerance in model units (default: the file's uncertainty); each\n"
    "           edge is checked against the larger of T and its own tolerance\n"
    "\n"
    "Edge tolerances: files often hold edges farther from their faces than the uncertainty\n"
    "they declare. The reader measures each edge's deviation from its faces, vertices and\n"
    "pcurves and raises the edge's tolerance to it (plus 5%), up to a cap of 1e-4 of the\n"
    "diagonal of the model's box; an edge beyond the cap keeps the file's tolerance and is\n"
    "reported. The summary says how many edges were raised and the largest edge tolerance.\n"
    "\n"
    "Exit status: 0 the model was read (and, for STEP, is valid), 1 the model was read but\n"
    "validation found problems, 2 bad usage or an input that cannot be used (missing,\n"
    "unreadable, malformed or of an unknown format: the message names file:line and the\n"
    "entity #id where there is one).\n"
    "\n"
    "example:\n"
    "  colibri info ../shared/models/ujoint_fork.step --json\n";

static int has_extension(const char *path, const char *ext)
{
    const char *dot = strrchr(path, '.');
    return dot && !strcasecmp(dot + 1, ext);
}

static void print_patches(const char *path, const cb_nurbs_surface_struct *p, int n, int json)
{
    long points = 0;
    int rational = 0, max_du = 0, max_dv = 0;
    for (int k = 0; k < n; k++) {
        points += (long)p[k].n_u * p[k].n_v;
        max_du = p[k].deg_u > max_du ? p[k].deg_u : max_du;
        max_dv = p[k].deg_v > max_dv ? p[k].deg_v : max_dv;
        for (long i = 0; i < (long)p[k].n_u * p[k].n_v; i++)
            if (p[k].cw[4 * i + 3] != 1.0) {
                rational++;
                break;
            }
    }
    if (json) {
        fputs("{\"file\": ", stdout);
        cb_json_string(stdout, path);
        printf(", \"format\": \"bpt\", \"patches\": %d, \"rational\": %d, \"control_points\": %ld, "
               "\"max_degree\": [%d, %d]}\n",
               n, rational, points, max_du, max_dv);
        return;
    }
    printf("%s: %d patches (%d rational), %ld control points, degrees up to (%d, %d)\n", path, n,
           rational, points, max_du, max_dv);
}

static int info_bpt(const char *path, int json)
{
    cb_error err;
    cb_error_clear(&err);
    cb_nurbs_surface_struct *patches;
    int n;
    cb_status st = cb_bpt_read(&patches, &n, path, &err);
    if (st) {
        fprintf(stderr, "colibri: %s\n", err.msg);
        return cb_cli_input_exit(st);
    }
    print_patches(path, patches, n, json);
    cb_nurbs_surface_array_free(patches, n);
    return 0;
}

static void print_step_json(const char *path, const cb_topo_body *b, const cb_aabb *box,
                            const cb_topo_report *r, double tol, const cb_step_stats *ts)
{
    const char *names[8];
    int counts[8], nt = cb_topo_body_surface_types(names, counts, b);
    fputs("{\"file\": ", stdout);
    cb_json_string(stdout, path);
    printf(", \"format\": \"step\", \"solids\": %d, \"shells\": %d, \"faces\": %d, \"edges\": %d, "
           "\"vertices\": %d, \"surface_types\": {",
           b->n_solids, b->n_shells, b->n_faces, b->n_edges, b->n_vertices);
    for (int k = 0; k < nt; k++)
        printf("%s\"%s\": %d", k ? ", " : "", names[k], counts[k]);
    printf("}, \"bbox\": [%.17g, %.17g, %.17g, %.17g, %.17g, %.17g], \"unit_mm\": %.17g, "
           "\"tolerance\": %.17g, \"valid\": %s, \"problems\": [",
           box->lo[0], box->lo[1], box->lo[2], box->hi[0], box->hi[1], box->hi[2],
           b->length_unit_mm, tol, r->n ? "false" : "true");
    for (int k = 0; k < r->n; k++) {
        fputs(k ? ", " : "", stdout);
        cb_json_string(stdout, r->items[k]);
    }
    printf("], \"problems_not_listed\": %d, \"max_edge_surface_deviation\": %.17g, "
           "\"max_loop_gap\": %.17g, \"max_edge_vertex_deviation\": %.17g, "
           "\"edges_tol_raised\": %d, \"edges_over_cap\": %d, \"max_edge_tol\": %.17g, "
           "\"edge_tol_cap\": %.17g}\n",
           r->dropped, r->max_edge_surface, r->max_loop_gap, r->max_edge_vertex,
           ts->edges_tol_raised, ts->edges_over_cap, ts->max_edge_tol, ts->edge_tol_cap);
}

static void print_step_text(const char *path, const cb_topo_body *b, const cb_aabb *box,
                            const cb_topo_report *r, double tol, const cb_step_stats *ts)
{
    const char *names[8];
    int counts[8], nt = cb_topo_body_surface_types(names, counts, b);
    printf("%s: %d solid%s, %d shell%s, %d faces, %d edges, %d vertices\n", path, b->n_solids,
           b->n_solids == 1 ? "" : "s", b->n_shells, b->n_shells == 1 ? "" : "s", b->n_faces,
           b->n_edges, b->n_vertices);
    printf("surface types:");
    for (int k = 0; k < nt; k++)
        printf(" %s %d%s", names[k], counts[k], k + 1 < nt ? "," : "");
    printf("\nbounding box of the edges: [%g, %g] x [%g, %g] x [%g, %g] (unit %g mm)\n", box->lo[0],
           box->hi[0], box->lo[1], box->hi[1], box->lo[2], box->hi[2], b->length_unit_mm);
    printf("largest deviations: edge-surface %.3g, loop gap %.3g, edge-vertex %.3g\n",
           r->max_edge_surface, r->max_loop_gap, r->max_edge_vertex);
    printf("edge tolerances: %d raised above the file's %g, largest %.3g (cap %.3g)",
           ts->edges_tol_raised, b->tol, ts->max_edge_tol, ts->edge_tol_cap);
    if (ts->edges_over_cap)
        printf("; %d edge%s deviate%s beyond the cap", ts->edges_over_cap,
               ts->edges_over_cap == 1 ? "" : "s", ts->edges_over_cap == 1 ? "s" : "");
    printf("\n");
    if (!r->n) {
        printf("validation (tolerance %g): valid\n", tol);
        return;
    }
    printf("validation (tolerance %g): %d problem%s\n", tol, r->n + r->dropped,
           r->n + r->dropped == 1 ? "" : "s");
    for (int k = 0; k < r->n && k < 20; k++)
        printf("  %s\n", r->items[k]);
    if (r->n + r->dropped > 20)
        printf("  ... and %d more\n", r->n + r->dropped - 20);
}

static int info_step(const char *path, int json, double tol)
{
    cb_error err;
    cb_error_clear(&err);
    cb_topo_body *b;
    cb_step_stats ts;
    cb_status st = cb_step_read_opt(&b, path, NULL, &ts, &err);
    if (st) {
        fprintf(stderr, "colibri: %s\n", err.msg);
        return cb_cli_input_exit(st);
    }
    if (!(tol > 0))
        tol = b->tol;
    cb_topo_report r;
    cb_topo_report_init(&r);
    if (cb_topo_validate(&r, b, tol, 9, &err)) {
        fprintf(stderr, "colibri: %s: %s\n", path, err.msg);
        cb_topo_report_clear(&r);
        cb_topo_body_free(b);
        return 1;
    }
    cb_aabb box;
    cb_topo_body_edge_box(&box, b);
    if (json)
        print_step_json(path, b, &box, &r, tol, &ts);
    else
        print_step_text(path, b, &box, &r, tol, &ts);
    int code = r.n ? 1 : 0;
    cb_topo_report_clear(&r);
    cb_topo_body_free(b);
    return code;
}

int cb_cli_info(int argc, char **argv)
{
    const char *path = NULL;
    int json = 0;
    double tol = 0;
    for (int k = 1; k < argc; k++) {
        if (!strcmp(argv[k], "--help")) {
            fputs(INFO_USAGE, stdout);
            return 0;
        }
        if (!strcmp(argv[k], "--json")) {
            json = 1;
        } else if (!strcmp(argv[k], "--tol") && k + 1 < argc) {
            char *end;
            tol = strtod(argv[++k], &end);
            if (*end || !(tol > 0) || !isfinite(tol)) {
                fprintf(stderr, "colibri: --tol needs a positive number, not '%s'\n", argv[k]);
                return 2;
            }
        } else if (argv[k][0] == '-' || path) {
            fputs(INFO_USAGE, stderr);
            return 2;
        } else {
            path = argv[k];
        }
    }
    if (!path) {
        fputs(INFO_USAGE, stderr);
        return 2;
    }
    if (has_extension(path, "bpt"))
        return info_bpt(path, json);
    if (has_extension(path, "step") || has_extension(path, "stp"))
        return info_step(path, json, tol);
    fprintf(stderr, "colibri: %s: unknown model format (known: .step, .stp, .bpt)\n", path);
    return 2;
}
