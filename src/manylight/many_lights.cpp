#include "manylight/many_lights.h"

#include <fmt/format.h>

#include <chrono>

#include "core/rng.h"
#include "manylight/vpl_sampler.h"

namespace ml {

namespace {

// The defaults of the settings `vpl`, `lightcuts` and `mdlightcuts` share: the best measured on
// the kitchen and the Cornell box (bench/RESULTS.md, "Issue 13: the defaults"). Glossy VPLs
// through their whole BSDF sent 89% of the kitchen's lightcuts cuts to max_cut, and area lights
// as points are singular where an emitter nearly touches a surface; clamping takes the rare
// VPL spikes (a VPL millimetres from the receiver) at a cost of about 0.5% of the kitchen.
constexpr int kDefaultVplCount = 100000;

}  // namespace

RGB visible_point_light(const Scene& scene, const PointLightSet& set,
                        const ManyLightSettings& settings, const PointLight& pl,
                        const GatherPoint& g, ShadowResult* shadow, const PointLightWeigh& weigh) {
    RGB c;
    Ray ray;
    PointLightTerms terms;
    if (shadow) *shadow = ShadowResult::NotCast;
    if (!point_light_contribution(set, pl, g, &c, &ray, weigh ? &terms : nullptr)) return RGB();
    float w = 1;
    if (weigh) {
        w = weigh(terms);
        if (!(w > 0)) return RGB();
    }
    c = settings.clamped(c, pl.is_vpl);
    // Through media, the shadow ray's transmittance (after the clamp, which bounds what the
    // light would give unshadowed).
    RGB tr(1.f);
    bool blocked;
    if (g.sampler) {
        tr = point_light_transmittance(scene, g, pl);
        blocked = tr.is_black();
    } else {
        blocked = scene.occluded(ray);
    }
    if (shadow) *shadow = blocked ? ShadowResult::Occluded : ShadowResult::Visible;
    if (blocked) return RGB();
    return weigh ? c * tr * w : c * tr;
}

RGB unshadowed_point_light(const PointLightSet& set, const ManyLightSettings& settings,
                           const PointLight& pl, const GatherPoint& g) {
    RGB c;
    Ray ray;
    if (!point_light_contribution(set, pl, g, &c, &ray)) return RGB();
    return settings.clamped(c, pl.is_vpl);
}

void read_vpl_sampler(const Settings& s, VplSamplerOptions* o) {
    o->kind = parse_vpl_sampler(
        s.get_string("vpl.sampler", vpl_sampler_name(o->kind),
                     {"standard, power, bidirectional, metropolis",
                      "How the VPLs are made: light paths from the lights by power (standard), by "
                      "each light's measured share of the image (power), from camera sub-paths "
                      "joined back to the lights (bidirectional), or by a Metropolis chain over "
                      "camera-to-light paths (metropolis; consistent, not unbiased)."}));
    // Each sampler reads only its own settings, so that another's is reported as unused.
    if (o->kind == VplSamplerKind::Power || o->kind == VplSamplerKind::Bidirectional)
        o->pilot = s.get_int("vpl.pilot", o->pilot,
                             {">= 1",
                              "Camera points the pilot traces to measure what each light (power) "
                              "or VPL position (bidirectional) gives the image."});
    if (o->kind == VplSamplerKind::Power)
        o->pilot_paths = s.get_int(
            "vpl.pilot_paths", o->pilot_paths,
            {">= 1", "Light paths the pilot traces to estimate each light's share of the image."});
    if (o->kind == VplSamplerKind::Bidirectional)
        o->candidates = s.get_int("vpl.candidates", o->candidates,
                                  {">= 1",
                                   "Candidates that bring light, per VPL kept, traced on average "
                                   "before resampling down to vpl.count."});
    if (o->kind == VplSamplerKind::Metropolis) {
        o->tries = s.get_int(
            "vpl.metropolis.tries", o->tries,
            {">= 1", "Proposals per Metropolis step (above 1: multiple-try Metropolis)."});
        o->mir_pilot = s.get_int("vpl.metropolis.pilot", o->mir_pilot,
                                 {">= 1",
                                  "Camera points, stratified over the film, on which each "
                                  "geometric VPL's power is measured."});
        o->mir_chains = s.get_int(
            "vpl.metropolis.chains", o->mir_chains,
            {">= 1", "Independent Metropolis chains, each started from a bootstrap path."});
        o->mir_large_step = s.get_float(
            "vpl.metropolis.large_step", o->mir_large_step,
            {"0 to 1",
             "Probability of a large step; the rest are small camera-side and light-side steps."});
        o->mir_cap =
            s.get_float("vpl.metropolis.cap", o->mir_cap,
                        {">= 0",
                         "Bound on a VPL's light at the first camera vertex in the chains' target, "
                         "times the bootstrap's power estimate (0: no bound)."});
    }
    if (!(o->mir_cap >= 0)) throw UsageError("vpl.metropolis.cap must be >= 0 (0: no bound)");
    if (o->mir_chains < 1) throw UsageError("vpl.metropolis.chains must be >= 1");
    if (!(o->mir_large_step >= 0 && o->mir_large_step <= 1))
        throw UsageError("vpl.metropolis.large_step must be in [0, 1]");
    if (o->pilot < 1 || o->pilot_paths < 1 || o->candidates < 1 || o->tries < 1 || o->mir_pilot < 1)
        throw UsageError(
            "vpl.pilot, vpl.pilot_paths, vpl.candidates, vpl.metropolis.tries and "
            "vpl.metropolis.pilot must be >= 1");
}

ManyLightSettings ManyLightSettings::read(const Settings& s, const Defaults& defaults) {
    ManyLightSettings m;
    m.max_depth = s.get_int("maxdepth", 5,
                            {">= 0",
                             "Longest light transport path, in bounces (the scene's `Integrator` "
                             "maxdepth, or --max-depth)."});
    if (defaults.gathers)
        m.medium_points = s.get_int(
            "gather.medium_points", m.medium_points,
            {">= 0",
             "Gather points on each stretch of a camera ray through a homogeneous medium, at "
             "distances drawn stratified by its transmittance, plus one towards a light at a point "
             "(0: one, where delta tracking finds the ray scatter)."});
    if (m.medium_points < 0 || m.medium_points > 256)
        throw UsageError("gather.medium_points must be 0 to 256");
    m.lights.vpl_count = s.get_int("vpl.count", kDefaultVplCount,
                                   {">= 0",
                                    "VPLs made from light paths (0: the emitters' point lights "
                                    "only); under --time-limit, the most made."});
    // A VPL deposited at a light path's b-th bounce lights paths of b + 1 bounces, so light
    // paths stop where the path tracer's would (maxdepth bounces) unless told otherwise.
    const bool vpl_depth_given = s.has("vpl.max_depth");
    m.lights.vpl_max_depth =
        s.get_int("vpl.max_depth", std::max(1, m.max_depth - 1),
                  {">= 1",
                   "VPLs along one light path; by default maxdepth - 1, so that VPLs carry light "
                   "over as many bounces as the path tracer."});
    std::string glossy =
        s.get_string("vpl.glossy", defaults.glossy,
                     {"bsdf, diffuse, skip",
                      "VPLs on glossy surfaces re-emit through the whole BSDF (bsdf), through its "
                      "diffuse part only (diffuse), or are not made (skip)."});
    if (glossy == "bsdf")
        m.lights.vpl_glossy = GlossyVpls::Bsdf;
    else if (glossy == "diffuse")
        m.lights.vpl_glossy = GlossyVpls::Diffuse;
    else if (glossy == "skip")
        m.lights.vpl_glossy = GlossyVpls::Skip;
    else
        throw UsageError("vpl.glossy must be bsdf, diffuse or skip, not " + glossy);
    // At maxdepth 1 (or 0) the path tracer's paths end at their first vertex: no VPL light,
    // unless vpl.max_depth asks for it.
    m.vpls_reach = vpl_depth_given || m.max_depth >= 2;
    m.lights.vpls = m.lights.vpl_count > 0 && m.vpls_reach;
    read_vpl_sampler(s, &m.lights.vpl_sampler);
    m.lights.vpl_focus = s.get_float(
        "vpl.focus", defaults.focus,
        {"0 to 0.99",
         "Share of the distant and infinite lights' VPL paths started towards what the camera "
         "sees, the rest over the whole scene (0: none); unbiased either way. Where the camera "
         "sees a room in a large scene, paths over the whole scene mostly miss it."});
    if (!(m.lights.vpl_focus >= 0 && m.lights.vpl_focus <= 0.99f))
        throw UsageError("vpl.focus must be 0 to 0.99");
    m.lights.area_count = s.get_int("lights.area_count", m.lights.area_count,
                                    {">= 1", "Point lights sampled on the area lights."});
    m.lights.env_count = s.get_int("lights.env_count", m.lights.env_count,
                                   {">= 1", "Directional lights sampled per environment map."});
    int seed =
        s.get_int("vpl.seed", -1,
                  {">= -1",
                   "Seed of the VPLs' light paths, the points on emitters and the light tree's "
                   "representatives (-1: the render's --seed)."});  // -1: follow --seed
    if (seed < -1) throw UsageError("vpl.seed must be >= 0 (or -1: from --seed)");
    if (seed >= 0) m.explicit_seed = uint64_t(seed);
    m.lights.seed = m.explicit_seed.value_or(0);
    m.clamp = s.get_float("vpl.clamp", defaults.clamp,
                          {">= 0",
                           "Most radiance one VPL gives a gather point, per channel (0: no clamp): "
                           "fewer spikes near VPLs, for light lost for good: a fixed bias that "
                           "more time does not take back, only when asked for."});
    // Read only by the integrators that build a light tree, so that others report it unused.
    if (defaults.tree_reps > 0) {
        m.tree_reps = s.get_int("tree.reps", defaults.tree_reps,
                                {"1 to 256",
                                 "Representatives each light-tree node keeps, drawn in proportion "
                                 "to luminance; each sample shades with one of them."});
        if (m.tree_reps < 1 || m.tree_reps > kLightTreeMaxReps)
            throw UsageError(fmt::format("tree.reps must be 1 to {}", kLightTreeMaxReps));
    }
    std::string direct = s.get_string(
        "lights.direct", defaults.direct,
        {"sample, points",
         "The area and environment lights' direct light: next-event estimation with MIS (sample) "
         "or point lights in the set (points); delta lights are always point lights."});
    if (direct == "sample")
        m.lights.sampled_direct = true;
    else if (direct != "points")
        throw UsageError("lights.direct must be points or sample, not " + direct);
    // Read only when sampling, so that a count given with `points` is reported as unused.
    if (m.lights.sampled_direct) {
        m.direct_samples = s.get_int(
            "lights.direct_samples", m.direct_samples,
            {">= 1",
             "Light samples (and BSDF samples) per gather point for the sampled direct light."});
        std::string mis =
            s.get_string("lights.direct_mis", "always",
                         {"always, glossy",
                          "Which gather points also take a BSDF sample, weighed by MIS, for the "
                          "direct light: all (always) or only those with a glossy lobe (glossy)."});
        if (mis != "always" && mis != "glossy")
            throw UsageError("lights.direct_mis must be always or glossy, not " + mis);
        m.direct_mis = mis == "always";
    }
    if (m.direct_samples < 1) throw UsageError("lights.direct_samples must be at least 1");
    if (m.max_depth < 0 || m.lights.vpl_count < 0 || m.lights.vpl_max_depth < 1 ||
        m.lights.area_count < 1 || m.lights.env_count < 1 || m.clamp < 0)
        throw UsageError("vpl settings out of range (counts >= 1, vpl.max_depth >= 1, clamp >= 0)");
    return m;
}

void ManyLightSettings::use_render_seed(uint64_t seed) {
    lights.seed = explicit_seed.value_or(seed);
    render_seed = lights.seed;
    // A render after one that took fewer VPLs for its later sets asks for the count again.
    if (first_vpl_request > 0) lights.vpl_count = first_vpl_request;
    first_vpl_request = 0;
}

bool ManyLightSettings::use_set(int64_t index, const PointLightSet& first) {
    if (!set_per_pass || index == 0) return false;
    lights.seed = hash_ints(render_seed, uint64_t(index));
    if (index == 1 && lights.vpl_budget.seconds > 0) {
        first_vpl_request = first.vpl_count_requested;
        lights.vpl_count = std::min(lights.vpl_count, int(first.vpls));
        lights.vpl_budget = VplBudget{};
    }
    return true;
}

void ManyLightSettings::use_first_set_vpls(int vpls) {
    if (!(lights.vpl_budget.seconds > 0) || vpls <= 0) return;
    first_vpl_request = lights.vpl_count;
    lights.vpl_count = std::min(lights.vpl_count, vpls);
    lights.vpl_budget = VplBudget{};
}

void read_vpl_sets(const Settings& s, ManyLightSettings* settings) {
    const std::string sets = s.get_string(
        "vpl.sets", "pass",
        {"pass, one",
         "A new, independent VPL set and light tree for every pass (pass: the image's error "
         "goes to zero with time), or one for the whole render (one: that set's error stays)."});
    if (sets != "pass" && sets != "one")
        throw UsageError("vpl.sets must be pass or one, not " + sets);
    settings->set_per_pass = sets == "pass";
}

namespace {

// The light tree's options as build_light_tree uses them.
LightTreeOptions light_tree_options(const Scene& scene, const ManyLightSettings& settings) {
    LightTreeOptions opts;
    opts.seed = settings.lights.seed;
    opts.scene_diagonal = length(scene.bounds().diagonal());
    opts.reps = settings.tree_reps;
    return opts;
}

}  // namespace

void ManyLightSettings::use_time_limit(const RenderContext& ctx, bool with_tree) {
    lights.vpl_budget = vpl_build_budget(ctx);
    if (!with_tree || !(lights.vpl_budget.seconds > 0)) return;
    LightTreeOptions opts = light_tree_options(ctx.scene, *this);
    lights.vpl_budget.also_timed = [opts](const PointLightSet& set) {
        [[maybe_unused]] LightTree tree(set.lights, opts);
    };
}

void build_many_lights(const Scene& scene, const ManyLightSettings& settings, PointLightSet* set,
                       SampledDirectLight* direct) {
    // The other samplers weigh VPLs by unshadowed or occluded pilot paths, blind to media.
    if (scene.has_media() && settings.lights.vpl_sampler.kind != VplSamplerKind::Standard)
        throw UsageError(fmt::format(
            "vpl.sampler={} does not handle participating media yet (use vpl.sampler=standard)",
            vpl_sampler_name(settings.lights.vpl_sampler.kind)));
    *set = build_point_light_set(scene, settings.lights);
    // A later set (use_set) reports the count the user asked for, as the first did.
    if (settings.first_vpl_request > 0) set->vpl_count_requested = settings.first_vpl_request;
    *direct = settings.lights.sampled_direct
                  ? SampledDirectLight(scene, settings.direct_samples, settings.direct_mis)
                  : SampledDirectLight();
}

std::string capped_cut_warning(const std::string& integrator, const char* what, double capped,
                               int max_cut, const PointLightSet& set, int time_cap) {
    if (!(capped > 0.1)) return "";
    if (time_cap > 0 && time_cap < max_cut)
        return fmt::format(
            "{0}: to end a pass within --time-limit, cuts stopped at {3} (not {0}.max_cut, {4}); "
            "{1:.0f}% of {2} reached it, where the error is not bounded by {0}.error (more "
            "noise): a longer time limit lifts the cap",
            integrator, 100 * capped, what, time_cap, max_cut);
    return fmt::format(
        "{0}: {1:.0f}% of {2} reached {0}.max_cut ({3}), where the error is not bounded by "
        "{0}.error{4}",
        integrator, 100 * capped, what, max_cut,
        set.glossy > 0 ? "; glossy VPLs with sharp lobes do that (vpl.glossy=diffuse keeps their "
                         "diffuse part only)"
                       : "");
}

nlohmann::json cut_cap_json(const CutCapPlan& plan) {
    return {{"cap", plan.cap},
            {"full_pass_seconds", plan.full_seconds},
            {"capped_pass_seconds", plan.capped_seconds},
            {"probe_mean_cut", plan.mean_full_size},
            {"samples_scale", plan.samples_scale},
            {"fixed_share", plan.fixed_share}};
}

nlohmann::json pass_plan_json(const CutCapPlan& plan, int first_set_vpls) {
    nlohmann::json j = cut_cap_json(plan);
    j["first_set_vpls"] = first_set_vpls;
    return j;
}

bool read_pass_plan(const nlohmann::json& state, CutCapPlan* plan, int* first_set_vpls) {
    if (!state.contains("pass_plan")) return false;
    try {
        const nlohmann::json& j = state.at("pass_plan");
        plan->cap = j.at("cap").get<int>();
        plan->full_seconds = j.at("full_pass_seconds").get<double>();
        plan->capped_seconds = j.at("capped_pass_seconds").get<double>();
        plan->mean_full_size = j.at("probe_mean_cut").get<double>();
        plan->samples_scale = j.at("samples_scale").get<double>();
        plan->fixed_share = j.at("fixed_share").get<double>();
        *first_set_vpls = j.at("first_set_vpls").get<int>();
    } catch (const nlohmann::json::exception& e) {
        throw UsageError(std::string("--resume: a damaged checkpoint (") + e.what() + ")");
    }
    return true;
}

ResumedPasses resume_passes(const RenderContext& ctx, ManyLightSettings& settings) {
    ResumedPasses r;
    if (!ctx.checkpoint || !ctx.checkpoint->resuming()) return r;
    r.state = &ctx.checkpoint->integrator_state();
    r.planned = read_pass_plan(*r.state, &r.plan, &r.first_set_vpls);
    if (r.planned) settings.use_first_set_vpls(r.first_set_vpls);
    return r;
}

nlohmann::json many_light_figures(const PointLightSet& set, const SampledDirectLight& direct) {
    nlohmann::json j = {{"point_light_seconds", set.seconds},
                        {"omni", set.omni},
                        {"oriented", set.oriented},
                        {"directional", set.directional},
                        {"glossy", set.glossy},
                        {"light_paths", set.light_paths},
                        {"direct", direct.empty() ? "points" : "sample"},
                        {"direct_samples", direct.empty() ? 0 : direct.samples()},
                        {"direct_mis", direct.mis() ? "always" : "glossy"}};
    j.update(vpl_focus_json(set));
    j.update(vpl_budget_json(set));
    return j;
}

nlohmann::json vpl_focus_json(const PointLightSet& set) {
    if (!(set.focus_share > 0)) return nlohmann::json::object();
    return {{"vpl_focus", {{"share", set.focus_share}, {"radius", set.focus_radius}}}};
}

LightTree build_light_tree(const Scene& scene, const ManyLightSettings& settings,
                           const PointLightSet& set, double* seconds) {
    auto t0 = std::chrono::steady_clock::now();
    LightTree tree(set.lights, light_tree_options(scene, settings));
    *seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return tree;
}

}  // namespace ml
