// Power-based VPL sampling (Wald, Benthin and Slusallek 2003, as Segovia's thesis describes it):
// a pilot pass estimates how much each light gives the image through its VPLs, and the light
// paths then start at the lights in proportion to that estimate.
#include <algorithm>
#include <numeric>

#include "core/parallel.h"
#include "core/rng.h"
#include "lights/light_sampler.h"
#include "manylight/gather.h"
#include "manylight/point_light_set.h"
#include "manylight/vpl_sampler.h"
#include "scene/scene.h"

namespace ml {
namespace {

// The share of each light's probability that follows its power whatever the pilot found: it
// keeps every light that emits possible (the estimator stays unbiased where the pilot saw
// nothing) and bounds the flux of a VPL from a light the pilot underrated.
constexpr float kDefensiveShare = 0.1f;

// The luminance the pilot VPL `pl` sends to the pilot points (visibility included).
double pilot_contribution(const Scene& scene, const PointLightSet& set, const PointLight& pl,
                          const PilotPoints& pilot) {
    double sum = 0;
    for (const GatherPoint& g : pilot.points) {
        RGB c;
        Ray shadow;
        if (!point_light_contribution(set, pl, g, &c, &shadow)) continue;
        float y = c.luminance();
        if (y > 0 && !scene.occluded(shadow)) sum += double(y);
    }
    return sum;
}

}  // namespace

std::vector<float> power_light_pmf(const Scene& scene, const PerspectiveCamera& camera,
                                   const VplOptions& options) {
    const auto& lights = scene.lights();
    LightSampler by_power("power", lights);
    // Step 1: the pilot: camera points, and VPLs of light paths started by power.
    PilotPoints pilot = camera_pilot_points(scene, camera, options.sampler.pilot, 8,
                                            hash_ints(options.seed, 0x706f776572ULL));
    VplOptions po = options;
    po.paths = size_t(options.sampler.pilot_paths);
    po.light_pmf.clear();
    po.seed = hash_ints(options.seed, 0x7069706174687321ULL);
    PointLightSet set;
    std::vector<int> vpl_light;
    generate_vpls(scene, po, set, &vpl_light);
    // Step 2: each light's share of what the pilot VPLs give the pilot points. A VPL's flux is
    // already divided by the pilot paths and by its light's probability, so the sum over a
    // light's VPLs estimates that light's contribution without bias.
    std::vector<double> per_vpl(set.lights.size(), 0.0);
    parallel_for_chunks(size_t(0), set.lights.size(), size_t(16), [&](size_t b, size_t e) {
        for (size_t i = b; i < e; ++i)
            per_vpl[i] = pilot_contribution(scene, set, set.lights[i], pilot);
    });
    std::vector<double> contribution(lights.size(), 0.0);
    for (size_t i = 0; i < per_vpl.size(); ++i)
        if (vpl_light[i] >= 0) contribution[size_t(vpl_light[i])] += per_vpl[i];
    double total = std::accumulate(contribution.begin(), contribution.end(), 0.0);
    // Step 3: the mixture of the pilot's estimate and the lights' power.
    std::vector<float> pmf(lights.size());
    for (size_t l = 0; l < lights.size(); ++l) {
        double p_power = by_power.pmf(int(l));
        double p_pilot = total > 0 ? contribution[l] / total : p_power;
        pmf[l] = float(kDefensiveShare * p_power + (1 - kDefensiveShare) * p_pilot);
    }
    return pmf;
}

void sample_power_vpls(const Scene& scene, const PerspectiveCamera& camera,
                       const VplOptions& options, PointLightSet& set) {
    if (options.count <= 0 || scene.lights().empty()) return;
    VplOptions o = options;
    o.light_pmf = power_light_pmf(scene, camera, options);
    generate_vpls(scene, o, set);
}

}  // namespace ml
