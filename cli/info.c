/* colibri info: load a model and print what it holds. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "brep/mass.h"
#include "brep/nurbs.h"
#include "brep/topo.h"
#include "cli/commands.h"
#include "io/bpt.h"
#include "io/step.h"
#include "io/json.h"

static const char INFO_USAGE[] =
    "usage: colibri info FILE [--json] [--tol T] [--no-mass]\n"
    "\n"
    "Loads a model and prints what it holds.\n"
    "Formats, by extension:\n"
    "  .step, .stp  STEP B-rep: counts of solids, shells, faces, edges, vertices, surface\n"
    "               types, the bounding box of the edges (in the file's length unit), and a\n"
    "               topology validation (closed shells, closed loops, edges on their faces),\n"
    "               and the volume and area (exact integrals over the trimmed faces,\n"
    "               brep/mass.h, to about 1e-9 relative), or why they cannot be integrated\n"
    "               (an open shell, loops that do not close) or trusted (the faces'\n"
    "               integrated normals do not close up within the edges' tolerances: a\n"
    "               face integrated over the wrong region; the numbers are in the message)\n"
    "  .bpt         Bezier patch text (e.g. the Newell teapot): patches, degrees, points\n"
    "\n"
    "options:\n"
    "  --json     print one JSON object instead of text; for STEP it has the keys solids,\n"
    "             shells, faces, edges, vertices, surface_types (name -> count), bbox\n"
    "             ([xmin, ymin, zmin, xmax, ymax, zmax]), unit_mm, tolerance, valid,\n"
    "             problems (list of strings), the largest deviations measured,\n"
    "             edges_tol_raised, edges_over_cap, max_edge_tol, edge_tol_cap, volume and\n"
    "             area (model units^3 and ^2; null when they are not integrated, the reason\n"
    "             then in mass_error, else null; a surface model, open shells and no\n"
    "             solid, has its area and a null volume)\n"
    "  --tol T    validation tolerance in model units (default: the file's uncertainty);\n"
    "             each edge is checked against the larger of T and its own tolerance\n"
    "  --no-mass  skip the volume and area (they take about a second on a few dozen\n"
    "             B-spline faces)\n"
    "\n"
    "Edge tolerances: files often hold edges farther from their faces than the uncertainty\n"
    "they declare. The reader measures each edge's deviation from its faces, vertices and\n"
    "pcurves and raises the edge's tolerance to it (plus 5%), up to a cap of 1e-4 of the\n"
    "diagonal of the model's box; an edge beyond the cap keeps the file's tolerance and is\n"
    "reported. The summary says how many edges were raised and the largest edge tolerance.\n"
    "\n"
    "Volume and area are in the file's length unit (mm^3 and mm^2, cm^3, in^3, ...); whether\n"
    "they could be integrated does not change the exit status.\n"
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

/* Relative accuracy asked of the volume and area: the ten digits printed (CB_MASS_REL_TOL's
 * 1e-10 takes ten times longer on trj5's B-splines for the same digits). */
#define INFO_MASS_REL_TOL 1e-9

/* Volume and area of a body, or why they could not be integrated. */
typedef struct {
    int ok, skipped; /* skipped: --no-mass */
    int sheets;      /* ok, a surface model: open shells only, which bound no volume */
    double volume, area; /* model units^3, ^2 */
    char error[CB_ERROR_MSG_LEN];
} info_mass;

static void info_mass_compute(info_mass *m, const cb_topo_body *b)
{
    cb_error err;
    cb_error_clear(&err);
    cb_mass_props p = {0};
    cb_status st = b->n_shells > 0
                       ? cb_mass_body(&p, b, INFO_MASS_REL_TOL, NULL, &err)
                       : cb_error_set(&err, CB_ERR_INVALID, "mass: the model has no shell");
    m->skipped = 0;
    /* Faces that do not close up (cb_mass_closure_bound, at the edges' own tolerances): a
     * face integrated over the wrong region, the volume not to be trusted. */
    double va = cb_vec3_norm(p.vector_area), bound = st ? 0 : cb_mass_closure_bound(b, p.area, 1);
    if (st == CB_OK && !(va <= bound))
        st = cb_error_set(&err, CB_ERR_NUMERIC,
                          "mass: the faces' integrated normals do not close up (vector area "
                          "%.3g, the edges' tolerances allow %.3g): a face integrated over the "
                          "wrong region, the volume %.10g and area %.10g not to be trusted",
                          va, bound, p.volume, p.area);
    m->ok = st == CB_OK && isfinite(p.volume) && isfinite(p.area);
    m->volume = m->ok ? p.volume : 0;
    m->area = m->ok ? p.area : 0;
    m->sheets = 0;
    /* A surface model (no solid, no shell declared closed): its faces' area, no volume. */
    int sheets = st != CB_OK && b->n_solids == 0 && b->n_shells > 0;
    for (int k = 0; k < b->n_shells && sheets; k++)
        sheets = !b->shells[k].closed;
    if (sheets) {
        cb_error_clear(&err);
        double area;
        st = cb_mass_area(&area, b, INFO_MASS_REL_TOL, NULL, &err);
        m->ok = m->sheets = st == CB_OK && isfinite(area);
        m->area = m->ok ? area : 0;
    }
    snprintf(m->error, sizeof m->error, "%s",
             m->ok ? "" : st ? err.msg : "mass: the integrals are not finite");
}

/* The name of a length unit of mm millimetres, NULL if it has none here. */
static const char *unit_name(double mm)
{
    static const struct {
        double mm;
        const char *name;
    } units[] = {{1, "mm"},    {10, "cm"},   {1000, "m"},    {1e6, "km"},
                 {1e-3, "um"}, {1e-6, "nm"}, {25.4, "in"},   {304.8, "ft"}};
    for (size_t k = 0; k < sizeof units / sizeof units[0]; k++)
        if (fabs(mm - units[k].mm) <= 1e-12 * units[k].mm)
            return units[k].name;
    return NULL;
}

static void print_step_json(const char *path, const cb_topo_body *b, const cb_aabb *box,
                            const cb_topo_report *r, double tol, const cb_step_stats *ts,
                            const info_mass *m)
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
           "\"edge_tol_cap\": %.17g, ",
           r->dropped, r->max_edge_surface, r->max_loop_gap, r->max_edge_vertex,
           ts->edges_tol_raised, ts->edges_over_cap, ts->max_edge_tol, ts->edge_tol_cap);
    if (m->ok && m->sheets) {
        printf("\"volume\": null, \"area\": %.17g, \"mass_error\": null}\n", m->area);
        return;
    }
    if (m->ok) {
        printf("\"volume\": %.17g, \"area\": %.17g, \"mass_error\": null}\n", m->volume, m->area);
        return;
    }
    fputs("\"volume\": null, \"area\": null, \"mass_error\": ", stdout);
    cb_json_string(stdout, m->error);
    fputs("}\n", stdout);
}

/* The volume and area in the body's unit (unit_mm millimetres), or why they are missing. */
static void print_mass_text(const info_mass *m, double unit_mm)
{
    const char *unit = unit_name(unit_mm);
    if (!m->ok)
        printf("volume, area: not integrated (%s)\n", m->error);
    else if (m->sheets)
        printf("volume: none (a surface model: open shells), area %.10g %s^2\n", m->area,
               unit ? unit : "units");
    else if (unit)
        printf("volume %.10g %s^3, area %.10g %s^2\n", m->volume, unit, m->area, unit);
    else
        printf("volume %.10g units^3, area %.10g units^2 (unit %g mm)\n", m->volume, m->area,
               unit_mm);
}

static void print_step_text(const char *path, const cb_topo_body *b, const cb_aabb *box,
                            const cb_topo_report *r, double tol, const cb_step_stats *ts,
                            const info_mass *m)
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
    if (!m->skipped)
        print_mass_text(m, b->length_unit_mm);
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

static int info_step(const char *path, int json, double tol, int mass)
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
    info_mass m = {0, 1, 0, 0, 0, "not computed (--no-mass)"};
    if (mass)
        info_mass_compute(&m, b);
    if (json)
        print_step_json(path, b, &box, &r, tol, &ts, &m);
    else
        print_step_text(path, b, &box, &r, tol, &ts, &m);
    int code = r.n ? 1 : 0;
    cb_topo_report_clear(&r);
    cb_topo_body_free(b);
    return code;
}

int cb_cli_info(int argc, char **argv)
{
    const char *path = NULL;
    int json = 0, mass = 1;
    double tol = 0;
    for (int k = 1; k < argc; k++) {
        if (!strcmp(argv[k], "--help")) {
            fputs(INFO_USAGE, stdout);
            return 0;
        }
        if (!strcmp(argv[k], "--json")) {
            json = 1;
        } else if (!strcmp(argv[k], "--no-mass")) {
            mass = 0;
        } else if (!strcmp(argv[k], "--tol") && k + 1 < argc) {
            if (cb_cli_tol_arg(&tol, argv[++k]))
                return 2;
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
        return info_step(path, json, tol, mass);
    fprintf(stderr, "colibri: %s: unknown model format (known: .step, .stp, .bpt)\n", path);
    return 2;
}
