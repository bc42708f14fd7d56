// What the many-light integrators (vpl, lightcuts, mdlightcuts) shade with, built once per render:
// the point-light set (the scene's lights turned into point lights, plus VPLs), the sampled direct
// light, the light tree over the set, and the settings that choose them.
#pragma once

#include <nlohmann/json.hpp>

#include <functional>
#include <optional>
#include <string>

#include "manylight/direct.h"
#include "manylight/gather.h"
#include "manylight/light_tree.h"
#include "manylight/pilot.h"
#include "manylight/point_light_set.h"
#include "render/settings.h"

namespace ml {

// The settings both `vpl` and `lightcuts` read: the point-light set and clamping.
struct ManyLightSettings {
    PointLightOptions lights;
    float clamp = 0;    // > 0: no VPL contributes more than this radiance (per channel)
    int max_depth = 5;  // delta bounces followed from the camera before gathering
    // Whether VPLs have light to give: maxdepth 2 or more (a VPL's light is a second bounce), or
    // vpl.max_depth given.
    bool vpls_reach = true;
    // gather.medium_points: gather points on each stretch of a camera ray through a homogeneous
    // medium (0: one, where delta tracking finds the ray scatter; manylight/gather.h). 4, the
    // default, measured best on fog and a coloured cloud (bench/RESULTS.md, "Participating
    // media").
    int medium_points = 4;
    // The lights gather points in media are also drawn towards (medium_gather_targets): set by
    // use_render_seed's caller through use_scene.
    std::vector<EquiangularTarget> medium_targets;
    GatherOptions gather() const { return {max_depth, medium_points, &medium_targets}; }
    // The render's scene: the targets above.
    void use_scene(const Scene& scene) { medium_targets = medium_gather_targets(scene); }
    // lights.direct=sample: area and infinite lights by next-event estimation
    // (manylight/direct.h) with lights.direct_samples samples per gather point, not as points.
    int direct_samples = 4;
    int tree_reps = kLightTreeReps;  // `tree.reps`: representatives per light-tree node
    // lights.direct_mis=always|glossy: light and BSDF samples weighted by MIS at every gather
    // point (true), or only at glossy ones, the others taking light samples alone (false).
    bool direct_mis = true;
    // vpl.seed when given; else lights.seed follows the render's seed (use_render_seed).
    std::optional<uint64_t> explicit_seed;
    // vpl.sets: pass (true, the default) draws a new, independent point-light set and light tree
    // for every pass (or block of samples), so that the image averages many VPL sets and its
    // error goes to zero with time; one (false) keeps one set for the whole render, whose error
    // (a few bright VPLs more or less) then stays in the image however long it renders.
    bool set_per_pass = true;
    uint64_t render_seed = 0;   // lights.seed of the first set (use_render_seed)
    int first_vpl_request = 0;  // > 0: the first set's vpl.count, where later sets take fewer
    // The defaults of vpl.glossy, vpl.clamp and lights.direct: the measured best for `vpl`,
    // `lightcuts` and `mdlightcuts`; an integrator that needs others (bdlightcuts) passes them,
    // so that the settings listed for it are its own.
    struct Defaults {
        const char* glossy = "bsdf";
        float clamp = 0.f;
        const char* direct = "sample";
        int tree_reps = kLightTreeReps;  // 0: builds no light tree (tree.reps is not read)
        // Whether camera paths gather with gather_along (gather.medium_points is read); false
        // for an integrator that traces its own eye paths through media (bdlightcuts).
        bool gathers = true;
        // vpl.focus: on for `vpl` and `igi`, whose few or exactly summed VPLs gain from it, and
        // for `bdlightcuts`, whose VPLs are only made near what the camera sees in such scenes
        // (bdlightcuts.vpl_region); the other cuts' capped refinement did worse with more VPLs
        // where the camera looks (bench/RESULTS.md, "VPL samplers").
        float focus = 0.f;
    };
    static ManyLightSettings read(const Settings& s, const Defaults& defaults);
    static ManyLightSettings read(const Settings& s) { return read(s, Defaults{}); }
    // Sets lights.seed, which every random choice of the point-light set (VPL paths, points on
    // area lights and environment maps) and of the light tree (representatives) draws from:
    // vpl.seed if given, else the render's seed (--seed), so that a new --seed gives new VPLs
    // and representatives. (build_point_light_set hashes it into streams of its own, which never
    // replay the camera's samples.)
    void use_render_seed(uint64_t render_seed);
    // With set_per_pass, makes the settings those of set `index` (0: the first, as
    // use_render_seed left them): lights.seed hashed with the index, and from set 1 on the first
    // set's VPL count without a time budget (the budget fitted the count once; each later set
    // costs what the first did). `first` is the first set. Returns false (nothing changed)
    // without set_per_pass or for index 0.
    bool use_set(int64_t index, const PointLightSet& first);
    // A render resumed from a checkpoint under a time limit: every set takes `vpls`, what the
    // first run's budget fitted its first set to, as use_set takes it from set 1 on (the time
    // left now is not what that budget had), and no budget of its own. Nothing without a budget.
    void use_first_set_vpls(int vpls);
    // Under ctx's time limit, what the VPL build may take (lights.vpl_budget, vpl_budget.h); with
    // `with_tree`, the light tree over the set counts in it (it grows with the count: the
    // standard sampler's 266k VPLs took 0.31 s, their tree 1.07 s). Call after use_render_seed.
    void use_time_limit(const RenderContext& ctx, bool with_tree);
    // A point light's contribution after clamping (VPLs only; the emitters' lights are exact).
    RGB clamped(const RGB& c, bool is_vpl) const {
        if (clamp <= 0 || !is_vpl) return c;
        return RGB(std::min(c.r, clamp), std::min(c.g, clamp), std::min(c.b, clamp));
    }
};

// What the shadow ray of visible_point_light found: none was cast (the light gives nothing at
// the point whatever the visibility), or the light was seen or blocked.
enum class ShadowResult : uint8_t { NotCast, Visible, Occluded };

// What `pl` gives at g with its shadow ray: point_light_contribution, clamped as the settings
// say (VPLs), or nothing when the ray is blocked. The one shading of a single point light that
// `vpl`, `lightcuts`, `stochasticlightcuts` and the product cuts share. *shadow (when given)
// receives what the shadow ray found. `weigh` (when given) weighs the value from the pair's terms
// before the shadow ray, which is not cast where the weight is 0 (bdlightcuts' split weights).
using PointLightWeigh = std::function<float(const PointLightTerms& terms)>;
RGB visible_point_light(const Scene& scene, const PointLightSet& set,
                        const ManyLightSettings& settings, const PointLight& pl,
                        const GatherPoint& g, ShadowResult* shadow = nullptr,
                        const PointLightWeigh& weigh = {});
// The same without the shadow ray, the light taken as seen: for lightcuts' reconstruction cuts,
// where the nearby samples' shadow rays say it is.
RGB unshadowed_point_light(const PointLightSet& set, const ManyLightSettings& settings,
                           const PointLight& pl, const GatherPoint& g);

// With vpl.sets=pass, the samples per pixel that one VPL set serves in the pixel integrators
// (lightcuts, stochasticlightcuts, vpl); mdlightcuts and bdlightcuts draw one per pass.
constexpr int64_t kPixelPassSamples = 8;
// Reads vpl.sets (pass or one) into settings->set_per_pass.
void read_vpl_sets(const Settings& s, ManyLightSettings* settings);

// vpl.sampler and the settings of the sampler it names (manylight/vpl_sampler.h).
void read_vpl_sampler(const Settings& s, VplSamplerOptions* options);

// The VPLs' emission focus, where the set has one: {"vpl_focus": {share, radius}}; else {}.
nlohmann::json vpl_focus_json(const PointLightSet& set);

// What `vpl`, `lightcuts` and `mdlightcuts` shade with: the point-light set and, with
// lights.direct=sample, the sampled direct light.
void build_many_lights(const Scene& scene, const ManyLightSettings& settings, PointLightSet* set,
                       SampledDirectLight* direct);
// For `lightcuts` and `mdlightcuts`: the warning that a fraction `capped` of their cuts (of
// "gather points" or "pixel passes", `what`) stopped at max_cut, where the error is not bounded;
// or, where a time limit stopped them at time_cap < max_cut (manylight/pilot.h), that it did.
// Empty below 10%.
std::string capped_cut_warning(const std::string& integrator, const char* what, double capped,
                               int max_cut, const PointLightSet& set, int time_cap = 0);
// The --stats figures of a time-limited pass's cut cap (mdlightcuts.time_cap).
nlohmann::json cut_cap_json(const CutCapPlan& plan);
// What a checkpoint of an integrator with whole-film passes (mdlightcuts, bdlightcuts) keeps of
// the plan it made before its first pass: the cut cap plan (pilot.h; the passes' cap and samples
// under a time limit) and the VPL count the time budget chose for the first set (0: none; see
// use_first_set_vpls). A resumed render takes them again rather than planning from the time
// left, so that its passes are the first run's. The integrator's state holds it as "pass_plan";
// read_pass_plan returns false where `state` has none, throws UsageError where it is damaged.
nlohmann::json pass_plan_json(const CutCapPlan& plan, int first_set_vpls);
bool read_pass_plan(const nlohmann::json& state, CutCapPlan* plan, int* first_set_vpls);
// What a render resuming from ctx's checkpoint takes again (mdlightcuts, bdlightcuts): the
// integrator's saved state (null where it does not resume) and its pass plan (`planned` false
// where there is none). Where there is one, `settings` takes its first set's VPL count
// (use_first_set_vpls).
struct ResumedPasses {
    const nlohmann::json* state = nullptr;
    bool planned = false;
    CutCapPlan plan;
    int first_set_vpls = 0;
};
ResumedPasses resume_passes(const RenderContext& ctx, ManyLightSettings& settings);
// The --stats figures of the point-light set and the sampled direct light (build time, lights
// by kind, light paths, direct-light mode), as lightcuts and mdlightcuts report them.
nlohmann::json many_light_figures(const PointLightSet& set, const SampledDirectLight& direct);
// The light tree over `set` as `lightcuts` and `mdlightcuts` build it (representatives seeded by
// lights.seed, the cone weight from the scene's size); *seconds receives the build time.
LightTree build_light_tree(const Scene& scene, const ManyLightSettings& settings,
                           const PointLightSet& set, double* seconds);

}  // namespace ml
