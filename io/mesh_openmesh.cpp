// OpenMesh's mesh file readers and writers behind the C interface of mesh_openmesh.h.
//
// The readers and writers talk to a mesh through OpenMesh's BaseImporter and BaseExporter
// interfaces; implementing those over cb_mesh directly (instead of going through an OpenMesh
// halfedge mesh) keeps faces exactly as given: a halfedge mesh would refuse or split
// non-manifold faces, which the mesh checks must see. Nothing but points and faces is
// exchanged, and OpenMesh 9.0's writers and readers of these formats pass points as floats
// whatever the interface offers (see io/mesh.h). No C++ type or exception crosses into C.
extern "C" {
#include "io/mesh_openmesh.h"
}

#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/IO/exporter/BaseExporter.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <OpenMesh/Core/System/omstream.hh>

namespace {

using OpenMesh::EdgeHandle;
using OpenMesh::FaceHandle;
using OpenMesh::HalfedgeHandle;
using OpenMesh::Vec2f;
using OpenMesh::Vec3d;
using OpenMesh::Vec3f;
using OpenMesh::Vec3uc;
using OpenMesh::Vec3ui;
using OpenMesh::Vec4f;
using OpenMesh::Vec4uc;
using OpenMesh::Vec4ui;
using OpenMesh::VertexHandle;
using Status = OpenMesh::Attributes::StatusInfo;

// Catches what OpenMesh writes to std::cerr (where its error stream goes) in a string and
// mutes its log for the lifetime of the guard, so a failure reaches the caller inside cb_error
// instead of on the terminal. std::cerr's buffer is swapped rather than OpenMesh's stream
// reconnected: OpenMesh 9.0 leaks the target object of every disconnect.
class QuietOpenMesh {
public:
    QuietOpenMesh()
        : cerr_buf_(std::cerr.rdbuf(text_.rdbuf())), log_on_(::omlog().is_enabled()),
          out_on_(::omout().is_enabled())
    {
        ::omlog().disable();
        ::omout().disable();
    }
    ~QuietOpenMesh()
    {
        ::omerr().flush();
        std::cerr.rdbuf(cerr_buf_);
        if (log_on_)
            ::omlog().enable();
        if (out_on_)
            ::omout().enable();
    }
    QuietOpenMesh(const QuietOpenMesh &) = delete;
    QuietOpenMesh &operator=(const QuietOpenMesh &) = delete;

    // What OpenMesh reported so far, on one line ("" when nothing).
    std::string text()
    {
        ::omerr().flush();
        std::string s = text_.str();
        for (char &c : s)
            if (c == '\n' || c == '\r')
                c = ' ';
        while (!s.empty() && s.back() == ' ')
            s.pop_back();
        return s;
    }

private:
    std::ostringstream text_;
    std::streambuf *cerr_buf_;
    bool log_on_, out_on_;
};

// The points and faces of a cb_mesh as OpenMesh's writers ask for them.
class Exporter : public OpenMesh::IO::BaseExporter {
public:
    explicit Exporter(const cb_mesh_struct *m) : m_(m) {}

    Vec3f point(VertexHandle v) const override { return Vec3f(pointd(v)); }
    Vec3d pointd(VertexHandle v) const override
    {
        const double *p = m_->xyz + 3 * (size_t)v.idx();
        return Vec3d(p[0], p[1], p[2]);
    }
    bool is_point_double() const override { return true; }
    unsigned int get_vhandles(FaceHandle f, std::vector<VertexHandle> &vh) const override
    {
        const int *t = m_->tri + 3 * (size_t)f.idx();
        vh.assign({VertexHandle(t[0]), VertexHandle(t[1]), VertexHandle(t[2])});
        return 3;
    }
    // STL stores a facet normal: the unit normal of the triangle's own winding.
    Vec3d normald(FaceHandle f) const override
    {
        std::vector<VertexHandle> vh;
        get_vhandles(f, vh);
        Vec3d a = pointd(vh[0]), n = OpenMesh::cross(pointd(vh[1]) - a, pointd(vh[2]) - a);
        double len = n.norm();
        return len > 0 ? n / len : Vec3d(0, 0, 0);
    }
    Vec3f normal(FaceHandle f) const override { return Vec3f(normald(f)); }
    bool has_face_normals() const override { return true; }
    bool is_triangle_mesh() const override { return true; }
    size_t n_vertices() const override { return (size_t)m_->n_vertices; }
    size_t n_faces() const override { return (size_t)m_->n_triangles; }
    // Only the OpenMesh format (.om), which is not offered, reads edges or halfedges.
    size_t n_edges() const override { return 0; }
    int get_halfedge_id(VertexHandle) override { return -1; }
    int get_halfedge_id(FaceHandle) override { return -1; }
    int get_next_halfedge_id(HalfedgeHandle) override { return -1; }
    int get_to_vertex_id(HalfedgeHandle) override { return -1; }
    int get_face_id(HalfedgeHandle) override { return -1; }
    HalfedgeHandle getHeh(FaceHandle, VertexHandle) const override { return HalfedgeHandle(); }
    // The PLY writer looks for custom properties in the kernel without checking for null;
    // an empty kernel has none.
    const OpenMesh::BaseKernel *kernel() override { return &no_properties_; }

    // Attributes a cb_mesh does not have; the has_* queries say so, and the writers only ask
    // when an option requests them.
    Vec3f normal(VertexHandle) const override { return Vec3f(0, 0, 0); }
    Vec3d normald(VertexHandle) const override { return Vec3d(0, 0, 0); }
    bool is_normal_double() const override { return true; }
    Vec3uc color(VertexHandle) const override { return Vec3uc(0, 0, 0); }
    Vec4uc colorA(VertexHandle) const override { return Vec4uc(0, 0, 0, 0); }
    Vec3ui colori(VertexHandle) const override { return Vec3ui(0, 0, 0); }
    Vec4ui colorAi(VertexHandle) const override { return Vec4ui(0, 0, 0, 0); }
    Vec3f colorf(VertexHandle) const override { return Vec3f(0, 0, 0); }
    Vec4f colorAf(VertexHandle) const override { return Vec4f(0, 0, 0, 0); }
    Vec2f texcoord(VertexHandle) const override { return Vec2f(0, 0); }
    Vec2f texcoord(HalfedgeHandle) const override { return Vec2f(0, 0); }
    Status status(VertexHandle) const override { return Status(); }
    unsigned int get_face_texcoords(std::vector<Vec2f> &tc) const override
    {
        tc.clear();
        return 0;
    }
    Vec3uc color(FaceHandle) const override { return Vec3uc(0, 0, 0); }
    Vec4uc colorA(FaceHandle) const override { return Vec4uc(0, 0, 0, 0); }
    Vec3ui colori(FaceHandle) const override { return Vec3ui(0, 0, 0); }
    Vec4ui colorAi(FaceHandle) const override { return Vec4ui(0, 0, 0, 0); }
    Vec3f colorf(FaceHandle) const override { return Vec3f(0, 0, 0); }
    Vec4f colorAf(FaceHandle) const override { return Vec4f(0, 0, 0, 0); }
    Status status(FaceHandle) const override { return Status(); }
    Vec3uc color(EdgeHandle) const override { return Vec3uc(0, 0, 0); }
    Vec4uc colorA(EdgeHandle) const override { return Vec4uc(0, 0, 0, 0); }
    Vec3ui colori(EdgeHandle) const override { return Vec3ui(0, 0, 0); }
    Vec4ui colorAi(EdgeHandle) const override { return Vec4ui(0, 0, 0, 0); }
    Vec3f colorf(EdgeHandle) const override { return Vec3f(0, 0, 0); }
    Vec4f colorAf(EdgeHandle) const override { return Vec4f(0, 0, 0, 0); }
    Status status(EdgeHandle) const override { return Status(); }
    Status status(HalfedgeHandle) const override { return Status(); }

private:
    const cb_mesh_struct *m_;
    OpenMesh::BaseKernel no_properties_;
};

// Builds a cb_mesh from what OpenMesh's readers hand over. The first problem is kept in err_
// and everything after it ignored, since a reader cannot be stopped midway.
class Importer : public OpenMesh::IO::BaseImporter {
public:
    explicit Importer(cb_mesh_struct *m) : m_(m) { cb_error_clear(&err_); }

    const cb_error &error() const { return err_; }

    VertexHandle add_vertex(const Vec3f &p) override { return add_vertex(Vec3d(p)); }
    VertexHandle add_vertex(const Vec3d &p) override
    {
        double q[3] = {p[0], p[1], p[2]};
        if (err_.status)
            return VertexHandle();
        if (cb_status st = cb_mesh_append_vertex(m_, q, &err_)) {
            if (st == CB_ERR_INVALID)
                err_.status = CB_ERR_PARSE;
            return VertexHandle();
        }
        return VertexHandle(m_->n_vertices - 1);
    }
    VertexHandle add_vertex() override { return add_vertex(Vec3d(0, 0, 0)); }
    void set_point(VertexHandle v, const Vec3f &p) override
    {
        if (v.idx() >= 0 && v.idx() < m_->n_vertices)
            for (int k = 0; k < 3; k++)
                m_->xyz[3 * (size_t)v.idx() + k] = p[k];
    }
    FaceHandle add_face(const VHandles &vh) override
    {
        int face = faces_++;
        if (err_.status)
            return FaceHandle();
        if (vh.size() != 3) {
            cb_error_set(&err_, CB_ERR_UNSUPPORTED,
                         "face %d has %zu vertices; only triangle meshes are read", face,
                         vh.size());
            return FaceHandle();
        }
        if (cb_mesh_append_triangle(m_, vh[0].idx(), vh[1].idx(), vh[2].idx(), &err_)) {
            err_.status = CB_ERR_PARSE;
            cb_error_prefix(&err_, "face %d: ", face);
            return FaceHandle();
        }
        return FaceHandle(m_->n_triangles - 1);
    }
    size_t n_vertices() const override { return (size_t)m_->n_vertices; }
    size_t n_faces() const override { return (size_t)m_->n_triangles; }
    // Edges are not stored: a triangle soup has none until the checks derive them.
    size_t n_edges() const override { return 0; }

    // Topology by halfedges comes from the OpenMesh format (.om) only, which is not offered;
    // attributes (normals, colours, texture coordinates, status) are not kept.
    HalfedgeHandle add_edge(VertexHandle, VertexHandle) override { return HalfedgeHandle(); }
    FaceHandle add_face(HalfedgeHandle) override { return FaceHandle(); }
    void set_halfedge(VertexHandle, HalfedgeHandle) override {}
    void set_next(HalfedgeHandle, HalfedgeHandle) override {}
    void set_face(HalfedgeHandle, FaceHandle) override {}
    void add_face_texcoords(FaceHandle, VertexHandle, const std::vector<Vec2f> &) override {}
    void add_face_texcoords(FaceHandle, VertexHandle, const std::vector<Vec3f> &) override {}
    void set_face_texindex(FaceHandle, int) override {}
    void set_normal(VertexHandle, const Vec3f &) override {}
    void set_normal(VertexHandle, const Vec3d &) override {}
    void set_color(VertexHandle, const Vec3uc &) override {}
    void set_color(VertexHandle, const Vec4uc &) override {}
    void set_color(VertexHandle, const Vec3f &) override {}
    void set_color(VertexHandle, const Vec4f &) override {}
    void set_texcoord(VertexHandle, const Vec2f &) override {}
    void set_status(VertexHandle, const Status &) override {}
    void request_face_texcoords2D() override {}
    void set_texcoord(HalfedgeHandle, const Vec2f &) override {}
    void set_texcoord(VertexHandle, const Vec3f &) override {}
    void set_texcoord(HalfedgeHandle, const Vec3f &) override {}
    void set_status(HalfedgeHandle, const Status &) override {}
    void set_color(EdgeHandle, const Vec3uc &) override {}
    void set_color(EdgeHandle, const Vec4uc &) override {}
    void set_color(EdgeHandle, const Vec3f &) override {}
    void set_color(EdgeHandle, const Vec4f &) override {}
    void set_status(EdgeHandle, const Status &) override {}
    void set_normal(FaceHandle, const Vec3f &) override {}
    void set_normal(FaceHandle, const Vec3d &) override {}
    void set_color(FaceHandle, const Vec3uc &) override {}
    void set_color(FaceHandle, const Vec4uc &) override {}
    void set_color(FaceHandle, const Vec3f &) override {}
    void set_color(FaceHandle, const Vec4f &) override {}
    void set_status(FaceHandle, const Status &) override {}
    void add_texture_information(int, std::string) override {}

private:
    cb_mesh_struct *m_;
    cb_error err_;
    int faces_ = 0;
};

} // namespace

extern "C" cb_status cb_mesh_openmesh_write(const char *path, const cb_mesh_t mesh,
                                            int stl_binary, cb_error *err)
{
    try {
        QuietOpenMesh quiet;
        Exporter ex(mesh);
        OpenMesh::IO::Options opt(stl_binary ? OpenMesh::IO::Options::Binary
                                             : OpenMesh::IO::Options::Default);
        if (!OpenMesh::IO::IOManager().write(path, ex, opt, 17)) {
            std::string why = quiet.text();
            return cb_error_set(err, CB_ERR_IO, "%s: OpenMesh could not write the mesh%s%s",
                                path, why.empty() ? "" : ": ", why.c_str());
        }
    } catch (const std::bad_alloc &) {
        return cb_error_set(err, CB_ERR_NOMEM, "%s: out of memory while writing", path);
    } catch (const std::exception &e) {
        return cb_error_set(err, CB_ERR_IO, "%s: OpenMesh failed while writing: %s", path,
                            e.what());
    } catch (...) {
        return cb_error_set(err, CB_ERR_IO, "%s: OpenMesh failed while writing", path);
    }
    return CB_OK;
}

extern "C" cb_status cb_mesh_openmesh_read(cb_mesh_t mesh, const char *path, cb_error *err)
{
    try {
        QuietOpenMesh quiet;
        Importer im(mesh);
        OpenMesh::IO::Options opt;
        bool ok = OpenMesh::IO::IOManager().read(path, im, opt);
        if (im.error().status) {
            cb_error_set(err, im.error().status, "%s", im.error().msg);
            return cb_error_prefix(err, "%s: ", path);
        }
        if (!ok) {
            std::string why = quiet.text();
            return cb_error_set(err, CB_ERR_PARSE, "%s: OpenMesh could not read the file%s%s",
                                path, why.empty() ? "" : ": ", why.c_str());
        }
    } catch (const std::bad_alloc &) {
        return cb_error_set(err, CB_ERR_NOMEM, "%s: out of memory while reading", path);
    } catch (const std::exception &e) {
        return cb_error_set(err, CB_ERR_PARSE, "%s: OpenMesh failed while reading: %s", path,
                            e.what());
    } catch (...) {
        return cb_error_set(err, CB_ERR_PARSE, "%s: OpenMesh failed while reading", path);
    }
    return CB_OK;
}
