/* mesh.h — triangle meshes: the output of tessellation and the input of mesh files and checks.
 *
 * A mesh is a soup of vertices (double coordinates) and triangles (three vertex indices each,
 * counter-clockwise seen from outside for a solid). Nothing here requires the mesh to be closed
 * or manifold: the checks of mesh_check.h say whether it is. Triangles always hold three
 * distinct vertex indices in range; the functions that add them refuse anything else. */
#ifndef CB_MESH_H
#define CB_MESH_H

#include "brep/bbox.h"
#include "brep/status.h"

typedef struct {
    double *xyz;     /* n_vertices points (x, y, z) */
    int *tri;        /* n_triangles index triples into the points */
    int n_vertices, n_triangles;
    int cap_vertices, cap_triangles; /* allocated sizes, in points and triangles */
} cb_mesh_struct;
typedef cb_mesh_struct cb_mesh_t[1];

/* An empty mesh that owns no memory. */
void cb_mesh_init(cb_mesh_t m);

/* Frees the arrays; m is an empty mesh again and may be reused. */
void cb_mesh_clear(cb_mesh_t m);

/* Makes room for at least nv points and nt triangles in total, so that appending them cannot
 * fail. CB_ERR_NOMEM when the allocation fails (m is unchanged), CB_ERR_INVALID for negative
 * sizes. */
cb_status cb_mesh_reserve(cb_mesh_t m, int nv, int nt, cb_error *err);

/* Appends the point p (finite coordinates) as vertex n_vertices. CB_ERR_INVALID for a
 * non-finite coordinate, CB_ERR_NOMEM when growing fails. */
cb_status cb_mesh_append_vertex(cb_mesh_t m, const double p[3], cb_error *err);

/* Appends the triangle (a, b, c). CB_ERR_INVALID, naming the triangle, unless the indices are
 * distinct vertices of m; CB_ERR_NOMEM when growing fails. */
cb_status cb_mesh_append_triangle(cb_mesh_t m, int a, int b, int c, cb_error *err);

/* Appends every vertex and triangle of src to dst (src's indices shifted past dst's vertices);
 * no vertex is shared between the two parts until cb_mesh_merge_vertices. src may not be dst. */
cb_status cb_mesh_append(cb_mesh_t dst, const cb_mesh_t src, cb_error *err);

/* Signed volume by the divergence theorem: the sum over triangles of the signed volume of the
 * tetrahedron (c, p0, p1, p2), where c is the centre of the bounding box (taken instead of the
 * origin so that a mesh far from the origin loses no digits to cancellation). Positive for a
 * closed outward-oriented mesh, negative when inward; for an open mesh it depends on c. */
double cb_mesh_volume(const cb_mesh_t m);

/* Sum of the triangle areas. */
double cb_mesh_area(const cb_mesh_t m);

/* Exact bounds of all vertices, referenced or not (the empty box for no vertices). */
void cb_mesh_bbox(cb_aabb *box, const cb_mesh_t m);

/* Merges vertices closer than tol: vertices whose distance is <= tol are joined, transitively
 * (a chain of close vertices becomes one), and a merged group keeps the coordinates of its
 * lowest-indexed vertex. tol = 0 merges exactly equal points only. Surviving vertices keep
 * their relative order; triangles that lose a corner to the merge are removed and their number
 * stored in *collapsed (if non-NULL). Method: vertices are bucketed in a grid of cell size tol,
 * sorted by cell, and each is compared with the vertices of the 27 cells around it.
 * CB_ERR_INVALID for tol < 0, non-finite, or so small against the mesh size that the grid's
 * cell indices would not fit in 62 bits; CB_ERR_NOMEM. m is unchanged on failure. */
cb_status cb_mesh_merge_vertices(cb_mesh_t m, double tol, int *collapsed, cb_error *err);

#endif
