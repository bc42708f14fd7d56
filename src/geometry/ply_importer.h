// The receiving end of OpenMesh's PLY reader: vertices, normals and uvs go straight into a
// TriangleMesh and each polygon becomes a triangle fan. No half-edge structure is built, so
// non-manifold meshes load as they are and faces keep their file order.
#pragma once

#include <OpenMesh/Core/IO/importer/BaseImporter.hh>

#include <algorithm>
#include <string>

#include "geometry/mesh.h"

namespace ml {

class PlyImporter final : public OpenMesh::IO::BaseImporter {
public:
    using VertexHandle = OpenMesh::VertexHandle;
    using FaceHandle = OpenMesh::FaceHandle;
    using HalfedgeHandle = OpenMesh::HalfedgeHandle;
    using EdgeHandle = OpenMesh::EdgeHandle;
    using Vec2f = OpenMesh::Vec2f;
    using Vec3f = OpenMesh::Vec3f;
    using Vec3d = OpenMesh::Vec3d;
    using Vec3uc = OpenMesh::Vec3uc;
    using Vec4uc = OpenMesh::Vec4uc;
    using Vec4f = OpenMesh::Vec4f;
    using Status = OpenMesh::Attributes::StatusInfo;

    // The validated header counts size the arrays once.
    PlyImporter(TriangleMesh& mesh, size_t vertices, size_t triangles) : m_mesh(mesh) {
        m_mesh.p.reserve(vertices);
        m_mesh.indices.reserve(3 * triangles);
    }
    size_t faces() const { return m_faces; }
    // Empty unless the reader handed us something inconsistent.
    const std::string& error() const { return m_error; }

    VertexHandle add_vertex(const Vec3f& p) override {
        m_mesh.p.emplace_back(p[0], p[1], p[2]);
        return VertexHandle(int(m_mesh.p.size() - 1));
    }
    VertexHandle add_vertex() override {
        m_mesh.p.emplace_back();
        return VertexHandle(int(m_mesh.p.size() - 1));
    }
    FaceHandle add_face(const VHandles& v) override {
        ++m_faces;
        if (v.size() < 3) return FaceHandle();
        for (const VertexHandle& h : v)
            if (h.idx() < 0 || size_t(h.idx()) >= m_mesh.p.size()) {
                if (m_error.empty())
                    m_error =
                        "face " + std::to_string(m_faces - 1) + " has a vertex index out of range";
                return FaceHandle();
            }
        for (size_t k = 1; k + 1 < v.size(); ++k) {
            m_mesh.indices.push_back(uint32_t(v[0].idx()));
            m_mesh.indices.push_back(uint32_t(v[k].idx()));
            m_mesh.indices.push_back(uint32_t(v[k + 1].idx()));
        }
        return FaceHandle(int(m_faces - 1));
    }
    void set_normal(VertexHandle h, const Vec3f& n) override {
        if (!valid(h)) return;
        if (size_t(h.idx()) >= m_mesh.n.size()) m_mesh.n.resize(arrays_size());
        m_mesh.n[h.idx()] = Vec3(n[0], n[1], n[2]);
    }
    void set_normal(VertexHandle h, const Vec3d& n) override { set_normal(h, Vec3f(n)); }
    void set_texcoord(VertexHandle h, const Vec2f& t) override {
        if (!valid(h)) return;
        if (size_t(h.idx()) >= m_mesh.uv.size()) m_mesh.uv.resize(arrays_size());
        m_mesh.uv[h.idx()] = Vec2(t[0], t[1]);
    }
    void set_point(VertexHandle h, const Vec3f& p) override {
        if (valid(h)) m_mesh.p[h.idx()] = Vec3(p[0], p[1], p[2]);
    }
    size_t n_vertices() const override { return m_mesh.p.size(); }
    size_t n_faces() const override { return m_faces; }
    size_t n_edges() const override { return 0; }

    // Everything else a PLY may carry (colours, status, face attributes) we do not use.
    HalfedgeHandle add_edge(VertexHandle, VertexHandle) override { return HalfedgeHandle(); }
    FaceHandle add_face(HalfedgeHandle) override { return FaceHandle(); }
    void add_face_texcoords(FaceHandle, VertexHandle, const std::vector<Vec2f>&) override {}
    void add_face_texcoords(FaceHandle, VertexHandle, const std::vector<Vec3f>&) override {}
    void set_face_texindex(FaceHandle, int) override {}
    void set_halfedge(VertexHandle, HalfedgeHandle) override {}
    void set_color(VertexHandle, const Vec3uc&) override {}
    void set_color(VertexHandle, const Vec4uc&) override {}
    void set_color(VertexHandle, const Vec3f&) override {}
    void set_color(VertexHandle, const Vec4f&) override {}
    void set_status(VertexHandle, const Status&) override {}
    void set_next(HalfedgeHandle, HalfedgeHandle) override {}
    void set_face(HalfedgeHandle, FaceHandle) override {}
    void request_face_texcoords2D() override {}
    void set_texcoord(HalfedgeHandle, const Vec2f&) override {}
    void set_texcoord(VertexHandle, const Vec3f&) override {}
    void set_texcoord(HalfedgeHandle, const Vec3f&) override {}
    void set_status(HalfedgeHandle, const Status&) override {}
    void set_color(EdgeHandle, const Vec3uc&) override {}
    void set_color(EdgeHandle, const Vec4uc&) override {}
    void set_color(EdgeHandle, const Vec3f&) override {}
    void set_color(EdgeHandle, const Vec4f&) override {}
    void set_status(EdgeHandle, const Status&) override {}
    void set_normal(FaceHandle, const Vec3f&) override {}
    void set_normal(FaceHandle, const Vec3d&) override {}
    void set_color(FaceHandle, const Vec3uc&) override {}
    void set_color(FaceHandle, const Vec4uc&) override {}
    void set_color(FaceHandle, const Vec3f&) override {}
    void set_color(FaceHandle, const Vec4f&) override {}
    void set_status(FaceHandle, const Status&) override {}
    void add_texture_information(int, std::string) override {}

private:
    // Normals and uvs arrive per vertex after it was added: size their arrays once.
    size_t arrays_size() const { return std::max(m_mesh.p.size(), m_mesh.p.capacity()); }
    bool valid(VertexHandle h) const { return h.idx() >= 0 && size_t(h.idx()) < m_mesh.p.size(); }
    TriangleMesh& m_mesh;
    size_t m_faces = 0;
    std::string m_error;
};

}  // namespace ml
