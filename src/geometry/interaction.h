// What a ray hit: the point, its normals, tangents and texture coordinates, and what is there.
#pragma once

#include <cstdint>

#include "core/math.h"

namespace ml {

class Material;
class Light;
struct TriangleMesh;

// Ray origins off surfaces, from floating-point error bounds (pbrt-v4's OffsetRayOrigin and
// SpawnRayTo, section 6.8.6). A computed point p lies within p +- p_error of the true surface;
// a ray leaving from inside that box may hit the surface it left. Moving p along the unit
// normal n by the box's extent along n, |n| . p_error, clears the box: the offset is
// surface_offset(n, p_error), the same for rays to either side. It is never zero, so that it
// keeps n (segment_ray needs it) where the box is flat (a point exactly on an axis-aligned
// plane): the floor of 1e-30 is far below any float spacing of a scene.
inline Vec3 surface_offset(const Vec3& n, const Vec3& p_error) {
    return n * std::max(dot(vabs(n), p_error), 1e-30f);
}

// p moved by `offset` (a surface_offset, or zero for points on no surface, which stay put) to the
// side of the surface that w points into, each coordinate then rounded one float further from
// p so that rounding the sum cannot bring it back into the error box.
inline Vec3 offset_ray_origin(const Vec3& p, const Vec3& offset, const Vec3& w) {
    Vec3 off = dot(w, offset) < 0 ? -offset : offset;
    Vec3 po = p + off;
    for (int i = 0; i < 3; ++i) {
        if (off[i] > 0) po[i] = next_float_up(po[i]);
        if (off[i] < 0) po[i] = next_float_down(po[i]);
    }
    return po;
}

// The ray between two points, each moved off its surface (offsets as above) towards the other:
// t in (0, 1) spans the segment, and everything between the two error boxes is an occluder,
// however close to either end (no fraction of the length is cut off). The ray tracer finds the
// far surface at a t whose error grows with the distance from the origin (its vertices are
// taken relative to the origin, one rounding each), so the far end also clears that error.
inline Ray segment_ray(const Vec3& from, const Vec3& from_offset, const Vec3& to,
                       const Vec3& to_offset, float time = 0) {
    Vec3 o = offset_ray_origin(from, from_offset, to - from);
    // Lengthened along itself by the error, with its largest component for its length (a
    // floor offset's squared length would underflow; the bound grows by at most sqrt(3)).
    Vec3 off = to_offset;
    float l = max_component(vabs(to_offset));
    if (l > 0) off = off * (1 + gamma_bound(4) * dot(vabs(to - o), Vec3(1, 1, 1)) / l);
    Vec3 e = offset_ray_origin(to, off, o - to);
    return Ray{o, e - o, 1.f, time};
}

struct SurfaceInteraction {
    Vec3 p;           // hit point, world space
    Vec3 p_error;     // bound on the error of each coordinate of p (zero: exact)
    Vec3 ng;          // geometric normal (unit): towards ns if the mesh has normals, else
                      // per the winding and flip_normals (pbrt-v4's convention)
    Vec3 ns;          // shading normal (unit), in the hemisphere of ng
    Vec3 dpdu, dpdv;  // position derivatives with respect to uv
    Vec2 uv;          // texture coordinates
    Vec3 wo;          // unit direction back towards the ray origin
    float t = 0;      // ray parameter of the hit
    float time = 0;
    const Material* material = nullptr;
    const Light* area_light = nullptr;
    const TriangleMesh* mesh = nullptr;
    uint32_t mesh_id = 0, prim_id = 0;

    // This point's offset off its surface (surface_offset along ng).
    Vec3 offset() const { return surface_offset(ng, p_error); }
    // A ray origin off the surface, on the side w points into (offset_ray_origin).
    Vec3 offset_origin(const Vec3& w) const { return offset_ray_origin(p, offset(), w); }
};

}  // namespace ml
