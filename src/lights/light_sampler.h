// Choosing one light for next-event estimation: uniformly ("uniform"), or in proportion to
// emitted power ("power", pbrt-v4's PowerLightSampler). The scene sets each light's `index` to its
// position in the list before building a sampler, and pmf() finds lights by it. Build it after
// the lights' preprocess(): distant and infinite lights need the scene bounds for their power.
#pragma once

#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "lights/light.h"
#include "sampling/distributions.h"

namespace ml {

struct SampledLight {
    const Light* light = nullptr;
    int index = -1;  // position in the light list
    float pmf = 0;
};

class LightSampler {
public:
    // "uniform" or "power"; throws UsageError for other names.
    LightSampler(const std::string& name, std::span<const Light* const> lights);
    LightSampler(const std::string& name, const std::vector<std::unique_ptr<Light>>& lights);

    // nullopt when there is no light to choose. "power": the pmf is proportional to the
    // luminance of power(), positive for every light with positive power in any channel, zero for
    // lights that emit nothing (uniform when no light has power).
    std::optional<SampledLight> sample(float u) const;
    float pmf(const Light* light) const { return light ? pmf(light->index) : 0.f; }
    float pmf(int index) const {
        return index >= 0 && size_t(index) < m_lights.size() ? m_dist.pmf(size_t(index)) : 0.f;
    }
    const std::string& name() const { return m_name; }

private:
    void build();

    std::string m_name;
    std::vector<const Light*> m_lights;
    Distribution1D m_dist;
};

}  // namespace ml
