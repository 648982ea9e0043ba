/* colibri check: is a mesh file the closed, manifold, outward boundary of a solid? */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "brep/mesh.h"
#include "brep/mesh_check.h"
#include "cli/commands.h"
#include "io/mesh.h"
#include "io/json.h"

static const char CHECK_USAGE[] =
    "usage: colibri check MESH [--json]\n"
    "\n"
    "Reads a triangle mesh (.stl, .obj, .ply, .off) and checks that it bounds a solid:\n"
    "  closed              every edge borders exactly two triangles\n"
    "  manifold            no edge borders more than two triangles, and the triangles around\n"
    "                      each vertex form a single fan\n"
    "  oriented            neighbouring triangles agree in orientation\n"
    "  self-intersections  no two triangles cross or touch other than at a shared edge or\n"
    "                      vertex (CGAL, exact predicates)\n"
    "  bounds a volume     (CGAL) nested parts are oppositely oriented\n"
    "  outward             (CGAL) the outer surface faces outward\n"
    "  volume              (CGAL) the enclosed volume\n"
    "Checks whose preconditions fail are not run (\"not checked\"; null in JSON): the CGAL\n"
    "checks need a manifold, oriented mesh, and the last three also a closed one without\n"
    "self-intersections. Faces are taken as the file gives them (STL files share exactly\n"
    "equal points); nothing is repaired.\n"
    "\n"
    "options:\n"
    "  --json   print one JSON object with the keys file, vertices, triangles, closed,\n"
    "           manifold, edge_manifold, vertex_manifold, oriented, triangle_mesh,\n"
    "           self_intersections, bounds_volume, outward, volume, boundary_edges,\n"
    "           nonmanifold_edges, nonmanifold_vertices, misoriented_edges, passed\n"
    "\n"
    "Exit status: 0 every check passed, 1 a check failed or could not run, 2 bad usage or a\n"
    "file that cannot be used (missing, unreadable, malformed, unknown format).\n"
    "\n"
    "example:\n"
    "  colibri check part.stl --json\n";

/* A check result in JSON: true, false, or null when the check was not run. */
static const char *json_flag(int v)
{
    return v < 0 ? "null" : v ? "true" : "false";
}

static void print_json(const char *path, const cb_mesh_check_report *r)
{
    fputs("{\"file\": ", stdout);
    cb_json_string(stdout, path);
    printf(", \"vertices\": %d, \"triangles\": %d, \"closed\": %s, \"manifold\": %s, "
           "\"edge_manifold\": %s, \"vertex_manifold\": %s, \"oriented\": %s, "
           "\"triangle_mesh\": %s, \"self_intersections\": %s, \"bounds_volume\": %s, "
           "\"outward\": %s, \"volume\": ",
           r->vertices, r->triangles, json_flag(r->closed),
           json_flag(r->edge_manifold && r->vertex_manifold), json_flag(r->edge_manifold),
           json_flag(r->vertex_manifold), json_flag(r->oriented), json_flag(r->triangle_mesh),
           json_flag(r->self_intersections), json_flag(r->bounds_volume), json_flag(r->outward));
    if (isnan(r->volume))
        fputs("null", stdout);
    else
        printf("%.17g", r->volume);
    printf(", \"boundary_edges\": %d, \"nonmanifold_edges\": %d, \"nonmanifold_vertices\": %d, "
           "\"misoriented_edges\": %d, \"passed\": %s}\n",
           r->boundary_edges, r->nonmanifold_edges, r->nonmanifold_vertices,
           r->misoriented_edges, json_flag(cb_mesh_check_passed(r)));
}

static const char *yes_no(int v)
{
    return v < 0 ? "not checked" : v ? "yes" : "no";
}

static void print_text(const char *path, const cb_mesh_check_report *r)
{
    printf("%s: %d vertices, %d triangles\n", path, r->vertices, r->triangles);
    printf("closed: %s", yes_no(r->closed));
    if (r->boundary_edges)
        printf(" (%d boundary edge%s)", r->boundary_edges, r->boundary_edges == 1 ? "" : "s");
    printf("\nmanifold: %s", yes_no(r->edge_manifold && r->vertex_manifold));
    if (r->nonmanifold_edges || r->nonmanifold_vertices)
        printf(" (%d non-manifold edge%s, %d non-manifold vert%s)", r->nonmanifold_edges,
               r->nonmanifold_edges == 1 ? "" : "s", r->nonmanifold_vertices,
               r->nonmanifold_vertices == 1 ? "ex" : "ices");
    printf("\noriented: %s", yes_no(r->oriented));
    if (r->misoriented_edges)
        printf(" (%d edge%s run the same way by both triangles)", r->misoriented_edges,
               r->misoriented_edges == 1 ? "" : "s");
    printf("\nself-intersections: %s\n",
           r->self_intersections < 0 ? "not checked" : r->self_intersections ? "yes" : "none");
    printf("bounds a volume: %s\n", yes_no(r->bounds_volume));
    printf("outward: %s\n", yes_no(r->outward));
    if (isnan(r->volume))
        printf("volume: not checked\n");
    else
        printf("volume: %.15g\n", r->volume);
    printf("result: %s\n", cb_mesh_check_passed(r) ? "pass" : "FAIL");
}

int cb_cli_check(int argc, char **argv)
{
    const char *path = NULL;
    int json = 0;
    for (int k = 1; k < argc; k++) {
        if (!strcmp(argv[k], "--help")) {
            fputs(CHECK_USAGE, stdout);
            return 0;
        }
        if (!strcmp(argv[k], "--json")) {
            json = 1;
        } else if (argv[k][0] == '-' || path) {
            fputs(CHECK_USAGE, stderr);
            return 2;
        } else {
            path = argv[k];
        }
    }
    if (!path) {
        fputs(CHECK_USAGE, stderr);
        return 2;
    }
    cb_error err;
    cb_error_clear(&err);
    cb_mesh_t mesh;
    cb_mesh_init(mesh);
    cb_status rs = cb_mesh_read(mesh, path, &err);
    if (rs) {
        fprintf(stderr, "colibri: %s\n", err.msg);
        return cb_cli_input_exit(rs);
    }
    cb_mesh_check_report r;
    cb_status st = cb_mesh_check(&r, mesh, &err);
    cb_mesh_clear(mesh);
    if (st) {
        fprintf(stderr, "colibri: %s: %s\n", path, err.msg);
        return 1;
    }
    if (json)
        print_json(path, &r);
    else
        print_text(path, &r);
    return cb_mesh_check_passed(&r) ? 0 : 1;
}
