#include "manylight/point_light_set.h"

#include <chrono>
#include <cmath>

#include "core/rng.h"
#include "lights/light.h"
#include "manylight/vpl_budget.h"
#include "manylight/vpl_sampler.h"
#include "sampling/sampler.h"
#include "scene/scene.h"

namespace ml {
namespace {

// The samplers' seed for the point lights of `seed`: hashed, so that a render whose --seed is
// also the lights' seed (the default, vpl.seed unset) never draws its light paths from the very
// sequence its camera samples use (an independent sampler of the same seed would give VPL path
// k the numbers of pixel (k, 0)'s first sample).
uint64_t stream_seed(uint64_t seed) { return hash_ints(seed, 0x706f696e746c6967ULL); }

// Point lights of the scene's emitters: area lights share options.area_count samples in
// proportion to power (at least one each), every infinite light gets options.env_count; with
// options.sampled_direct only the delta lights are added.
void add_emitters(const Scene& scene, const PointLightOptions& options, PointLightSet& set) {
    const auto& lights = scene.lights();
    double area_power = 0;
    size_t area_lights = 0;
    for (const auto& l : lights) {
        if (l->type() != LightType::Area) continue;
        area_power += double(std::max(0.f, l->power().luminance()));
        ++area_lights;
    }
    // A separate stream from the VPL paths' (which use sample 0 of their pixels).
    auto sampler = create_sampler("independent", 1, stream_seed(options.seed));
    for (size_t i = 0; i < lights.size(); ++i) {
        const Light& light = *lights[i];
        if (options.sampled_direct && !is_delta_light(light.type())) continue;
        int n = 1;
        if (light.type() == LightType::Area) {
            double share = area_power > 0
                               ? double(options.area_count) *
                                     double(std::max(0.f, light.power().luminance())) / area_power
                               : double(options.area_count) / double(area_lights);
            n = std::max(1, int(std::lround(share)));
        } else if (light.type() == LightType::Infinite) {
            n = std::max(1, options.env_count);
        }
        sampler->start_pixel_sample({int(i), 0}, 1);
        light.to_point_lights(n, *sampler, set.lights);
    }
}

// Camera points that place the emission focus.
constexpr int kFocusPoints = 1024;

}  // namespace

bool has_disk_light(const Scene& scene) {
    Vec3 c;
    float r;
    for (const auto& l : scene.lights())
        if (l->emission_sphere(&c, &r)) return true;
    return false;
}

PointLightSet build_point_light_set(const Scene& scene, const PointLightOptions& options) {
    auto start = std::chrono::steady_clock::now();
    PointLightSet set;
    if (options.emitters) add_emitters(scene, options, set);
    if (options.vpls) {
        VplOptions vo;
        vo.count = options.vpl_count;
        vo.max_depth = options.vpl_max_depth;
        vo.glossy = options.vpl_glossy;
        vo.seed = stream_seed(options.seed);
        vo.sampler = options.vpl_sampler;
        const VplSamplerKind kind = options.vpl_sampler.kind;
        if (options.vpl_focus > 0 && options.camera &&
            (kind == VplSamplerKind::Standard || kind == VplSamplerKind::Power) &&
            has_disk_light(scene) &&
            camera_focus_sphere(scene, *options.camera, kFocusPoints, vo.seed, &vo.focus_center,
                                &vo.focus_radius))
            vo.focus_share = options.vpl_focus;
        set.focus_share = vo.focus_share;
        set.focus_radius = vo.focus_share > 0 ? vo.focus_radius : 0.f;
        vo.region = options.vpl_region;
        set.vpl_count_requested = vo.count;
        set.vpl_count_used = sample_vpls_within(scene, options.camera, vo, options.vpl_budget, set);
    }
    for (const PointLight& pl : set.lights) {
        switch (pl.kind) {
            case PointLightKind::Omni:
                ++set.omni;
                break;
            case PointLightKind::Oriented:
                ++set.oriented;
                break;
            case PointLightKind::Directional:
                ++set.directional;
                break;
            case PointLightKind::Glossy:
                ++set.glossy;
                break;
        }
    }
    set.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return set;
}

}  // namespace ml
