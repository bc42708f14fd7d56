// Rays leaving surfaces: the one way every estimator spawns them, offset off the surface
// (SurfaceInteraction::offset_origin) so that they do not hit it again.
#pragma once

#include "geometry/interaction.h"
#include "lights/light.h"

namespace ml {

// Where a light sample is taken from: the surface point and its normals.
inline LightSampleContext light_context(const SurfaceInteraction& si) {
    return LightSampleContext{si.p, si.ng, si.ns};
}

// The ray leaving `si` in direction `wi`.
inline Ray spawn_ray(const SurfaceInteraction& si, const Vec3& wi) {
    return Ray{si.offset_origin(wi), wi, kInfinity, si.time};
}

}  // namespace ml
