// CGAL's Polygon Mesh Processing checks behind the C interface of tess_check_cgal.h.
// CGAL checks meshes here; it never makes or repairs them. No C++ type or exception crosses.
// GCC 12 reports a maybe-uninitialized temporary inside CGAL's Epic_converter (the static
// filters of the exact-constructions kernel) in the sanitizer build's optimisation; the
// temporary is a default-constructed triangle returned with "false" and never read. (Clang,
// which builds the fuzz targets, has no such warning and rejects the name.)
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

extern "C" {
#include "brep/tess_check_cgal.h"
}

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <iterator>
#include <new>
#include <utility>
#include <vector>

#include <CGAL/Cartesian_converter.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
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

// The mesh as CGAL's polygon soup: its points and its triangles' corner indices.
void read_soup(std::vector<Point> &points, std::vector<std::array<std::size_t, 3>> &triangles,
               const cb_mesh_struct *m)
{
    points.reserve((size_t)m->n_vertices);
    for (size_t v = 0; v < (size_t)m->n_vertices; v++)
        points.emplace_back(m->xyz[3 * v], m->xyz[3 * v + 1], m->xyz[3 * v + 2]);
    triangles.resize((size_t)m->n_triangles);
    for (size_t f = 0; f < triangles.size(); f++)
        for (int k = 0; k < 3; k++)
            triangles[f][k] = (std::size_t)m->tri[3 * f + k];
}

cb_status check(cb_mesh_check_report *r, const cb_mesh_struct *m, cb_error *err)
{
    std::vector<Point> points;
    std::vector<std::array<std::size_t, 3>> triangles;
    read_soup(points, triangles, m);
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

// The contacts are constructed exactly: two triangles that touch along an edge are nearly
// coplanar there, where floating-point constructions break down.
using Exact = CGAL::Exact_predicates_exact_constructions_kernel;
using To_exact = CGAL::Cartesian_converter<Kernel, Exact>;
using Face = Mesh::Face_index;

// Distance from p to the nearest edge of t.
double boundary_distance(const Exact::Triangle_3 &t, const Exact::Point_3 &p)
{
    double d2 = HUGE_VAL;
    for (int k = 0; k < 3; k++)
        d2 = std::min(d2, CGAL::to_double(CGAL::squared_distance(
                              p, Exact::Segment_3(t.vertex(k), t.vertex((k + 1) % 3)))));
    return std::sqrt(d2);
}

struct Contacts {
    const Mesh &mesh;
    double eps;
    To_exact exact;

    Exact::Triangle_3 triangle(Face f) const
    {
        auto h = mesh.halfedge(f);
        return exact(Kernel::Triangle_3(mesh.point(mesh.source(h)), mesh.point(mesh.target(h)),
                                        mesh.point(mesh.target(mesh.next(h)))));
    }

    // The triangles of `rest` around the points `at` (its corners within eps of them, or
    // else those of its edge nearest them) all lie on one side of the plane of `other`
    // (exact orientations; points in the plane count for either side): near the contact,
    // rest's surface stays on one side of other's instead of passing through it.
    bool one_side(Face rest, Face other, const std::vector<Exact::Point_3> &at) const
    {
        auto h0 = mesh.halfedge(other);
        const Point &o0 = mesh.point(mesh.source(h0)), &o1 = mesh.point(mesh.target(h0)),
                    &o2 = mesh.point(mesh.target(mesh.next(h0)));
        std::vector<Mesh::Halfedge_index> corners;
        for (auto h : CGAL::halfedges_around_face(mesh.halfedge(rest), mesh))
            for (const Exact::Point_3 &p : at)
                if (std::sqrt(CGAL::to_double(CGAL::squared_distance(
                        exact(mesh.point(mesh.target(h))), p))) <= eps) {
                    corners.push_back(h);
                    break;
                }
        if (corners.empty()) {
            // The contact lies inside an edge of rest: that edge's two ends.
            double best = HUGE_VAL;
            for (auto h : CGAL::halfedges_around_face(mesh.halfedge(rest), mesh)) {
                Exact::Segment_3 e(exact(mesh.point(mesh.source(h))),
                                   exact(mesh.point(mesh.target(h))));
                double d = 0;
                for (const Exact::Point_3 &p : at)
                    d = std::max(d, CGAL::to_double(CGAL::squared_distance(e, p)));
                if (d < best) {
                    best = d;
                    corners = {h, mesh.prev(h)};
                }
            }
        }
        int below = 0, above = 0;
        for (auto c : corners)
            for (Face f : CGAL::faces_around_target(c, mesh)) {
                if (f == Mesh::null_face())
                    continue;
                for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
                    CGAL::Orientation o = CGAL::orientation(o0, o1, o2, mesh.point(v));
                    below |= o == CGAL::NEGATIVE;
                    above |= o == CGAL::POSITIVE;
                }
            }
        return !(below && above);
    }

    // Two intersecting triangles touch when their intersection (constructed exactly; a point,
    // a segment, or a coplanar overlap) lies on the boundary of both — checked at its corners
    // and the midpoints of its sides, so that a segment across the inside of either or an
    // overlap of positive area is caught — or on the boundary of one that, around it, stays on
    // one side of the other's plane.
    bool touch(Face fa, Face fb) const
    {
        Exact::Triangle_3 a = triangle(fa), b = triangle(fb);
        if (fa == fb || a.is_degenerate() || b.is_degenerate())
            return false;
        auto x = CGAL::intersection(a, b);
        if (!x)
            return false;
        std::vector<Exact::Point_3> corners;
        if (const Exact::Point_3 *p = boost::get<Exact::Point_3>(&*x))
            corners.push_back(*p);
        else if (const Exact::Segment_3 *g = boost::get<Exact::Segment_3>(&*x))
            corners = {g->source(), g->target()};
        else
            return false; // coplanar overlap: one surface lies on the other
        std::vector<Exact::Point_3> probes = corners;
        if (corners.size() == 2)
            probes.push_back(CGAL::midpoint(corners[0], corners[1]));
        bool on_a = true, on_b = true;
        for (const Exact::Point_3 &p : probes) {
            on_a = on_a && boundary_distance(a, p) <= eps;
            on_b = on_b && boundary_distance(b, p) <= eps;
        }
        if (on_a && on_b)
            return true;
        if (on_a && one_side(fa, fb, corners))
            return true;
        if (on_b && one_side(fb, fa, corners))
            return true;
        return shallow(a, b) || shallow(b, a);
    }

    // The corners of a on the lesser side of b's plane lie within eps of it: moving them by
    // at most eps onto the plane undoes the crossing. Where two surfaces touch, they lie
    // within the tolerance of each other over a band round the contact, and their meshes
    // may cross there by that much; a crossing of surfaces at an angle cuts through the
    // inside of triangles, far deeper.
    bool shallow(const Exact::Triangle_3 &a, const Exact::Triangle_3 &b) const
    {
        Exact::Plane_3 pb = b.supporting_plane();
        double above = 0, below = 0;
        for (int k = 0; k < 3; k++) {
            double d = std::sqrt(CGAL::to_double(CGAL::squared_distance(pb, a.vertex(k))));
            switch (pb.oriented_side(a.vertex(k))) {
            case CGAL::ON_POSITIVE_SIDE: above = std::max(above, d); break;
            case CGAL::ON_NEGATIVE_SIDE: below = std::max(below, d); break;
            default: break;
            }
        }
        return std::min(above, below) <= eps;
    }
};

cb_status contacts(int *touching, int *crossing, std::vector<int> *pairs_out,
                   const cb_mesh_struct *m, double eps, cb_error *err)
{
    std::vector<Point> points;
    std::vector<std::array<std::size_t, 3>> triangles;
    read_soup(points, triangles, m);
    // One copy of a vertex per fan of triangles around it (the caller checked the orientation,
    // so nothing is turned): where parts of the surface meet at a point they become separate
    // there, and their meeting is then a contact between triangles like any other.
    PMP::orient_polygon_soup(points, triangles);
    if (!PMP::is_polygon_soup_a_polygon_mesh(triangles))
        return cb_error_set(err, CB_ERR_INVALID,
                            "mesh contacts: CGAL does not accept the mesh as a polygon mesh");
    Mesh mesh;
    PMP::polygon_soup_to_polygon_mesh(points, triangles, mesh);
    // Faces are made in the soup's order (orienting turns polygons, never reorders them), so
    // a face's index is the triangle's.
    if (mesh.number_of_faces() != triangles.size())
        return cb_error_set(err, CB_ERR_INVALID,
                            "mesh contacts: CGAL made %zu faces of %zu triangles",
                            (size_t)mesh.number_of_faces(), triangles.size());
    std::vector<std::pair<Face, Face>> pairs;
    PMP::self_intersections(mesh, std::back_inserter(pairs));
    Contacts c{mesh, eps, To_exact()};
    *touching = *crossing = 0;
    for (const auto &fp : pairs) {
        bool t = c.touch(fp.first, fp.second);
        ++*(t ? touching : crossing);
        if (!t && pairs_out) {
            int a = (int)(std::size_t)fp.first, b = (int)(std::size_t)fp.second;
            pairs_out->push_back(std::min(a, b));
            pairs_out->push_back(std::max(a, b));
        }
    }
    return CB_OK;
}

} // namespace

extern "C" cb_status cb_tess_check_cgal_contacts(int *touching, int *crossing,
                                                 int **crossing_pairs, const cb_mesh_t m,
                                                 double eps, cb_error *err)
{
    try {
        if (!crossing_pairs)
            return contacts(touching, crossing, nullptr, m, eps, err);
        *crossing_pairs = nullptr;
        std::vector<int> pairs;
        cb_status st = contacts(touching, crossing, &pairs, m, eps, err);
        if (st || pairs.empty())
            return st;
        *crossing_pairs = static_cast<int *>(std::malloc(pairs.size() * sizeof(int)));
        if (!*crossing_pairs)
            return cb_error_set(err, CB_ERR_NOMEM, "mesh contacts: out of memory");
        std::copy(pairs.begin(), pairs.end(), *crossing_pairs);
        return CB_OK;
    } catch (const std::bad_alloc &) {
        return cb_error_set(err, CB_ERR_NOMEM, "mesh contacts: out of memory in CGAL");
    } catch (const std::exception &e) {
        return cb_error_set(err, CB_ERR_NUMERIC, "mesh contacts: CGAL failed: %s", e.what());
    } catch (...) {
        return cb_error_set(err, CB_ERR_NUMERIC, "mesh contacts: CGAL failed");
    }
}

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
