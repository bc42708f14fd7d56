// Direct light from the area and infinite lights by sampling (`lights.direct=sample`), for the
// many-light integrators: instead of turning those emitters into fixed point lights, whose
// 1/d^2 blows up on surfaces that touch or nearly touch an emitter (a strip light over a
// worktop, a window's frame), every gather point takes `lights.direct_samples` samples of
// next-event estimation with multiple importance sampling, as the path tracer does: a light
// chosen in proportion to power and a point on it, and a BSDF sample whose ray may find an
// emitter, weighted by the power heuristic. The result is unbiased; delta lights (point, spot,
// distant) stay point lights, which are exact for them. With lights.direct_mis=glossy (the
// viewer's moving frames) receivers without a glossy lobe take only the light samples, with the
// lights' complete densities (still unbiased, and without the BSDF sample's closest-hit ray);
// glossy receivers keep both with MIS.
#pragma once

#include <vector>

#include "manylight/gather.h"
#include "sampling/distributions.h"

namespace ml {

class Light;

class SampledDirectLight {
public:
    SampledDirectLight() = default;
    // The scene's non-delta lights; `samples` light and BSDF samples per gather point (with
    // `mis` false: light samples only where the receiver has no glossy lobe).
    SampledDirectLight(const Scene& scene, int samples, bool mis = true);

    bool empty() const { return m_count == 0; }
    int samples() const { return m_samples; }
    bool mis() const { return m_mis; }
    // Direct radiance at g from the sampled lights, times g.beta. Draws 5 dimensions per sample
    // from the sampler (none when empty()), whatever happens, and in a scene with media those of
    // the transmittance as well.
    RGB estimate(const Scene& scene, const GatherPoint& g, Sampler& sampler) const;
    // Probability of choosing the light at position `index` of the scene's list.
    float pmf(int index) const;

private:
    // estimate() in a scene with media (g.sampler set): the point may be in a medium, and every
    // ray to a light takes the media's transmittance.
    RGB estimate_through_media(const Scene& scene, const GatherPoint& g, Sampler& sampler) const;

    Distribution1D m_choice;  // over the scene's lights; delta lights weigh 0
    size_t m_count = 0;       // lights that can be chosen
    int m_samples = 1;
    bool m_mis = true;
};

}  // namespace ml
