// pbrt-v4's stochastic alpha test, shared by the ray filter (geometry/embree_scene.cpp) and the
// emission of area lights on cut-out shapes (lights/diffuse_area_light.cpp): alpha 1 or more
// keeps the surface, 0 or less removes it, and a fractional alpha keeps it where a uniform
// number hashed from what is tested (a ray, a point) lies below it. Hashing rather than drawing
// keeps the answer the same each time the same thing is tested.
#pragma once

#include <cstdint>

#include "core/math.h"
#include "core/rng.h"

namespace ml {

// Whether the surface is there at alpha `a`, `hash` being the tested thing's 64-bit hash.
inline bool alpha_keeps(float a, uint64_t hash) {
    if (a >= 1) return true;
    if (a <= 0) return false;
    return float(hash >> 40) * 0x1p-24f < a;
}

// The hash of a point (pbrt-v4's HashFloat(p), which its area lights test their emission by).
inline uint64_t alpha_hash(const Vec3& p) {
    return hash_ints(float_bits(p.x, p.y), float_bits(p.z, 0.f));
}

}  // namespace ml
