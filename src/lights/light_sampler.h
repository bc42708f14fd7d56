// Choosing one light for next-event estimation: by emitted power (the default for path
// tracing, as pbrt-v4's "power" sampler) or uniformly.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "lights/light.h"
#include "sampling/distributions.h"

namespace ml {

struct SampledLight {
    const Light* light = nullptr;
    float pmf = 0;
};

class LightSampler {
public:
    // "power": pmf proportional to the luminance of each light's power (lights of zero power
    // are never chosen); "uniform": equal pmf. `lights[i]->index` must be i.
    LightSampler(const std::string& kind, const std::vector<std::unique_ptr<Light>>& lights);
    std::optional<SampledLight> sample(float u) const {
        if (m_lights.empty()) return std::nullopt;
        float pmf;
        size_t i = m_distribution.sample_discrete(u, &pmf);
        if (pmf == 0) return std::nullopt;
        return SampledLight{m_lights[i], pmf};
    }
    float pmf(const Light* light) const {
        return light && light->index >= 0 && size_t(light->index) < m_lights.size()
                   ? m_distribution.pmf(size_t(light->index))
                   : 0.f;
    }
    size_t size() const { return m_lights.size(); }

private:
    std::vector<const Light*> m_lights;
    Distribution1D m_distribution;
};

}  // namespace ml
