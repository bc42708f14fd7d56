// Pieces the radiance integrators share: MIS weights, next-event estimation, spawning rays.
#pragma once

#include "geometry/interaction.h"
#include "lights/light.h"
#include "materials/bsdf.h"
#include "sampling/sampler.h"
#include "scene/scene.h"

namespace ml {

inline float power_heuristic(float f_pdf, float g_pdf) {
    float f = f_pdf * f_pdf, g = g_pdf * g_pdf;
    if (std::isinf(f)) return 1.f;
    return f + g > 0 ? f / (f + g) : 0.f;
}

inline LightSampleContext light_context(const SurfaceInteraction& si) {
    return LightSampleContext{si.p, si.ng, si.ns};
}

inline Ray spawn_ray(const SurfaceInteraction& si, const Vec3& wi) {
    return Ray{si.offset_origin(wi), wi, kInfinity, si.time};
}

class LightSampler;

// Emission found by a ray that escaped (hit == null: infinite lights) or hit an area light.
// From the camera and after delta bounces (`full_weight`) it counts whole; otherwise it is
// MIS-weighted against next-event estimation having chosen that light with the pmf of
// `light_sampler` (null: every light is sampled, pmf 1) and sampled the direction.
RGB emission_along(const Scene& scene, const Ray& ray, const SurfaceInteraction* hit,
                   bool full_weight, float prev_pdf, const LightSampleContext& prev_ctx,
                   const LightSampler* light_sampler);

// Radiance from `light` towards the surface, one light sample, weighted by MIS against BSDF
// sampling unless `mis` is false (delta lights take no weight). `light_pmf` is the probability
// that the caller chose this light: the light strategy's density is pmf * pdf, as in the weight
// emission_along gives the BSDF strategy. The result is not divided by it (the caller does).
RGB estimate_direct(const Scene& scene, const SurfaceInteraction& si, const Bsdf& bsdf,
                    const Light& light, const Vec2& u_light, bool mis = true,
                    float light_pmf = 1.f);

}  // namespace ml
