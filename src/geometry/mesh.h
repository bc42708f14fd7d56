// Triangle meshes in world space, structure-of-arrays. Every shape becomes one: spheres and disks
// are tessellated finely (with analytic shading normals), PLY and trianglemesh are read as given.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "core/math.h"

namespace ml {

class Material;
class Light;
class Medium;

// A cut-out (pbrt-v4's "alpha" on a shape): at a point of the surface, the probability that the
// surface is there. Given by the scene layer (a float texture); geometry only evaluates it.
class AlphaMask {
public:
    virtual ~AlphaMask() = default;
    // At point p with texture coordinates uv on a surface of geometric normal ng (any length).
    virtual float eval(const Vec3& p, const Vec2& uv, const Vec3& ng) const = 0;
    // A constant alpha of 0: no ray ever meets the shape (pbrt-v4 makes such an emitter an
    // invisible light).
    virtual bool removes_all() const { return false; }
};

// pbrt-v4's "curve" shape as Embree curves: each segment a cubic Bezier whose four control
// points are the mesh's p[4 * s .. 4 * s + 3] (world space; a curve mesh has no triangles).
enum class CurveType { flat, cylinder, ribbon };
struct CurveSet {
    CurveType type = CurveType::flat;
    std::vector<float> width;  // 2 per segment: the width at u = 0 and u = 1 (world units)
    std::vector<Vec3> n;       // ribbon: 2 per segment, the unit normals at u = 0 and u = 1
    // The object-to-world transform reverses handedness: normals computed from world-space
    // cross products are negated to agree with pbrt-v4, which takes them in object space.
    bool swaps_handedness = false;
    // A moving curve mesh (TriangleMesh::moves()): the widths and normals of each time step, as
    // its motion_p holds the control points (step k's at [k * width.size()] and
    // [k * n.size()]); width and n hold step 0's.
    std::vector<float> motion_width;
    std::vector<Vec3> motion_n;
    size_t segment_count() const { return width.size() / 2; }
};

struct TriangleMesh {
    std::vector<Vec3> p;            // positions, world space
    std::vector<Vec3> n;            // per-vertex shading normals, world space (empty: none)
    std::vector<Vec2> uv;           // per-vertex texture coordinates (empty: none)
    std::vector<uint32_t> indices;  // 3 per triangle
    // Flips the geometric normal (pbrt's ReverseOrientation xor a handedness-swapping transform).
    bool flip_normals = false;
    const Material* material = nullptr;
    const Light* area_light = nullptr;  // set when the mesh emits
    // Null: opaque. Else every ray (camera, bounce and shadow rays alike) passes through the
    // surface where the mask is 0, and with probability 1 - alpha where it is fractional.
    std::shared_ptr<const AlphaMask> alpha;
    // A boundary between two media (pbrt-v4's MediumInterface with two different media): a ray
    // leaving the surface on the side of the geometric normal is in `medium_outside`, else in
    // `medium_inside` (null: vacuum). Elsewhere a ray keeps the medium it was in.
    bool medium_interface = false;
    const Medium* medium_inside = nullptr;
    const Medium* medium_outside = nullptr;
    // Motion (a shape under an animated transform): the positions and normals at
    // motion_steps >= 2 times spread evenly over the transform times, step after step
    // (motion_p[k * p.size() + v]); between two steps each vertex moves linearly (Embree's
    // motion blur). Empty for a mesh that does not move. p and n hold step 0.
    int motion_steps = 0;
    std::vector<Vec3> motion_p, motion_n;
    bool moves() const { return motion_steps >= 2; }
    // Set for a curve shape (then p holds control points and indices is empty).
    std::optional<CurveSet> curves;

    size_t triangle_count() const { return indices.size() / 3; }
    float triangle_area(size_t tri) const {
        const Vec3& a = p[indices[3 * tri]];
        const Vec3& b = p[indices[3 * tri + 1]];
        const Vec3& c = p[indices[3 * tri + 2]];
        return 0.5f * length(cross(b - a, c - a));
    }
    // Geometric normal of a triangle: the side it faces is, as in pbrt-v4, the side of the
    // per-vertex normals when the mesh has them, else the winding's flipped by flip_normals.
    // This is the side one-sided area lights emit from.
    Vec3 triangle_normal(size_t tri) const {
        uint32_t i0 = indices[3 * tri], i1 = indices[3 * tri + 1], i2 = indices[3 * tri + 2];
        Vec3 ng = normalize(cross(p[i1] - p[i0], p[i2] - p[i0]));
        if (!n.empty()) return face_forward(ng, n[i0] + n[i1] + n[i2]);
        return flip_normals ? -ng : ng;
    }
    // Over the whole motion.
    Bounds3 bounds() const {
        Bounds3 b;
        for (const Vec3& q : p) b.expand(q);
        for (const Vec3& q : motion_p) b.expand(q);
        return b;
    }
};

}  // namespace ml
