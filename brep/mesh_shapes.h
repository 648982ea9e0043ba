/* mesh_shapes.h — closed, outward-oriented triangle meshes of simple solids with known volumes:
 * references for tests and benchmarks of tessellation, mesh files and mesh checks.
 *
 * Each function replaces the contents of m; on failure (CB_ERR_INVALID for bad sizes,
 * CB_ERR_NOMEM) m is empty. Vertices are shared: every mesh is closed and manifold. */
#ifndef CB_MESH_SHAPES_H
#define CB_MESH_SHAPES_H

#include "brep/mesh.h"
#include "brep/status.h"

/* The tetrahedron with vertices p[0..3], oriented outward (p[3] may lie on either side of the
 * plane of the others, but not on it); volume |det(p1-p0, p2-p0, p3-p0)| / 6. */
cb_status cb_mesh_tetrahedron(cb_mesh_t m, const double p[4][3], cb_error *err);

/* The box [lo, hi] (lo < hi in every axis): 8 vertices, 12 triangles. */
cb_status cb_mesh_box(cb_mesh_t m, const double lo[3], const double hi[3], cb_error *err);

/* The sphere of centre c and radius r > 0 approximated by an icosahedron whose triangles are
 * split in four, with the new vertices pushed onto the sphere, `level` times (0 <= level <= 10):
 * 10 * 4^level + 2 vertices, 20 * 4^level triangles, all vertices on the sphere. The volume
 * approaches 4/3 pi r^3 from below, its error shrinking about 4 times per level. */
cb_status cb_mesh_icosphere(cb_mesh_t m, const double c[3], double r, int level, cb_error *err);

/* The torus around the z axis through c with major radius R and minor radius r (0 < r < R),
 * sampled at nu angles around the axis and nv around the tube (each >= 3): nu * nv vertices,
 * 2 nu nv triangles. Volume 2 pi^2 R r^2 in the limit. */
cb_status cb_mesh_torus(cb_mesh_t m, const double c[3], double R, double r, int nu, int nv,
                        cb_error *err);

#endif
