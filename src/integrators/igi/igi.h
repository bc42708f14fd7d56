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

#include "core/scratch.h"
#include "integrators/igi/interleave.h"
#include "manylight/gather.h"
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
    // igi.packets: shadow rays in Embree packets of eight, one VPL's rays to a row's points
    bool packets = true;
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
    // A gather point of a row's camera paths, the subset that shades it, and what it gathered:
    // the sampled direct light when it is filtered (igi.filter_direct) and the VPLs' light.
    struct RowPoint {
        GatherPoint g;
        int sub = 0;
        RGB direct, vpls;
    };
    // A pixel of the row for one sample: its gather points [first, last) and the light that is
    // not filtered (emission, direct light, the emitters' point lights).
    struct RowPixel {
        size_t index = 0, first = 0, last = 0;
        RGB direct;
        float weight = 0;         // the filter's
        float camera_weight = 1;  // the camera ray's: it scales direct and indirect
    };
    // Per thread: the sampler, the BSDFs of a row's gather points (reset after each sample), the
    // row's points and pixels, and the seconds of each phase (--stats).
    struct RowState {
        std::unique_ptr<Sampler> sampler;
        ScratchBuffer scratch;
        std::vector<RowPoint> points;
        std::vector<RowPixel> pixels;
        std::vector<int> subs;
        double seconds_gather = 0, seconds_vpls = 0;
    };
    // Sample s of the pixels x0 <= x < x1 of row y of the split buffer: the camera paths, their
    // gather points into rs (and the G-buffer texel of each pixel's first sample).
    void gather_row(const RenderContext& ctx, const InterleavedLayout& layout, int y, int x0,
                    int x1, int s, RowState& rs, std::vector<GBufferTexel>& gbuffer) const;
    // The VPLs of their subsets at the row's gather points: light by light, each light's shadow
    // rays to the row's points in packets of eight (igi.packets), times the subset's scale.
    void shade_row_vpls(const Scene& scene, RowState& rs) const;
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
