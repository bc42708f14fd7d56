// Instant global illumination with interleaved sampling (seed 000, its second half): a G-buffer
// of the first surfaces the camera sees, split into n x m sub-buffers that are each shaded by
// their own 1/(nm) of the VPLs (scaled by nm), gathered back, blurred by the discontinuity filter
// over continuous regions only, and added to the direct light. The VPLs come from the same
// point-light set as `vpl` and `lightcuts` (manylight/many_lights.h); the emitters' point lights
// and the sampled direct light shade every pixel in full, as `vpl` does, so that with interleave
// 1x1 and no filter `igi` is `vpl`. The viewer (`manylight view`) renders its moving frames
// with it.
#pragma once

#include <string>
#include <vector>

#include "integrators/igi/interleave.h"
#include "manylight/many_lights.h"
#include "render/integrator.h"
#include "render/settings.h"

namespace ml {

struct IgiSettings {
    int n = 4, m = 4;  // igi.interleave=NxM
    // igi.filter: the box blur spans filter x filter interleave patterns, (filter n) x
    // (filter m) pixels, so each VPL subset counts once per pattern (0: no filter).
    int filter = 1;
    DiscontinuityThresholds thresholds;
    bool packets = true;  // igi.packets: shadow rays in Embree packets of eight
    // igi.filter_direct: the sampled direct light (lights.direct=sample) goes through the
    // filter with the VPLs' light (the viewer's moving frames: one noisy sample per pixel).
    bool filter_direct = false;
    static IgiSettings read(const Settings& s);
};

class IgiIntegrator final : public Integrator {
public:
    explicit IgiIntegrator(const Settings& settings);
    std::string name() const override { return "igi"; }
    RenderResult render(const RenderContext& ctx) override;

private:
    struct Pixel;
    // What the lights of `indices` give at g, each through a shadow ray, times `scale`.
    RGB shade(const Scene& scene, const GatherPoint& g, const std::vector<uint32_t>& indices,
              float scale) const;
    ManyLightSettings m_many;
    IgiSettings m_igi;
    PointLightSet m_set;
    SampledDirectLight m_direct;
    std::vector<uint32_t> m_emitters;              // the emitters' point lights: every pixel
    std::vector<std::vector<uint32_t>> m_subsets;  // the VPLs of each sub-buffer
    std::vector<float> m_scales;                   // VPLs in all / VPLs of the sub-buffer
};

}  // namespace ml
