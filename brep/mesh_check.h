/* mesh_check.h — is a triangle mesh the boundary of a solid? The checks users run on a
 * tessellation or a Boolean result before trusting it.
 *
 * Combinatorial checks (closed, edge- and vertex-manifold, consistently oriented) are made on
 * the triangle soup itself, so that they can describe meshes no halfedge structure can hold.
 * When the mesh passes them, it is turned into a CGAL Surface_mesh and CGAL's Polygon Mesh
 * Processing decides the geometric ones: self-intersections
 * (CGAL::Polygon_mesh_processing::does_self_intersect, exact predicates; a degenerate triangle
 * counts as self-intersecting), bounding a volume (does_bound_a_volume), outward orientation
 * (is_outward_oriented) and the enclosed volume (volume). The checks report; they never repair.
 *
 * A check whose preconditions fail is not run and reads -1 (volume: NaN): self-intersections
 * need a manifold, consistently oriented mesh; bounds_volume, outward and volume need in
 * addition a closed mesh without self-intersections. */
#ifndef CB_MESH_CHECK_H
#define CB_MESH_CHECK_H

#include "brep/mesh.h"
#include "brep/status.h"

typedef struct {
    int vertices, triangles;
    int closed;             /* every edge borders exactly two triangles (an empty mesh is not
                               closed: it bounds nothing) */
    int edge_manifold;      /* no edge borders more than two triangles */
    int vertex_manifold;    /* the triangles around each vertex are one fan, connected
                               through their edges at that vertex */
    int oriented;           /* each edge of two triangles is run in opposite directions by them */
    int triangle_mesh;      /* CGAL::is_triangle_mesh of the Surface_mesh built (-1: not built) */
    int self_intersections; /* 1 when two triangles meet other than in their shared edge or
                               vertex, or a triangle is degenerate */
    int bounds_volume;      /* CGAL: the mesh bounds a volume (nested parts oppositely oriented) */
    int outward;            /* CGAL: the outermost part is oriented outward */
    double volume;          /* CGAL's enclosed volume (negative when inward) */
    int boundary_edges;     /* edges of one triangle */
    int nonmanifold_edges;  /* edges of three or more triangles */
    int nonmanifold_vertices;  /* vertices whose triangles form two or more fans */
    int misoriented_edges;  /* edges of two triangles that run it the same way */
} cb_mesh_check_report;

/* Runs every check on m and fills r. Fails only for lack of memory (CB_ERR_NOMEM) or when CGAL
 * throws (CB_ERR_NUMERIC, with CGAL's message): a mesh that fails a check is reported, not an
 * error. */
cb_status cb_mesh_check(cb_mesh_check_report *r, const cb_mesh_t m, cb_error *err);

/* Where a closed mesh meets itself. The surface of a solid that touches itself, or of solids
 * that touch each other, along a curve or at a point (a union of operands in contact: the exact
 * result is no manifold there) meets itself without crossing: its mesh has vertices whose
 * triangles form several fans, or CGAL reports it self-intersecting, and both are also what a
 * wrong result looks like. This tells them apart. Each vertex is first given one copy per fan
 * of triangles around it; then every pair of triangles CGAL finds intersecting (exact
 * predicates, PMP::self_intersections) is
 *   touching: every point of their intersection lies within eps of an edge of each (checked
 *             at the corners of the intersection and the midpoints of its sides): they meet
 *             along their edges or at their corners; or it lies within eps of an edge of one
 *             whose triangles there stay on one side of the other's plane; or they cross by
 *             no more than eps: the corners of one on the lesser side of the other's plane
 *             lie within eps of it (two surfaces touching lie within the tolerance of each
 *             other over a band round the contact, where their meshes may cross by that
 *             much; surfaces crossing at an angle cut through the insides of triangles);
 *   crossing: otherwise: one cuts through the inside of the other, they overlap in a common
 *             plane, or a triangle is degenerate.
 * eps is a distance in the mesh's units: how far apart the mesh may carry one curve along which
 * two parts meet, and how far two touching parts may overlap (e.g. the B-rep's largest edge
 * tolerance). */
typedef struct {
    int touching, crossing; /* pairs of triangles */
} cb_mesh_contacts;

/* Fills c for m. CB_ERR_INVALID unless m is closed, edge-manifold and consistently oriented
 * (cb_mesh_check's closed and oriented), or eps is not positive and finite; otherwise errors as
 * cb_mesh_check. */
cb_status cb_mesh_check_contacts(cb_mesh_contacts *c, const cb_mesh_t m, double eps,
                                 cb_error *err);

/* The crossing pairs of cb_mesh_check_contacts themselves: triangles (*pairs)[2k] and
 * (*pairs)[2k + 1], k < *n_pairs, in a malloc'ed array the caller frees (NULL when none).
 * Errors as cb_mesh_check_contacts, with *pairs NULL and *n_pairs 0. */
cb_status cb_mesh_check_crossings(int **pairs, int *n_pairs, const cb_mesh_t m, double eps,
                                  cb_error *err);

/* 1 when r says the mesh is a closed, manifold, outward-oriented, self-intersection-free
 * triangle mesh bounding a volume, else 0. */
int cb_mesh_check_passed(const cb_mesh_check_report *r);

#endif
