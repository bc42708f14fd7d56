#include "lights/light_sampler.h"

#include "core/error.h"

namespace ml {

LightSampler::LightSampler(const std::string& name, std::span<const Light* const> lights)
    : m_name(name), m_lights(lights.begin(), lights.end()) {
    build();
}

LightSampler::LightSampler(const std::string& name,
                           const std::vector<std::unique_ptr<Light>>& lights)
    : m_name(name) {
    m_lights.reserve(lights.size());
    for (const auto& l : lights) m_lights.push_back(l.get());
    build();
}

void LightSampler::build() {
    if (m_name != "uniform" && m_name != "power")
        throw UsageError("unknown light sampler \"" + m_name + "\"");
    if (m_lights.empty()) return;
    std::vector<float> w(m_lights.size(), 1.f);
    if (m_name == "power")
        for (size_t i = 0; i < m_lights.size(); ++i) {
            RGB phi = clamp_zero(m_lights[i]->power());
            // Luminance weights are all positive: any positive channel gives a positive weight.
            w[i] = phi.is_finite() ? phi.luminance() : 0.f;
        }
    m_dist = Distribution1D(w);
}

std::optional<SampledLight> LightSampler::sample(float u) const {
    if (m_lights.empty()) return std::nullopt;
    float pmf;
    size_t i = m_dist.sample_discrete(u, &pmf);
    if (pmf == 0) return std::nullopt;
    return SampledLight{m_lights[i], int(i), pmf};
}

}  // namespace ml
