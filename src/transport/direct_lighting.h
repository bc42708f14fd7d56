// Direct light, as every radiance estimator (integrators/, manylight/) gathers it: next-event
// estimation from a surface, and emission found by a ray, each weighted by MIS against the other.
#pragma once

#include <functional>

#include "lights/light.h"
#include "materials/bsdf.h"
#include "sampling/sampler.h"
#include "scene/scene.h"
#include "transport/mis.h"
#include "transport/spawn.h"

namespace ml {

class LightSampler;
class Medium;

// Emission found by a ray that escaped (hit == null: infinite lights) or hit an area light.
// From the camera and after delta bounces (`full_weight`) it counts whole; otherwise it is
// MIS-weighted against next-event estimation at prev_ctx having chosen that light with the pmf
// of `light_sampler` at prev_ctx (null: every light is sampled, pmf 1) and sampled the direction.
RGB emission_along(const Scene& scene, const Ray& ray, const SurfaceInteraction* hit,
                   bool full_weight, float prev_pdf, const LightSampleContext& prev_ctx,
                   const LightSampler* light_sampler);

// Radiance from `light` towards the surface, one light sample, weighted by MIS against BSDF
// sampling unless `mis` is false (delta lights take no weight). `light_pmf` is the probability
// that the caller chose this light: the light strategy's density is pmf * pdf, as in the weight
// emission_along gives the BSDF strategy. The result is not divided by it (the caller does).
// `weight`, if given, multiplies the result by a weight of the light sample (its direction, the
// point on the light and its normal; f is bsdf.eval(si.wo, ls.wi), without the cosine), taken
// before the shadow ray: where it is 0, no ray is traced (bdlightcuts' split weights, which are
// 0 for most directions at some points). `bsdf_samples`: the BSDF samples the caller weighs
// against this one light sample by MIS (the power heuristic with the counts). `direction_pdf`, if
// given, is the density of the caller's direction sampling in place of the BSDF's (a BSDF mixed
// with a guide: path guiding).
// `media`, if given, is where the point is in a scene with participating media: the shadow ray
// takes the transmittance through them (transport/volume_path.h), and a point in a medium
// (si with p, wo and time, bsdf the phase function of transport/phase_bxdf.h) has no surface.
using LightSampleWeight = std::function<float(const LightLiSample& ls, const RGB& f)>;
using DirectionPdf = std::function<float(const Vec3& wi)>;
struct DirectMedia {
    const Medium* arrived = nullptr;  // the medium the path arrived in
    bool in_medium = false;           // a scattering point in `arrived`, on no surface
    Sampler* sampler = nullptr;       // draws the transmittance where it is not closed-form
};
RGB estimate_direct(const Scene& scene, const SurfaceInteraction& si, const Bsdf& bsdf,
                    const Light& light, const Vec2& u_light, bool mis = true, float light_pmf = 1.f,
                    const LightSampleWeight& weight = {}, int bsdf_samples = 1,
                    const DirectionPdf& direction_pdf = {}, const DirectMedia* media = nullptr);

// Where a light sample is taken from at a path vertex: light_context at a surface, the point
// alone in a medium.
inline LightSampleContext vertex_context(const SurfaceInteraction& si, bool in_medium) {
    return in_medium ? LightSampleContext{si.p, Vec3(), Vec3()} : light_context(si);
}

}  // namespace ml
