// What a ray hit: the point, its normals, tangents and texture coordinates, and what is there.
#pragma once

#include <cstdint>

#include "core/math.h"

namespace ml {

class Material;
class Light;
struct TriangleMesh;

struct SurfaceInteraction {
    Vec3 p;           // hit point, world space
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

    // A ray origin offset off the surface along ng towards w, against self-intersection.
    Vec3 offset_origin(const Vec3& w) const {
        float scale = 1e-4f * std::max(1.f, max_component(vabs(p)));
        Vec3 off = ng * scale;
        return dot(w, ng) < 0 ? p - off : p + off;
    }
};

}  // namespace ml
