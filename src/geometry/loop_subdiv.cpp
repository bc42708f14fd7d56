#include "geometry/loop_subdiv.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <unordered_map>

#include "core/error.h"

namespace ml {

namespace {

using Tri = std::array<uint32_t, 3>;

float loop_beta(int valence) { return valence == 3 ? 3.f / 16.f : 3.f / (8.f * float(valence)); }
float loop_gamma(int valence) { return 1.f / (float(valence) + 3.f / (8.f * loop_beta(valence))); }

// The mesh's adjacency at one level: its edges (with the vertices opposite them) and each
// vertex's one-ring in pbrt-v4's order.
struct Topology {
    struct Edge {
        uint32_t v[2];
        uint32_t opposite[2];  // the third vertex of each face; [1] unused on the boundary
        int faces = 0;
    };
    std::vector<Edge> edges;
    std::vector<std::array<uint32_t, 3>> face_edges;  // edge of (v0 v1), (v1 v2), (v2 v0)
    // Per vertex: its neighbours, in pbrt-v4's order (interior: against the winding; boundary:
    // along it, from one boundary neighbour to the other), and whether it is on the boundary.
    std::vector<std::vector<uint32_t>> ring;
    std::vector<bool> boundary;
};

Topology build_topology(size_t vertex_count, const std::vector<Tri>& faces, const FileLoc& loc) {
    Topology t;
    std::unordered_map<uint64_t, uint32_t> edge_of;
    edge_of.reserve(faces.size() * 2);
    // Per vertex, the winding's successor of each neighbour around it (face (v, a, b): a -> b)
    // and the reverse; a consistently wound manifold has at most one of each.
    std::vector<std::vector<std::pair<uint32_t, uint32_t>>> next(vertex_count);
    t.face_edges.resize(faces.size());
    for (size_t f = 0; f < faces.size(); ++f) {
        const Tri& tri = faces[f];
        for (int k = 0; k < 3; ++k) {
            uint32_t a = tri[size_t(k)], b = tri[size_t((k + 1) % 3)], c = tri[size_t((k + 2) % 3)];
            next[a].push_back({b, c});
            uint64_t key = (uint64_t(std::min(a, b)) << 32) | std::max(a, b);
            auto [it, fresh] = edge_of.try_emplace(key, uint32_t(t.edges.size()));
            if (fresh) t.edges.push_back({{a, b}, {c, c}, 0});
            Topology::Edge& e = t.edges[it->second];
            if (e.faces == 2)
                throw_input_error(loc, "loopsubdiv: the edge {}-{} has more than two faces", a, b);
            if (e.faces == 1) {
                if (e.v[0] == a)
                    throw_input_error(loc,
                                      "loopsubdiv: the faces beside the edge {}-{} are wound in "
                                      "opposite directions",
                                      a, b);
                e.opposite[1] = c;
            }
            ++e.faces;
            t.face_edges[f][size_t(k)] = it->second;
        }
    }
    // The rings: follow the successors from a neighbour without predecessor (the boundary) or
    // from any (interior).
    t.ring.resize(vertex_count);
    t.boundary.assign(vertex_count, false);
    for (size_t v = 0; v < vertex_count; ++v) {
        const auto& nx = next[v];
        if (nx.empty()) continue;  // not used by any face
        auto succ = [&](uint32_t a) -> int64_t {
            for (const auto& [from, to] : nx)
                if (from == a) return to;
            return -1;
        };
        uint32_t start = nx[0].first;
        for (const auto& [from, to] : nx) {
            bool has_pred = false;
            for (const auto& [f2, t2] : nx) has_pred |= t2 == from;
            if (!has_pred) {
                start = from;
                t.boundary[v] = true;
                break;
            }
        }
        std::vector<uint32_t>& ring = t.ring[v];
        uint32_t a = start;
        for (size_t steps = 0; steps <= nx.size(); ++steps) {
            ring.push_back(a);
            int64_t b = succ(a);
            if (b < 0 || uint32_t(b) == start) break;
            a = uint32_t(b);
        }
        // Every face around the vertex must lie on the one fan walked.
        size_t fan_faces = t.boundary[v] ? ring.size() - 1 : ring.size();
        if (fan_faces != nx.size())
            throw_input_error(loc,
                              "loopsubdiv: vertex {} is not manifold (its faces do not form "
                              "one fan)",
                              v);
        if (!t.boundary[v]) std::reverse(ring.begin() + 1, ring.end());
    }
    return t;
}

// (1 - n w) v + w * sum of the ring.
Vec3 weight_one_ring(const std::vector<Vec3>& p, size_t v, const std::vector<uint32_t>& ring,
                     float w) {
    Vec3 out = p[v] * (1 - float(ring.size()) * w);
    for (uint32_t r : ring) out += p[r] * w;
    return out;
}

// (1 - 2 w) v + w * its two boundary neighbours (the ring's ends).
Vec3 weight_boundary(const std::vector<Vec3>& p, size_t v, const std::vector<uint32_t>& ring,
                     float w) {
    return p[v] * (1 - 2 * w) + (p[ring.front()] + p[ring.back()]) * w;
}

}  // namespace

std::unique_ptr<TriangleMesh> loop_subdivide(std::vector<Vec3> p,
                                             const std::vector<uint32_t>& indices, int levels,
                                             const FileLoc& loc) {
    std::vector<Tri> faces(indices.size() / 3);
    for (size_t f = 0; f < faces.size(); ++f)
        faces[f] = {indices[3 * f], indices[3 * f + 1], indices[3 * f + 2]};
    for (const Tri& f : faces)
        if (f[0] == f[1] || f[1] == f[2] || f[2] == f[0])
            throw_input_error(loc, "loopsubdiv: a face uses vertex {} twice",
                              f[0] == f[1] || f[0] == f[2] ? f[0] : f[1]);

    // 1. Refine `levels` times: even vertices keep their indices, edge vertices follow.
    for (int level = 0; level < levels; ++level) {
        Topology t = build_topology(p.size(), faces, loc);
        const size_t nv = p.size();
        std::vector<Vec3> q(nv + t.edges.size());
        for (size_t v = 0; v < nv; ++v) {
            const auto& ring = t.ring[v];
            if (ring.empty())
                q[v] = p[v];
            else if (t.boundary[v])
                q[v] = weight_boundary(p, v, ring, 1.f / 8.f);
            else
                q[v] = weight_one_ring(p, v, ring, loop_beta(int(ring.size())));
        }
        for (size_t e = 0; e < t.edges.size(); ++e) {
            const Topology::Edge& ed = t.edges[e];
            if (ed.faces == 1)
                q[nv + e] = (p[ed.v[0]] + p[ed.v[1]]) * 0.5f;
            else
                q[nv + e] = (p[ed.v[0]] + p[ed.v[1]]) * (3.f / 8.f) +
                            (p[ed.opposite[0]] + p[ed.opposite[1]]) * (1.f / 8.f);
        }
        std::vector<Tri> children;
        children.reserve(faces.size() * 4);
        for (size_t f = 0; f < faces.size(); ++f) {
            const Tri& v = faces[f];
            uint32_t m01 = uint32_t(nv + t.face_edges[f][0]);
            uint32_t m12 = uint32_t(nv + t.face_edges[f][1]);
            uint32_t m20 = uint32_t(nv + t.face_edges[f][2]);
            children.push_back({v[0], m01, m20});
            children.push_back({v[1], m12, m01});
            children.push_back({v[2], m20, m12});
            children.push_back({m01, m12, m20});
        }
        p = std::move(q);
        faces = std::move(children);
    }

    // 2. The limit positions, then the limit normals from the limit positions.
    Topology t = build_topology(p.size(), faces, loc);
    std::vector<Vec3> limit(p.size());
    for (size_t v = 0; v < p.size(); ++v) {
        const auto& ring = t.ring[v];
        if (ring.empty())
            limit[v] = p[v];
        else if (t.boundary[v])
            limit[v] = weight_boundary(p, v, ring, 1.f / 5.f);
        else
            limit[v] = weight_one_ring(p, v, ring, loop_gamma(int(ring.size())));
    }
    auto mesh = std::make_unique<TriangleMesh>();
    mesh->n.resize(p.size());
    for (size_t v = 0; v < p.size(); ++v) {
        const auto& ring = t.ring[v];
        const int n = int(ring.size());
        if (n == 0) continue;
        auto r = [&](int j) { return limit[ring[size_t(j)]]; };
        Vec3 s, tt;
        if (!t.boundary[v]) {
            for (int j = 0; j < n; ++j) {
                float a = 2 * kPi * float(j) / float(n);
                s += r(j) * std::cos(a);
                tt += r(j) * std::sin(a);
            }
        } else {
            s = r(n - 1) - r(0);
            if (n == 2) {
                tt = r(0) + r(1) - limit[v] * 2;
            } else if (n == 3) {
                tt = r(1) - limit[v];
            } else if (n == 4) {
                tt = r(0) * -1 + r(1) * 2 + r(2) * 2 - r(3) - limit[v] * 2;
            } else {
                float theta = kPi / float(n - 1);
                tt = (r(0) + r(n - 1)) * std::sin(theta);
                for (int k = 1; k < n - 1; ++k)
                    tt += r(k) * ((2 * std::cos(theta) - 2) * std::sin(float(k) * theta));
                tt = -tt;
            }
        }
        mesh->n[v] = cross(s, tt);
    }
    // 3. The triangles, over the vertices faces use (a vertex no face names is left out).
    std::vector<int64_t> remap(p.size(), -1);
    for (const Tri& f : faces)
        for (uint32_t v : f) {
            if (remap[v] < 0) {
                remap[v] = int64_t(mesh->p.size());
                mesh->p.push_back(limit[v]);
            }
            mesh->indices.push_back(uint32_t(remap[v]));
        }
    std::vector<Vec3> normals(mesh->p.size());
    for (size_t v = 0; v < p.size(); ++v)
        if (remap[v] >= 0) normals[size_t(remap[v])] = mesh->n[v];
    mesh->n = std::move(normals);
    for (Vec3& n : mesh->n) {
        float len = length(n);
        n = len > 0 ? n / len : Vec3(0, 0, 1);
    }
    return mesh;
}

std::unique_ptr<TriangleMesh> make_loop_subdiv(const ParameterList& params, const FileLoc& loc) {
    int levels = params.get_int("levels", 3);
    const FileLoc& levels_loc = params.find("levels") ? params.find("levels")->loc : loc;
    if (levels < 0) throw_input_error(levels_loc, "loopsubdiv: \"levels\" must not be negative");
    std::string scheme = params.get_string("scheme", "loop");
    if (scheme != "loop")
        throw_input_error(params.find("scheme")->loc,
                          "loopsubdiv: scheme \"{}\" is unknown (\"loop\" is the only one)",
                          scheme);
    std::vector<Vec3> p = params.get_point3s("P");
    if (p.empty()) throw_input_error(loc, "loopsubdiv: \"point3 P\" is required");
    std::vector<int> idx = params.get_ints("indices");
    const Param* i_param = params.find("indices");
    if (!i_param || idx.empty())
        throw_input_error(loc, "loopsubdiv: \"integer indices\" is required");
    if (idx.size() % 3 != 0)
        throw_input_error(i_param->loc, "loopsubdiv: {} indices is not a multiple of 3",
                          idx.size());
    // Each level makes four triangles of one.
    if (double(idx.size() / 3) * std::pow(4.0, levels) > double(1 << 26))
        throw_input_error(levels_loc,
                          "loopsubdiv: {} levels of {} triangles make more than 2^26 triangles",
                          levels, idx.size() / 3);
    std::vector<uint32_t> indices(idx.size());
    for (size_t i = 0; i < idx.size(); ++i) {
        if (idx[i] < 0 || size_t(idx[i]) >= p.size())
            throw_input_error(i_param->loc,
                              "loopsubdiv: index {} (entry {}) is out of range: there are {} "
                              "vertices",
                              idx[i], i, p.size());
        indices[i] = uint32_t(idx[i]);
    }
    return loop_subdivide(std::move(p), indices, levels, i_param->loc);
}

}  // namespace ml
