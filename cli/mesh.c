/* colibri mesh: tessellate a B-rep model, check the mesh and write it. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

#include "brep/mesh_check.h"
#include "brep/tess.h"
#include "cli/commands.h"
#include "io/json.h"
#include "io/mesh.h"
#include "io/step.h"

static const char MESH_USAGE[] =
    "usage: colibri mesh MODEL -o OUT [--tol T] [--json] [--threads N] [--quiet]\n"
    "\n"
    "Tessellates a STEP B-rep model (.step, .stp) into a watertight triangle mesh, checks it\n"
    "as 'colibri check' does (closed, manifold, oriented, self-intersections, bounds a volume,\n"
    "outward; CGAL) and writes it to OUT (.stl, .obj, .ply, .off, by extension). Every edge\n"
    "is sampled once and shared by its two faces; each face is triangulated in its parameter\n"
    "domain and refined until the surface lies within the chordal tolerance of the mesh and\n"
    "the normals within 20 degrees.\n"
    "\n"
    "options:\n"
    "  -o OUT       the mesh file to write (required)\n"
    "  --tol T      chordal tolerance in model units (default: 1e-3 of the diagonal of the\n"
    "               model's edge box)\n"
    "  --json       print one JSON object with the keys file, output, tolerance, unit_mm,\n"
    "               vertices, triangles, volume (model units^3), closed, manifold,\n"
    "               oriented, self_intersections, bounds_volume, outward, passed, seconds\n"
    "  --threads N  tessellate on at most N threads (default 0: all hardware threads; the\n"
    "               mesh is the same for any N)\n"
    "  --quiet      no progress and no text summary (the exit status tells; --json still\n"
    "               prints its object); errors still go to stderr\n"
    "\n"
    "Progress goes to stderr when stderr is a terminal (and --quiet is not given).\n"
    "Exit status: 0 the mesh passed every check and was written, 1 the mesh failed a check or\n"
    "could not be made or written, 2 bad usage or an unreadable or malformed model.\n"
    "\n"
    "example:\n"
    "  colibri mesh ../shared/models/ujoint_fork.step -o fork.stl --tol 0.05\n";

static int has_extension(const char *path, const char *ext)
{
    const char *dot = strrchr(path, '.');
    return dot && !strcasecmp(dot + 1, ext);
}

/* Redraws the line when the whole percentage changes (user: the last one shown). */
static const char *json_flag(int v)
{
    return v < 0 ? "null" : v ? "true" : "false";
}

static const char *yes_no(int v)
{
    return v < 0 ? "not checked" : v ? "yes" : "no";
}

static void print_json(const char *path, const char *out, double tol, const cb_topo_body *b,
                       const cb_mesh_t m, const cb_mesh_check_report *r, double seconds)
{
    fputs("{\"file\": ", stdout);
    cb_json_string(stdout, path);
    fputs(", \"output\": ", stdout);
    cb_json_string(stdout, out);
    printf(", \"tolerance\": %.17g, \"unit_mm\": %.17g, \"vertices\": %d, \"triangles\": %d, "
           "\"volume\": %.17g, \"closed\": %s, \"manifold\": %s, \"oriented\": %s, "
           "\"self_intersections\": %s, \"bounds_volume\": %s, \"outward\": %s, "
           "\"passed\": %s, \"seconds\": %.3f}\n",
           tol, b->length_unit_mm, m->n_vertices, m->n_triangles, cb_mesh_volume(m),
           json_flag(r->closed), json_flag(r->edge_manifold && r->vertex_manifold),
           json_flag(r->oriented), json_flag(r->self_intersections), json_flag(r->bounds_volume),
           json_flag(r->outward), json_flag(cb_mesh_check_passed(r)), seconds);
}

static void print_text(const char *path, const char *out, double tol, const cb_topo_body *b,
                       const cb_mesh_t m, const cb_mesh_check_report *r)
{
    printf("%s: %d faces -> %s: %d vertices, %d triangles (chordal tolerance %g)\n", path,
           b->n_faces, out, m->n_vertices, m->n_triangles, tol);
    printf("closed: %s\nmanifold: %s\noriented: %s\n", yes_no(r->closed),
           yes_no(r->edge_manifold && r->vertex_manifold), yes_no(r->oriented));
    printf("self-intersections: %s\n",
           r->self_intersections < 0 ? "not checked" : r->self_intersections ? "yes" : "none");
    printf("bounds a volume: %s\noutward: %s\n", yes_no(r->bounds_volume), yes_no(r->outward));
    double v = cb_mesh_volume(m);
    printf("mesh volume: %.10g (model units^3; %.10g mm^3)\n", v,
           v * pow(b->length_unit_mm, 3));
    printf("result: %s\n", cb_mesh_check_passed(r) ? "pass" : "FAIL");
}

int cb_cli_mesh(int argc, char **argv)
{
    const char *path = NULL, *out = NULL;
    int json = 0, quiet = 0, threads = 0;
    double tol = 0;
    for (int k = 1; k < argc; k++) {
        if (!strcmp(argv[k], "--help")) {
            fputs(MESH_USAGE, stdout);
            return 0;
        }
        if (!strcmp(argv[k], "--json")) {
            json = 1;
        } else if (!strcmp(argv[k], "--quiet")) {
            quiet = 1;
        } else if (!strcmp(argv[k], "--threads") && k + 1 < argc) {
            if (cb_cli_threads_arg(&threads, argv[++k]))
                return 2;
        } else if (!strcmp(argv[k], "-o") && k + 1 < argc) {
            out = argv[++k];
        } else if (!strcmp(argv[k], "--tol") && k + 1 < argc) {
            if (cb_cli_tol_arg(&tol, argv[++k]))
                return 2;
        } else if (argv[k][0] == '-' || path) {
            fputs(MESH_USAGE, stderr);
            return 2;
        } else {
            path = argv[k];
        }
    }
    if (!path || !out) {
        fputs(MESH_USAGE, stderr);
        return 2;
    }
    cb_error err;
    cb_error_clear(&err);
    cb_mesh_format fmt;
    if (cb_mesh_format_of_path(&fmt, out, &err)) {
        fprintf(stderr, "colibri: %s\n", err.msg);
        return 2;
    }
    if (!has_extension(path, "step") && !has_extension(path, "stp")) {
        fprintf(stderr, "colibri: %s: not a STEP file (.step, .stp)\n", path);
        return 2;
    }
    cb_topo_body *b;
    cb_status rst = cb_step_read(&b, path, &err);
    if (rst) {
        fprintf(stderr, "colibri: %s\n", err.msg);
        return cb_cli_input_exit(rst);
    }
    cb_context ctx;
    cb_context_init(&ctx);
    ctx.threads = threads;
    int tty = !quiet && isatty(STDERR_FILENO), shown = -1;
    if (tty) {
        ctx.progress = cb_cli_progress;
        ctx.user = &shown;
    }
    cb_tess_opts o;
    cb_tess_opts_init(&o);
    o.chord_tol = tol;
    cb_tess_opts ro;
    cb_mesh_t m;
    cb_mesh_init(m);
    double t0 = cb_cli_seconds();
    cb_status st = cb_tess_opts_resolve(&ro, &o, b, &err);
    if (!st)
        st = cb_tess_body(m, b, &ro, &ctx, &err);
    if (tty)
        fputs("\n", stderr);
    if (st) {
        fprintf(stderr, "colibri: %s: %s\n", path, err.msg);
        cb_topo_body_free(b);
        return st == CB_ERR_INVALID ? 2 : 1;
    }
    double seconds = cb_cli_seconds() - t0;
    cb_mesh_check_report r;
    st = cb_mesh_check(&r, m, &err);
    if (!st)
        st = cb_mesh_write(out, m, NULL, &err);
    int code = 1;
    if (st) {
        fprintf(stderr, "colibri: %s\n", err.msg);
    } else {
        if (json)
            print_json(path, out, ro.chord_tol, b, m, &r, seconds);
        else if (!quiet)
            print_text(path, out, ro.chord_tol, b, m, &r);
        code = cb_mesh_check_passed(&r) ? 0 : 1;
    }
    cb_mesh_clear(m);
    cb_topo_body_free(b);
    return code;
}
