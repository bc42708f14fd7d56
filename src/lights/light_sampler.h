// Choosing one light for next-event estimation: uniformly ("uniform"), in proportion to emitted
// power ("power", pbrt-v4's PowerLightSampler), or by the light tree ("tree", the default of the
// path tracer: pbrt-v4's BVHLightSampler, improved, see below). The scene sets each light's
// `index` to its position in the list before building a sampler, and pmf() finds lights by it.
// Build it after the lights' preprocess(): distant and infinite lights need the scene bounds.
//
// "tree": lights with bounds (point, spot, area) sit in a LightBvh (light_bvh.h), chosen by
// descending it with each child's importance at the receiving point. Lights without (distant,
// infinite) are chosen apart, as in pbrt-v4, but not with a fixed probability: each has a table
// of the irradiance it gives a surface of each orientation (E(n), |cos| weighted), and the tree
// as a whole has its root's importance, all in units of irradiance; the three-or-so top-level
// choices are made in proportion to those, mixed with kTopLevelUniform of a uniform choice so
// that no crude estimate can starve one. So a wall facing away from the sun rarely samples it.
//
// Points without a receiver (light subpaths, VPL emission) use sample(u)/pmf(light), which for
// "tree" is the power distribution.
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "lights/light.h"
#include "lights/light_bvh.h"
#include "sampling/distributions.h"

namespace ml {

struct SampledLight {
    const Light* light = nullptr;
    int index = -1;  // position in the light list
    float pmf = 0;
};

class LightSampler {
public:
    // "uniform", "power" or "tree"; throws UsageError for other names.
    LightSampler(const std::string& name, std::span<const Light* const> lights);
    LightSampler(const std::string& name, const std::vector<std::unique_ptr<Light>>& lights);

    // Without a receiver. nullopt when there is no light to choose. "power" and "tree": the pmf
    // is proportional to the luminance of power(), positive for every light with positive power
    // in any channel, zero for lights that emit nothing (uniform when no light has power).
    std::optional<SampledLight> sample(float u) const;
    float pmf(const Light* light) const { return light ? pmf(light->index) : 0.f; }
    float pmf(int index) const {
        return index >= 0 && size_t(index) < m_lights.size() ? m_dist.pmf(size_t(index)) : 0.f;
    }

    // For the receiver ctx: "tree" as above; the others as without a receiver. pmf(ctx, light)
    // is exactly the probability that sample(ctx, u) returns light, u uniform.
    std::optional<SampledLight> sample(const LightSampleContext& ctx, float u) const;
    float pmf(const LightSampleContext& ctx, const Light* light) const;

    const std::string& name() const { return m_name; }

private:
    void build();
    // Top-level probabilities at ctx: [0, m_unbounded.size()) for the unbounded lights, then the
    // tree (when it has lights). Returns how many there are.
    int top_level(const LightSampleContext& ctx, float* p) const;

    std::string m_name;
    std::vector<const Light*> m_lights;
    Distribution1D m_dist;

    // "tree"
    bool m_tree = false;
    LightBvh m_bvh;                            // items: indices into m_bounded
    std::vector<int> m_bounded;                // light index of each tree item
    std::vector<int> m_tree_item;              // per light: its tree item, or -1
    std::vector<int> m_unbounded;              // light indices of lights chosen apart
    std::vector<int> m_top_slot;               // per light: its top-level slot, or -1
    static constexpr int kIrradianceRes = 16;  // octahedral grid of normals per side
    // Per unbounded light: E(n) over the grid (and its mean, for receivers with no normal).
    std::vector<std::array<float, kIrradianceRes * kIrradianceRes>> m_irradiance;
    std::vector<float> m_irradiance_mean;
};

// The share of the top-level choice of the tree sampler made uniformly.
constexpr float kTopLevelUniform = 0.1f;
// Most top-level choices the tree sampler makes (unbounded lights plus the tree).
constexpr int kMaxTopLevel = 16;

}  // namespace ml
