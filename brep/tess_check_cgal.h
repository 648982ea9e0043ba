/* tess_check_cgal.h — CGAL's Polygon Mesh Processing checks behind a C interface (internal to
 * brep; users call mesh_check.h). Implemented in tess_check_cgal.cpp; no C++ type or exception
 * crosses it. */
#ifndef CB_TESS_CHECK_CGAL_H
#define CB_TESS_CHECK_CGAL_H

#include "brep/mesh_check.h"

/* Builds a CGAL Surface_mesh from m, which the caller has found edge- and vertex-manifold and
 * consistently oriented (r->closed set), and fills r->triangle_mesh and r->self_intersections;
 * when r->closed and no self-intersection, also r->bounds_volume, r->outward and r->volume.
 * CB_ERR_INVALID if CGAL does not accept m as a polygon mesh, CB_ERR_NOMEM, CB_ERR_NUMERIC
 * with CGAL's message when it throws. */
cb_status cb_tess_check_cgal(cb_mesh_check_report *r, const cb_mesh_t m, cb_error *err);

/* Counts the pairs of triangles of m that CGAL finds intersecting (exact predicates), after
 * giving each fan of triangles around a vertex its own copy of it, as touching or crossing
 * (cb_mesh_check_contacts). With crossing_pairs, also the crossing pairs: 2 * *crossing
 * triangle indices in a malloc'ed array (NULL when none; the caller frees it), in CGAL's
 * order. m is closed, edge-manifold and consistently oriented (the caller checked). Errors as
 * cb_tess_check_cgal. */
cb_status cb_tess_check_cgal_contacts(int *touching, int *crossing, int **crossing_pairs,
                                      const cb_mesh_t m, double eps, cb_error *err);

#endif
