// CGAL's Polygon Mesh Processing checks behind the C interface of tess_check_cgal.h.
// CGAL checks meshes here; it never makes or repairs them. No C++ type or exception crosses.
extern "C" {
#include "brep/tess_check_cgal.h"
}

#include <array>
#include <exception>
#include <new>
#include <vector>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/helpers.h>

namespace {

// Exact predicates decide intersections and orientation exactly on the double coordinates;
// only the volume is a floating-point sum.
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
namespace PMP = CGAL::Polygon_mesh_processing;

cb_status check(cb_mesh_check_report *r, const cb_mesh_struct *m, cb_error *err)
{
    std::vector<Point> points;
    points.reserve((size_t)m->n_vertices);
    for (size_t v = 0; v < (size_t)m->n_vertices; v++)
        points.emplace_back(m->xyz[3 * v], m->xyz[3 * v + 1], m->xyz[3 * v + 2]);
    std::vector<std::array<std::size_t, 3>> triangles((size_t)m->n_triangles);
    for (size_t f = 0; f < triangles.size(); f++)
        for (int k = 0; k < 3; k++)
            triangles[f][k] = (std::size_t)m->tri[3 * f + k];
    if (!PMP::is_polygon_soup_a_polygon_mesh(triangles))
        return cb_error_set(err, CB_ERR_INVALID,
                            "mesh check: CGAL does not accept the mesh as a polygon mesh");
    Mesh mesh;
    PMP::polygon_soup_to_polygon_mesh(points, triangles, mesh);
    r->triangle_mesh = CGAL::is_triangle_mesh(mesh);
    r->self_intersections = PMP::does_self_intersect(mesh);
    if (!r->closed || r->self_intersections)
        return CB_OK;
    r->bounds_volume = PMP::does_bound_a_volume(mesh);
    r->outward = PMP::is_outward_oriented(mesh);
    // PMP::volume sums tetrahedra on the origin: far from it they cancel to a few digits. The
    // same points moved next to the origin (by the centre of their box: a translation, exact
    // for a closed mesh) keep them; the exact predicates above saw the points as given.
    CGAL::Bbox_3 box = CGAL::bbox_3(points.begin(), points.end());
    Kernel::Vector_3 centre((box.xmin() + box.xmax()) / 2, (box.ymin() + box.ymax()) / 2,
                            (box.zmin() + box.zmax()) / 2);
    auto local = mesh.add_property_map<Mesh::Vertex_index, Point>("v:colibri_local").first;
    for (Mesh::Vertex_index v : mesh.vertices())
        local[v] = mesh.point(v) - centre;
    r->volume = CGAL::to_double(PMP::volume(mesh, CGAL::parameters::vertex_point_map(local)));
    return CB_OK;
}

} // namespace

extern "C" cb_status cb_tess_check_cgal(cb_mesh_check_report *r, const cb_mesh_t m, cb_error *err)
{
    try {
        return check(r, m, err);
    } catch (const std::bad_alloc &) {
        return cb_error_set(err, CB_ERR_NOMEM, "mesh check: out of memory in CGAL");
    } catch (const std::exception &e) {
        return cb_error_set(err, CB_ERR_NUMERIC, "mesh check: CGAL failed: %s", e.what());
    } catch (...) {
        return cb_error_set(err, CB_ERR_NUMERIC, "mesh check: CGAL failed");
    }
}
