// Bidirectional Lightcuts (Walter, Khungurn and Bala 2012; seed 003). Each pixel pass traces
// `bdlightcuts.samples` eye paths; every vertex with a non-delta part, up to
// `bdlightcuts.eye_length` of them per path, is a virtual sensor point (VSP), as the light paths'
// vertices are VPLs (the `vpl` set: emitters as point lights plus VPLs, which the VSP-VPL
// joins of every split cover). Every VSP of the pass is joined to every point light by one
// multidimensional cut through the product of the VSP tree and the light tree (the product cut
// of `mdlightcuts`, manylight/product_cut.h), each pair weighted by its split weight
// (split_weights.h), which replaces VPL clamping. The VSP tree keeps VSPs of different eye depths
// apart (`bdlightcuts.vsp_tree=depth`). Emission met by the eye paths counts with the
// weight the earlier splits left (the last split). With the energy weight alone the weights put
// everything on the first connectable eye vertex: the unbiased `vpl`/`mdlightcuts` estimator
// without clamping; clamping, diffuse VPLs and the spread exclusion move energy to longer eye
// paths or drop it. A VSP whose pairs all weigh 0 (vsp_weight_bound) stays out of the VSP tree.
// What no split up to the eye-path length takes, the remainder r (remainder_weight), is path
// traced past the last VSP's next vertex with weight r (`bdlightcuts.rest=path`, averaged over
// `bdlightcuts.rest_paths` paths), or dropped. The last split also takes light samples at the
// eye vertices, with its own weight, weighed against the BSDF samples by MIS
// (`bdlightcuts.emission=mis`, the default); with `lights.direct=sample` that is the emitters'
// split's light sample, which then carries both weights (one path, two splits). The split that
// joins a VSP to an area or infinite light is a light sample at the VSP, weighed by MIS against the
// eye path's BSDF sample (`lights.direct=sample`, the default), or the emitters' points in the cut
// (`lights.direct=points`); delta lights are always points of the cut, and their pairs take no
// clamping (no other split reaches them).
#pragma once

#include <atomic>
#include <memory>
#include <vector>

#include "integrators/bdlightcuts/pair_weights.h"
#include "integrators/bdlightcuts/split_weights.h"
#include "lights/light_sampler.h"
#include "manylight/light_tree.h"
#include "manylight/many_lights.h"
#include "manylight/point_light_set.h"
#include "manylight/product_cut.h"
#include "render/integrator.h"
#include "render/settings.h"
#include "sampling/distributions.h"
#include "transport/sd_tree.h"

namespace ml {

class BdLightcutsIntegrator final : public Integrator {
public:
    explicit BdLightcutsIntegrator(const Settings& settings);
    std::string name() const override { return "bdlightcuts"; }
    RenderResult render(const RenderContext& ctx) override;
    // A pass's set and samples depend on the seed and the pass alone; the checkpoint keeps the
    // pass plan (cap, samples), adaptive sampling's first pass (sample_shares.h) and the figures.
    // (Not with guided remainders: the guide is not saved.)
    bool can_checkpoint() const override { return !m_guiding; }

    // What a VSP keeps for its pairs' weights (pair_weights.h).
    using Vsp = VspWeightState;

private:
    struct ThreadState;
    struct PassEstimate {
        RGB value;
        double weight_sum = 0;
        int pairs = 0;
        size_t vsps = 0;
        int rests = 0;  // eye paths continued by the path-traced remainder
        // The variance of the eye paths' part of the value (its luminance: emission, light
        // samples, remainder paths), from the spread of the pass's samples. The cut's part is
        // left out: its noise is the cut's (one per pass), which more samples do not lower.
        float known_variance = 0;
    };
    // The pass of `pixel` over its samples first_sample to first_sample + samples - 1 (samples 0:
    // the pass's m_pass_samples), with cuts of at most max_cut pairs.
    PassEstimate estimate_pass(const RenderContext& ctx, ThreadState& ts, Point2i pixel,
                               int first_sample, int max_cut, int samples = 0) const;
    // One eye path: its VSPs into ts; returned, the weighted emission it meets and, with
    // m_rest_path, the remainder path traced past its last VSP (*rested: whether it was).
    RGB trace_eye(const Scene& scene, Ray ray, Sampler& sampler, ThreadState& ts,
                  float filter_weight, bool* rested) const;

    ManyLightSettings m_settings;
    // Defaults: bench/RESULTS.md, "Issue 17, Bidirectional Lightcuts".
    SplitWeightOptions m_weights;
    int m_samples = 16;
    int m_pass_samples = 16;  // m_samples, or fewer where a time limit needs (pilot.h)
    // bench/RESULTS.md, "Many-light images that converge": 1 lowers the worst scene's relMSE
    // ratio to path (the classroom's) and its largest mean error at 60 s; 2 before, 3 earlier.
    int m_eye_length = 1;
    bool m_rest_path = true;  // bdlightcuts.rest: path (true) or drop
    bool m_glowing = false;   // the scene's media emit light (only the eye paths carry it)
    int m_rest_paths = 4;     // bdlightcuts.rest_paths: remainder paths per continued eye path
    // bdlightcuts.guiding: the remainder paths are guided (transport/sd_tree.h) by what the
    // remainders of the passes before them (the pilots' first) learned.
    bool m_guiding = false;
    std::unique_ptr<SDTree> m_guide;
    mutable std::atomic<uint64_t> m_guide_paths{0};  // remainder paths recorded since the refine
    // bdlightcuts.vsp_tree: the VSP tree splits the VSPs by eye depth before position (depth,
    // true), or by position alone. A node of VSPs at several depths (the first VSPs, in the
    // pixel, with later ones across the scene) has a box as large as the scene and
    // representatives from both: bench/RESULTS.md, "Issue 17, session 16".
    bool m_tree_by_depth = true;
    // bdlightcuts.emission: the last split (the emitter met by the eye path) by BSDF samples and
    // light samples weighed by MIS (true), or by BSDF samples alone. With lights.direct=sample the
    // light sample is the emitters' split's own (bench/RESULTS.md, "Issue 17, session 15").
    bool m_emission_mis = true;
    // bdlightcuts.emission_samples: BSDF samples for the emission met from a glossy eye vertex
    // (the eye path goes on along one of them): bench/RESULTS.md, "Issue 17, session 18".
    int m_emission_samples = 1;
    // lights.direct=sample (the default): the emitters' split by a light sample at each VSP;
    // points: by the emitters' points in the cut.
    bool m_direct_sample = true;
    // The remainder's and the last split's next-event estimation.
    std::unique_ptr<LightSampler> m_nee_lights;
    float m_error = 0.07f;  // bench/RESULTS.md, "Issue 17, session 16" (0.1 before)
    // 150: with refine=bounds the cap does not move the mean, and at 20 s it lowered every
    // interior's relMSE or kept it (bench/RESULTS.md, "The VPL region"); 300 before.
    int m_max_cut = 150;
    // bdlightcuts.refine: bounds (true) splits pairs by their bound alone, relative to the eye
    // paths' part of the estimate (ProductCut::set_draw_free: the cut's mean does not depend on
    // max_cut); estimates, mdlightcuts' rule. bench/RESULTS.md, "Many-light images that
    // converge": the same relMSE at 20 s on the five interiors.
    bool m_refine_by_bounds = true;
    // bdlightcuts.vpl_region=view: VPLs only near what the camera sees, in scenes lit by
    // distant or infinite lights (render() decides; m_settings.lights.vpl_region holds it).
    bool m_vpl_region = true;
    // vpl.set_share: under a time limit, where the cuts are small, the most share of a pass that
    // making its VPL set and light tree may take; where a set costs more, one serves several
    // passes (render(): the set period; pilot.h: passes_per_set). bench/RESULTS.md, "Many-light
    // images that converge": coffee's sets took 12% of its passes.
    float m_set_share = 0.05f;
    float m_floor = 1.0f;
    float m_floor_luminance = 0;
    // bdlightcuts.adaptive: after the first pass, each pixel takes its share of the later passes'
    // samples (manylight/sample_shares.h), a high share as several passes: bench/RESULTS.md,
    // "Issue 17, session 17".
    bool m_adaptive = true;
    PointLightSet m_set;
    // The set's lights at a point (point and spot lights, not VPLs), chosen in proportion to
    // power for the equiangular samples in media: a distribution over them, the set's index of
    // each, and each set light's probability (0 for the others).
    Distribution1D m_eq_choice;
    std::vector<uint32_t> m_eq_lights;
    std::vector<float> m_eq_pmf;
    LightTree m_tree;
    std::vector<RGB> m_node_flux;  // per light-tree node: its lights' summed flux
    double m_tree_seconds = 0;
    mutable std::atomic<uint64_t> m_pair_sum{0}, m_pixel_passes{0}, m_vsps{0}, m_capped{0},
        m_rests{0};
};

}  // namespace ml
