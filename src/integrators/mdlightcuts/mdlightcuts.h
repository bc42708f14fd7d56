// Multidimensional Lightcuts (Walter et al. 2006, seed 003), restricted to the samples of one
// pixel: the S camera samples of a pixel pass (`mdlightcuts.samples`, default 32) are shaded
// together by one cut through the product of a gather tree over their gather points and the
// light tree of `lightcuts`, so a pass costs about as many shadow rays as one single-point cut
// (product_cut.h). The point-light set, clamping and sampled direct light are `vpl`'s and
// `lightcuts`' (ManyLightSettings), and the gather points are exactly `vpl`'s at the same sample
// indices, so the image converges to the brute-force `vpl` image as `mdlightcuts.error` -> 0.
//
// The pixel's estimate is the filter-weighted mean of its samples: emission and sampled direct
// light per sample, plus the cut, in which each gather point weighs its filter weight over the
// pass's sum, times its throughput. A pass adds that mean to the film with the pass's summed
// filter weight, which gives the film's filtered mean over all passes (`maxcomponentvalue`
// then clamps a pass's mean, not each sample). Under --time-limit passes repeat while time is
// left, and the cuts stop at the cap that lets the first pass end in time (manylight/pilot.h);
// --spp N takes ceil(N / S) passes.
#pragma once

#include <atomic>
#include <vector>

#include "manylight/direct.h"
#include "manylight/light_tree.h"
#include "manylight/many_lights.h"
#include "manylight/pilot.h"
#include "manylight/point_light_set.h"
#include "manylight/product_cut.h"
#include "render/integrator.h"
#include "render/settings.h"

namespace ml {

class MdLightcutsIntegrator final : public Integrator {
public:
    explicit MdLightcutsIntegrator(const Settings& settings);
    std::string name() const override { return "mdlightcuts"; }
    RenderResult render(const RenderContext& ctx) override;
    // A pass's set and samples depend on the seed and the pass alone; the checkpoint keeps the
    // pass plan (cap, samples) and the figures.
    bool can_checkpoint() const override { return true; }

private:
    struct ThreadState;
    void prepare(const Scene& scene);
    struct PassEstimate {
        RGB value;              // the pixel's filtered mean over the pass's samples
        double weight_sum = 0;  // their summed filter weight (0: no sample counts)
        int pairs = 0;          // the cut's size
        size_t gather_points = 0;
    };
    // The pass of `pixel` over its samples first_sample to first_sample + samples - 1 (samples 0:
    // the pass's m_pass_samples), with cuts of at most max_cut pairs.
    PassEstimate estimate_pass(const RenderContext& ctx, ThreadState& ts, Point2i pixel,
                               int first_sample, int max_cut, int samples = 0) const;
    // The same, added to the film and counted in the figures.
    void render_pixel_pass(const RenderContext& ctx, ThreadState& ts, Point2i pixel, int first,
                           int samples) const;
    nlohmann::json figures_json(const RenderContext& ctx, int passes) const;
    // The figures' sums, as a checkpoint keeps them, and back.
    nlohmann::json figures_state() const;
    void restore_figures(const nlohmann::json& state, size_t pixels);

    ManyLightSettings m_settings;
    // Defaults: bench/RESULTS.md, "Issue 13: the defaults".
    int m_samples = 32;
    float m_error = 0.1f;
    int m_max_cut = 1000;
    // The cap the passes use: max_cut, or under a time limit what lets the first pass end in
    // time (manylight/pilot.h: plan_pass_cut_cap).
    int m_pass_cap = 1000;
    int m_cap = 1000;         // the cap of the pass being shaded: m_pass_cap, or the last pass's
    int m_pass_samples = 32;  // m_samples, or fewer where a time limit needs (pilot.h)
    CutCapPlan m_cap_plan;
    int m_tighten = 1;  // pairs whose gather node has at most this many members get tight bounds
    // The error floor (manylight/pilot.h): `mdlightcuts.floor` times the pilot's mean luminance.
    float m_floor = 1.0f;
    float m_floor_luminance = 0;
    CutCriterion m_criterion = CutCriterion::Max;
    PointLightSet m_set;
    SampledDirectLight m_direct;
    LightTree m_tree;
    double m_tree_seconds = 0;
    // Figures: pairs summed over pixel passes, the largest cut, gather points, gather-tree time.
    mutable std::atomic<uint64_t> m_pair_sum{0}, m_pixel_passes{0}, m_gather_points{0};
    mutable std::atomic<uint64_t> m_gather_tree_ns{0}, m_capped{0};
    mutable std::atomic<int> m_pair_max{0};
    mutable std::vector<float> m_pixel_pairs;  // each pixel is written by one thread only
    mutable std::vector<uint32_t> m_pixel_passes_done;
};

}  // namespace ml
