#include "geometry/shapes.h"

#include <algorithm>
#include <cmath>

#include "core/assert.h"
#include "core/parallel.h"
#include "geometry/curves.h"

namespace ml {

std::unique_ptr<TriangleMesh> make_triangle_mesh(const ParameterList& params, const FileLoc& loc) {
    auto mesh = std::make_unique<TriangleMesh>();
    mesh->p = params.get_point3s("P");
    const Param* p_param = params.find("P");
    if (mesh->p.empty())
        throw_input_error(p_param ? p_param->loc : loc,
                          "trianglemesh: \"point3 P\" is required and must not be empty");

    std::vector<int> idx = params.get_ints("indices");
    const Param* i_param = params.find("indices");
    if (!i_param) {
        // pbrt-v4 lets a single triangle leave out its indices.
        if (mesh->p.size() != 3)
            throw_input_error(loc,
                              "trianglemesh: \"integer indices\" is required unless there are "
                              "exactly 3 vertices");
        idx = {0, 1, 2};
    }
    FileLoc iloc = i_param ? i_param->loc : loc;
    if (idx.empty()) throw_input_error(iloc, "trianglemesh: \"integer indices\" is empty");
    if (idx.size() % 3 != 0)
        throw_input_error(iloc, "trianglemesh: {} indices is not a multiple of 3", idx.size());
    mesh->indices.resize(idx.size());
    for (size_t i = 0; i < idx.size(); ++i) {
        if (idx[i] < 0 || size_t(idx[i]) >= mesh->p.size())
            throw_input_error(
                iloc, "trianglemesh: index {} (entry {}) is out of range: there are {} vertices",
                idx[i], i, mesh->p.size());
        mesh->indices[i] = uint32_t(idx[i]);
    }

    mesh->n = params.get_normals("N");
    if (!mesh->n.empty() && mesh->n.size() != mesh->p.size())
        throw_input_error(params.find("N")->loc,
                          "trianglemesh: {} normals \"N\" for {} vertices \"P\"", mesh->n.size(),
                          mesh->p.size());
    mesh->uv = params.get_point2s("uv");
    if (!mesh->uv.empty() && mesh->uv.size() != mesh->p.size())
        throw_input_error(params.find("uv")->loc,
                          "trianglemesh: {} texture coordinates \"uv\" for {} vertices \"P\"",
                          mesh->uv.size(), mesh->p.size());
    if (params.find("N") && mesh->n.empty())
        throw_input_error(params.find("N")->loc, "trianglemesh: \"normal N\" is empty");
    if (const Param* s = params.find("S"))
        throw_input_error(s->loc,
                          "trianglemesh: per-vertex tangents \"S\" are not supported by manylight");
    // Per-face indices only serve pbrt-v4's ptex textures (refused where declared).
    params.get_ints("faceIndices");
    if (params.find("uv") && mesh->uv.empty())
        throw_input_error(params.find("uv")->loc, "trianglemesh: \"point2 uv\" is empty");
    return mesh;
}

std::unique_ptr<TriangleMesh> make_bilinear_mesh(const ParameterList& params, const FileLoc& loc) {
    const Param* i_param = params.find("indices");
    std::vector<int> idx = params.get_ints("indices");
    std::vector<Vec3> p = params.get_point3s("P");
    if (!i_param && p.size() == 4) idx = {0, 1, 2, 3};
    FileLoc iloc = i_param ? i_param->loc : loc;
    if (idx.empty() || idx.size() % 4 != 0)
        throw_input_error(iloc, "bilinearmesh: needs a non-empty multiple of 4 indices, got {}",
                          idx.size());
    // Reuse the triangle mesh checks on the split patches.
    auto mesh = std::make_unique<TriangleMesh>();
    mesh->p = std::move(p);
    if (mesh->p.empty()) throw_input_error(loc, "bilinearmesh: \"point3 P\" is required");
    for (size_t k = 0; k < idx.size(); ++k)
        if (idx[k] < 0 || size_t(idx[k]) >= mesh->p.size())
            throw_input_error(
                iloc, "bilinearmesh: index {} (entry {}) is out of range: there are {} vertices",
                idx[k], k, mesh->p.size());
    for (size_t k = 0; k < idx.size(); k += 4) {
        uint32_t v00 = idx[k], v10 = idx[k + 1], v01 = idx[k + 2], v11 = idx[k + 3];
        mesh->indices.insert(mesh->indices.end(), {v00, v10, v11, v00, v11, v01});
    }
    mesh->n = params.get_normals("N");
    if (!mesh->n.empty() && mesh->n.size() != mesh->p.size())
        throw_input_error(params.find("N")->loc,
                          "bilinearmesh: {} normals \"N\" for {} vertices \"P\"", mesh->n.size(),
                          mesh->p.size());
    mesh->uv = params.get_point2s("uv");
    if (!mesh->uv.empty() && mesh->uv.size() != mesh->p.size())
        throw_input_error(params.find("uv")->loc,
                          "bilinearmesh: {} texture coordinates \"uv\" for {} vertices \"P\"",
                          mesh->uv.size(), mesh->p.size());
    params.get_ints("faceIndices");  // for ptex only, as in trianglemesh
    if (const Param* e = params.find("emissionfilename"))
        throw_input_error(e->loc,
                          "bilinearmesh: \"emissionfilename\" (image emission) is not supported "
                          "by manylight");
    return mesh;
}

namespace {

// Resolution of the tessellations: a full sphere gets kThetaSteps x kPhiSteps quads, which keeps
// the silhouette within 3e-4 of the radius and the area within 1e-3 of the analytic one.
constexpr int kThetaSteps = 64;
constexpr int kPhiSteps = 128;

// Adds the two triangles of the grid quad whose corners are a = (i, j), b = (i+1, j),
// c = (i, j+1), d = (i+1, j+1), skipping those collapsed at a pole or centre.
void add_quad(TriangleMesh& m, uint32_t a, uint32_t b, uint32_t c, uint32_t d) {
    auto add = [&](uint32_t x, uint32_t y, uint32_t z) {
        if (length_squared(cross(m.p[y] - m.p[x], m.p[z] - m.p[x])) == 0.f) return;
        m.indices.insert(m.indices.end(), {x, y, z});
    };
    add(a, b, c);
    add(b, d, c);
}

float phi_max_param(const ParameterList& params) {
    return radians(std::clamp(params.get_float("phimax", 360.f), 0.f, 360.f));
}

}  // namespace

std::unique_ptr<TriangleMesh> make_sphere(const ParameterList& params, const FileLoc& loc) {
    float radius = params.get_float("radius", 1.f);
    float zmin = params.get_float("zmin", -radius);
    float zmax = params.get_float("zmax", radius);
    float phi_max = phi_max_param(params);
    if (!(radius > 0.f))
        throw_input_error(params.find("radius") ? params.find("radius")->loc : loc,
                          "sphere: radius must be positive");
    // As pbrt-v4: z range clamped to the sphere; theta measured from +z.
    float z0 = std::clamp(std::min(zmin, zmax), -radius, radius);
    float z1 = std::clamp(std::max(zmin, zmax), -radius, radius);
    float theta_zmin = std::acos(std::clamp(z0 / radius, -1.f, 1.f));
    float theta_zmax = std::acos(std::clamp(z1 / radius, -1.f, 1.f));
    if (!(phi_max > 0.f) || !(theta_zmin > theta_zmax))
        throw_input_error(loc, "sphere: empty (zmin >= zmax or phimax = 0)");

    int nt = std::max(2, int(std::ceil(kThetaSteps * (theta_zmin - theta_zmax) / kPi)));
    int np = std::max(4, int(std::ceil(kPhiSteps * phi_max / (2 * kPi))));
    auto mesh = std::make_unique<TriangleMesh>();
    mesh->p.reserve(size_t(nt + 1) * (np + 1));
    mesh->n.reserve(mesh->p.capacity());
    mesh->uv.reserve(mesh->p.capacity());
    for (int i = 0; i <= nt; ++i) {
        // Row 0 at the top (theta_zmax), where pbrt's v is 1.
        float theta = lerp(float(i) / nt, theta_zmax, theta_zmin);
        if (i == 0) theta = theta_zmax;
        if (i == nt) theta = theta_zmin;
        float st = std::sin(theta), ct = std::cos(theta);
        if (theta == 0.f) st = 0.f;
        for (int j = 0; j <= np; ++j) {
            float phi = j == np ? phi_max : phi_max * float(j) / np;
            Vec3 n(st * std::cos(phi), st * std::sin(phi), ct);
            mesh->p.push_back(n * radius);
            mesh->n.push_back(n);
            mesh->uv.emplace_back(phi / phi_max, (theta - theta_zmin) / (theta_zmax - theta_zmin));
        }
    }
    // With theta growing down and phi counterclockwise, (a, b, c) winds outward.
    for (int i = 0; i < nt; ++i)
        for (int j = 0; j < np; ++j) {
            uint32_t a = uint32_t(i * (np + 1) + j), b = a + uint32_t(np + 1);
            add_quad(*mesh, a, b, a + 1, b + 1);
        }
    return mesh;
}

std::unique_ptr<TriangleMesh> make_disk(const ParameterList& params, const FileLoc& loc) {
    float height = params.get_float("height", 0.f);
    float radius = params.get_float("radius", 1.f);
    float inner = params.get_float("innerradius", 0.f);
    float phi_max = phi_max_param(params);
    if (!(radius > 0.f) || inner < 0.f || !(inner < radius) || !(phi_max > 0.f))
        throw_input_error(loc, "disk: needs 0 <= innerradius < radius and phimax > 0");
    // Rings do not change the area; a few keep the uv interpolation close to pbrt's.
    const int nr = 4;
    int np = std::max(4, int(std::ceil(kPhiSteps * phi_max / (2 * kPi))));
    auto mesh = std::make_unique<TriangleMesh>();
    for (int i = 0; i <= nr; ++i) {
        // Row 0 at the outer edge, where pbrt's v is 0.
        float r = i == nr ? inner : lerp(float(i) / nr, radius, inner);
        for (int j = 0; j <= np; ++j) {
            float phi = j == np ? phi_max : phi_max * float(j) / np;
            mesh->p.emplace_back(r * std::cos(phi), r * std::sin(phi), height);
            mesh->n.emplace_back(0.f, 0.f, 1.f);
            mesh->uv.emplace_back(phi / phi_max, (radius - r) / (radius - inner));
        }
    }
    // Rows grow inward, so (a, c, b) is the counterclockwise order seen from +z.
    for (int i = 0; i < nr; ++i)
        for (int j = 0; j < np; ++j) {
            uint32_t a = uint32_t(i * (np + 1) + j), b = a + uint32_t(np + 1);
            add_quad(*mesh, a, a + 1, b, b + 1);
        }
    return mesh;
}

std::unique_ptr<TriangleMesh> make_cylinder(const ParameterList& params, const FileLoc& loc) {
    float radius = params.get_float("radius", 1.f);
    float zmin = params.get_float("zmin", -1.f), zmax = params.get_float("zmax", 1.f);
    float phi_max = phi_max_param(params);
    if (zmin > zmax) std::swap(zmin, zmax);  // as pbrt-v4
    if (!(radius > 0.f) || !(zmax > zmin) || !(phi_max > 0.f))
        throw_input_error(loc, "cylinder: needs radius > 0, zmin != zmax and phimax > 0");
    // Straight along z: two rows of vertices are exact; the phi steps as the sphere's.
    int np = std::max(4, int(std::ceil(kPhiSteps * phi_max / (2 * kPi))));
    auto mesh = std::make_unique<TriangleMesh>();
    for (int i = 0; i <= 1; ++i) {
        float z = i == 0 ? zmin : zmax;
        for (int j = 0; j <= np; ++j) {
            float phi = j == np ? phi_max : phi_max * float(j) / np;
            Vec3 n(std::cos(phi), std::sin(phi), 0.f);
            mesh->p.push_back(Vec3(n.x * radius, n.y * radius, z));
            mesh->n.push_back(n);
            mesh->uv.emplace_back(phi / phi_max, float(i));  // pbrt's v = (z - zmin) / height
        }
    }
    // Row 1 above row 0 and phi counterclockwise: (a, a + 1, b) winds outward.
    for (int j = 0; j < np; ++j) {
        uint32_t a = uint32_t(j), b = a + uint32_t(np + 1);
        add_quad(*mesh, a, a + 1, b, b + 1);
    }
    return mesh;
}

void transform_mesh(TriangleMesh& mesh, const Transform& to_world, bool reverse_orientation) {
    const size_t nv = mesh.p.size();
    parallel_for_chunks(size_t(0), nv, size_t(1) << 14, [&](size_t begin, size_t end) {
        for (size_t i = begin; i != end; ++i) {
            mesh.p[i] = to_world.point(mesh.p[i]);
            if (!mesh.n.empty()) {
                Vec3 n = to_world.normal(mesh.n[i]);
                float l = length(n);
                // A zero normal in the file stays zero rather than becoming NaN.
                n = l > 0.f ? n / l : n;
                mesh.n[i] = reverse_orientation ? -n : n;
            }
        }
    });
    mesh.flip_normals = reverse_orientation != to_world.swaps_handedness();
    if (mesh.curves) transform_curves(*mesh.curves, to_world);
    if (mesh.n.empty()) return;
    const size_t nt = mesh.triangle_count();
    parallel_for_chunks(size_t(0), nt, size_t(1) << 14, [&](size_t begin, size_t end) {
        for (size_t t = begin; t != end; ++t) {
            uint32_t* v = &mesh.indices[3 * t];
            Vec3 ns = mesh.n[v[0]] + mesh.n[v[1]] + mesh.n[v[2]];
            Vec3 ng = cross(mesh.p[v[1]] - mesh.p[v[0]], mesh.p[v[2]] - mesh.p[v[0]]);
            if (mesh.flip_normals) ng = -ng;
            if (dot(ng, ns) < 0.f) std::swap(v[1], v[2]);
        }
    });
}

void transform_mesh_motion(TriangleMesh& mesh, const std::vector<Transform>& steps,
                           bool reverse_orientation) {
    ML_ASSERT(steps.size() >= 2, "a moving mesh needs two steps or more");
    const size_t nv = mesh.p.size();
    const std::vector<Vec3> p_object = mesh.p, n_object = mesh.n;
    if (mesh.curves) {
        // Each step's widths and ribbon normals, from the object space's.
        const CurveSet object = *mesh.curves;
        mesh.curves->motion_width.clear();
        mesh.curves->motion_n.clear();
        for (const Transform& t : steps) {
            CurveSet c = object;
            transform_curves(c, t);
            mesh.curves->motion_width.insert(mesh.curves->motion_width.end(), c.width.begin(),
                                             c.width.end());
            mesh.curves->motion_n.insert(mesh.curves->motion_n.end(), c.n.begin(), c.n.end());
        }
    }
    mesh.motion_steps = int(steps.size());
    mesh.motion_p.resize(steps.size() * nv);
    mesh.motion_n.resize(n_object.empty() ? 0 : steps.size() * nv);
    for (size_t k = 0; k < steps.size(); ++k) {
        const Transform& t = steps[k];
        for (size_t i = 0; i < nv; ++i) {
            mesh.motion_p[k * nv + i] = t.point(p_object[i]);
            if (n_object.empty()) continue;
            Vec3 n = t.normal(n_object[i]);
            float l = length(n);
            n = l > 0.f ? n / l : n;
            mesh.motion_n[k * nv + i] = reverse_orientation ? -n : n;
        }
    }
    // Step 0 as a static mesh: p, n, flip_normals and the triangles' vertex order (a motion that
    // changes handedness part way is not supported: the order of the start holds throughout).
    transform_mesh(mesh, steps[0], reverse_orientation);
}

int motion_segments(float radians) {
    return std::clamp(int(std::ceil(radians / (2 * kPi / 180))), 1, 64);
}

}  // namespace ml
