// Lightcuts (Walter et al. 2005, seed 004): the same point lights as `vpl`, clustered in a light
// tree; at each gather point a cut through the tree is refined, always splitting the node with
// the largest error bound, until every node's bound is below `lightcuts.error` (default 10%) of
// the current estimate or the cut holds `lightcuts.max_cut` nodes. A node is shaded by its
// representative light alone (one shadow ray), scaled by the cluster's luminance over the
// representative's, so that its expectation is the cluster's exact sum in every channel
// whatever the lights' colours (manylight/representative.h). The bounds hold every possible
// estimate, so the cut does not depend on the representatives drawn (without vpl.clamp).
// Each node keeps `lightcuts.reps` (default 8) representatives, each drawn in proportion to
// luminance; a gather point shades with the k-th of every node, k drawn from its sampler, so
// the samples of a pixel make independent errors that average out (1: Walter's one
// representative, whose error repeats at every sample).
//
// `lightcuts.criterion` says when a cut is fine enough:
// - "max" (default): Walter et al.'s test, every node's bound below the error times the estimate.
//   Each node's error is then small, but a cut of many nodes can add up to more.
// - "probable": the representatives are chosen at random in proportion to luminance, so each
//   node's error is zero-mean, independent of the other nodes' and within +-its bound; refining
//   until 3.26 sqrt(sum of bounds^2) is below the error bounds the whole estimate's error by it
//   with probability >= 99% (Hoeffding's inequality).
// - "sum": the sum of the bounds below the error: a certain bound, at the price of large cuts.
//
// `lightcuts.reconstruct` = B > 1: full cuts only at every B-th pixel in x and y, reconstruction
// cuts from them in between (reconstruction.h); 0 or 1: a full cut at every gather point.
#pragma once

#include <atomic>
#include <vector>

#include "integrators/lightcuts/reconstruction.h"
#include "manylight/gather.h"
#include "manylight/light_tree.h"
#include "manylight/many_lights.h"
#include "render/integrator.h"
#include "render/settings.h"

namespace ml {

class LightcutsIntegrator final : public PixelIntegrator {
public:
    explicit LightcutsIntegrator(const Settings& settings);
    std::string name() const override { return "lightcuts"; }
    void prepare(const Scene& scene) override;
    // The error floor's pilot (manylight/pilot.h).
    void before_pixels(const RenderContext& ctx) override;
    RGB li(const Ray& ray, const Scene& scene, Sampler& sampler, ScratchBuffer& scratch,
           Point2i pixel) const override;
    RenderResult render(const RenderContext& ctx) override;
    // Not with reconstruction (its passes shade pixels in an order of their own).
    bool can_checkpoint() const override { return m_reconstruct <= 1; }
    // vpl.sets=pass: a new VPL set every kPixelPassSamples samples (many_lights.h).
    int64_t block_samples() const override {
        return m_settings.set_per_pass ? kPixelPassSamples : 0;
    }
    void begin_block(const RenderContext& ctx, int64_t block) override {
        if (m_settings.use_set(block, m_set)) prepare(ctx.scene);
    }

private:
    struct CutEntry {
        int32_t node;
        int32_t rep;         // the representative light it is shaded with
        float bound;         // luminance of the error bound (infinite: must be split)
        RGB estimate;        // the node's estimate
        RGB rep_value;       // the representative's own contribution, visibility included
        bool tight = false;  // bound uses the node's own material bound (else the BSDF's overall)
        ShadowResult shadow = ShadowResult::NotCast;  // what rep_value's shadow ray found
        bool operator<(const CutEntry& o) const { return bound < o.bound; }
    };
    // The cut at one gather point: its radiance; *cut_size receives the number of nodes.
    // Representative k of every node stands for it (0 <= k < m_reps).
    // `known`: radiance the gather point gets besides the cut (sampled direct light), which
    // counts in the estimate the error threshold is relative to. *cut_out (when given) receives
    // the cut's nodes and their shadow rays' findings, sorted by node.
    RGB shade(const Scene& scene, const GatherPoint& g, int k, int* cut_size,
              const RGB& known = RGB()) const {
        return shade(scene, g, k, cut_size, known, m_max_cut);
    }
    RGB shade(const Scene& scene, const GatherPoint& g, int k, int* cut_size, const RGB& known,
              int max_cut, std::vector<CutNode>* cut_out = nullptr) const;
    // li() with reconstruction cuts: the sample's first gather point records its full cut in
    // *record (a sparse sample), or is shaded by a reconstruction cut from `corners` where they
    // agree with it (a sample between them). Both null: li(). first_k >= 0: the first gather
    // point shades with representative first_k of every node (else one drawn from its sampler).
    RGB li_sample(const Ray& ray, const Scene& scene, Sampler& sampler, ScratchBuffer& scratch,
                  Point2i pixel, SparseCut* record, std::span<const SparseCut* const> corners,
                  int first_k) const;
    // The render with lightcuts.reconstruct > 1: per sample index, the sparse samples' full
    // cuts first, then every pixel (reconstruction.h).
    RenderResult render_reconstructed(const RenderContext& ctx);
    // A node's error bound (RGB, times the gather point's throughput) from a bound of its
    // lights' sum: at most the larger of that and the estimate. With vpl.clamp > 0 the sum is
    // also at most n times the clamp per channel, for a node of n VPLs.
    RGB error_bound(const RGB& bound, const LightTreeNode& n, const RGB& estimate) const;
    // `lightcuts.verify`: every clustered node of the cut just made against the exact sum over
    // its lights (a shadow ray each): counts nodes whose error exceeds their bound.
    void verify_cut(const Scene& scene, const GatherPoint& g, const std::vector<CutEntry>& cut,
                    const RGB& estimate) const;

    ManyLightSettings m_settings;
    // Defaults: bench/RESULTS.md, "Issue 13: the defaults".
    float m_error = 0.1f;
    enum class Criterion { Max, Probable, Sum } m_criterion = Criterion::Max;
    const char* criterion_name() const {
        return m_criterion == Criterion::Max ? "max"
                                             : (m_criterion == Criterion::Sum ? "sum" : "probable");
    }
    int m_max_cut = 1000;
    // The cap the gather points' cuts use: max_cut, or under a time limit what lets the first
    // pass end in time (manylight/pilot.h: plan_pass_cut_cap).
    int m_pass_cap = 1000;
    CutCapPlan m_cap_plan;
    // The error floor (manylight/pilot.h): `lightcuts.floor` times the pilot's mean luminance.
    float m_floor = 1.0f;
    float m_floor_luminance = 0;
    bool m_verify = false;
    int m_reps = kLightTreeReps;  // representatives per node drawn from (1: always the first)
    // The sparse grid's spacing B in pixels (0, 1: off). Off by default: 4 halves the kitchen's
    // CPU time at 320x180 for 1% more relMSE, but it does not hold `error` per pixel where blocks
    // are large in the scene (bench/RESULTS.md, "Issue 13, session 9").
    int m_reconstruct = 0;
    // Figures of reconstruction: samples shaded by a reconstruction cut, their nodes, and the
    // samples between sparse ones that had to compute a full cut (corners disagreed).
    mutable std::atomic<uint64_t> m_reconstructed{0}, m_reconstructed_nodes{0}, m_refined{0};
    mutable std::atomic<uint64_t> m_verified_nodes{0}, m_violations{0};
    mutable std::atomic<double> m_verify_abs_error{0}, m_verify_bounds{0}, m_verify_total{0};
    PointLightSet m_set;
    SampledDirectLight m_direct;
    LightTree m_tree;
    double m_tree_seconds = 0;
    // Figures: cut sizes summed over gather points, the largest cut, and per pixel.
    mutable std::atomic<uint64_t> m_cut_sum{0}, m_gather_points{0}, m_capped{0};
    mutable std::atomic<int> m_cut_max{0};
    mutable std::vector<float> m_pixel_cut;  // each pixel is written by one thread only
    mutable std::vector<uint32_t> m_pixel_samples;
    int m_width = 0;
};

}  // namespace ml
