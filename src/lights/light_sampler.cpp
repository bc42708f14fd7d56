#include "lights/light_sampler.h"

#include <stdexcept>

namespace ml {

LightSampler::LightSampler(const std::string& kind,
                           const std::vector<std::unique_ptr<Light>>& lights) {
    if (kind != "power" && kind != "uniform")
        throw std::invalid_argument("unknown light sampler \"" + kind +
                                    "\" (power and uniform are)");
    std::vector<float> weights;
    for (size_t i = 0; i < lights.size(); ++i) {
        if (lights[i]->index != int(i))
            throw std::logic_error("LightSampler: lights must be indexed in order");
        m_lights.push_back(lights[i].get());
        float w = 1.f;
        if (kind == "power") {
            RGB phi = lights[i]->power();
            w = std::max(0.f, phi.luminance());
            // A coloured light of zero luminance still emits: fall back to its average.
            if (w == 0.f) w = std::max(0.f, phi.average());
        }
        weights.push_back(w);
    }
    if (!weights.empty()) m_distribution = Distribution1D(weights);
}

}  // namespace ml
