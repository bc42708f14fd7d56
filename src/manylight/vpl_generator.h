// Instant radiosity: virtual point lights (VPLs) deposited along light paths.
#pragma once

#include <cstdint>

#include "lights/point_lights.h"

namespace ml {

class Scene;

struct VplOptions {
    int count = 10000;  // target: paths are traced until at least this many VPLs exist
    int max_depth = 5;  // most VPLs along one light path
    GlossyVpls glossy = GlossyVpls::Bsdf;  // VPLs on glossy surfaces (point_light.h)
    uint64_t seed = 0;
};

// Appends VPLs to set.lights (their surfaces to set.surfaces, the surfaces' Bxdfs to set.arenas)
// and adds to set.vpls and set.light_paths. Each VPL's flux is the light path's throughput
// divided by the number of paths traced, so the VPLs' emission estimates the indirect light
// without bias. Deterministic for a seed: path k draws its numbers from pixel (k mod 2^20,
// k / 2^20) of an independent sampler, and paths are kept in order whatever the thread count.
void generate_vpls(const Scene& scene, const VplOptions& options, PointLightSet& set);

// An estimate of the largest BSDF value max_w f(w, wi) (times |cos(w, n)| when `with_cos`) over
// every direction w, by evaluation at probe directions and a safety margin; used as the bound
// `intensity` of glossy VPLs until BSDFs bound themselves.
RGB estimate_max_bsdf_value(const Bsdf& bsdf, const Vec3& wi, bool with_cos,
                            bool diffuse_only = false);

}  // namespace ml
