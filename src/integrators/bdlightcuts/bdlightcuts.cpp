#include "integrators/bdlightcuts/bdlightcuts.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

#include "core/parallel.h"
#include "core/rng.h"
#include "core/stats.h"
#include "integrators/bdlightcuts/eye_path.h"
#include "integrators/bdlightcuts/pair_weights.h"
#include "manylight/gather.h"
#include "manylight/gather_tree.h"
#include "manylight/pilot.h"
#include "manylight/sample_shares.h"
#include "manylight/vpl_sampler.h"
#include "materials/material.h"
#include "render/render_loop.h"
#include "transport/direct_lighting.h"
#include "transport/mis.h"
#include "transport/path_tracer.h"
#include "transport/spawn.h"
#include "transport/volume_path.h"

namespace ml {

namespace {

// A setting that takes one of two words (doc.range lists both): true for `yes`.
bool read_either(const Settings& settings, const char* key, bool def, const char* yes,
                 const char* no, const SettingDoc& doc) {
    const std::string v = settings.get_string(key, def ? yes : no, doc);
    if (v != yes && v != no)
        throw UsageError(std::string("bdlightcuts.") + key + " must be " + yes + " or " + no +
                         ", not '" + v + "'");
    return v == yes;
}

// Representatives per light-tree node (tree.reps). Every pixel draws its cut's from the same
// few, so their errors add up over the image and move its mean with the seed: with 32 instead of
// 8 the kitchen's red mean spreads a third as much between seeds, for relMSE 6% lower at 2% more
// CPU (bench/RESULTS.md, "Issue 17, session 19"; mdlightcuts, whose error is mostly its bias,
// gains nothing from them).
constexpr int kTreeReps = 32;
// Camera points that place the VPL region (as the emission focus's).
constexpr int kRegionPoints = 1024;

}  // namespace

struct BdLightcutsIntegrator::ThreadState {
    ThreadState(std::unique_ptr<Sampler> s, ProductCut c, SplitWeighting w)
        : sampler(std::move(s)), cut(std::move(c)), weighting(std::move(w)) {}
    std::unique_ptr<Sampler> sampler;
    ScratchBuffer scratch;
    ProductCut cut;
    SplitWeighting weighting;
    GatherTree tree;
    std::vector<WeightedGatherPoint> points;
    std::vector<Vsp> vsps;
    std::vector<Vec3> positions;
    std::vector<RGB> weights;
    std::vector<float> uniforms;
    std::vector<uint8_t> groups;  // the VSPs' eye depths, with `vsp_tree=depth`
};

BdLightcutsIntegrator::BdLightcutsIntegrator(const Settings& settings) {
    // The point-light set is `vpl`'s, with the emitters as point lights, whole BSDFs at the VPLs
    // and no clamping: the split weights do what those settings do for `vpl`.
    // lights.direct defaults to sample: bench/RESULTS.md, "Issue 17, session 14".
    // Its eye paths find their own vertices in media (delta tracking): gather.medium_points is
    // not its setting.
    // vpl.focus 0.5 fills the VPL region (render()): without it the region would take about
    // 60 times the light paths on the classroom.
    m_settings = ManyLightSettings::read(settings, {"bsdf", 0.f, "sample", kTreeReps, false, 0.5f});
    read_vpl_sets(settings, &m_settings);
    // lights.direct=sample: the split that joins a VSP to an emitter by a light sample at the
    // VSP, weighed by MIS against the eye path's BSDF sample, instead of the emitters' points
    // in the cut (the delta lights stay points).
    m_direct_sample = m_settings.lights.sampled_direct;
    if (m_direct_sample &&
        settings.get_int("lights.direct_samples", 1,
                         {"1", "One light sample per VSP (the split weights need it)."}) != 1)
        throw UsageError("bdlightcuts: lights.direct_samples must be 1 (one light sample per VSP)");
    m_settings.direct_samples = 1;
    if (settings.get_string("vpl.glossy", "bsdf",
                            {"bsdf",
                             "VPLs re-emit through their whole BSDF (the diffuse weight does what "
                             "the other choices do)."}) != "bsdf")
        throw UsageError("bdlightcuts: vpl.glossy must be bsdf (the diffuse weight replaces it)");
    if (settings.get_float("vpl.clamp", 0.f,
                           {"0", "No clamp (the clamping weight does its work)."}) != 0.f)
        throw UsageError("bdlightcuts: vpl.clamp must be 0 (the clamping weight replaces it)");
    m_settings.lights.vpl_glossy = GlossyVpls::Bsdf;
    m_settings.clamp = 0;

    m_samples =
        settings.get_int("samples", m_samples,
                         {">= 1", "Eye paths per pixel pass, shaded together by one product cut."});
    m_eye_length = settings.get_int("eye_length", m_eye_length,
                                    {">= 1",
                                     "Virtual sensor points (VSPs) per eye path; the eye path "
                                     "looks one bounce further for emission."});
    m_rest_path = read_either(settings, "rest", m_rest_path, "path", "drop",
                              {"path, drop",
                               "The weight no split up to the eye-path length takes: path traced "
                               "past the last VSP (path) or lost, a darkening (drop)."});
    m_rest_paths = settings.get_int(
        "rest_paths", m_rest_paths,
        {">= 1", "Remainder paths traced from each continued eye path, averaged."});
    if (m_rest_paths < 1) throw UsageError("bdlightcuts.rest_paths must be at least 1");
    m_guiding = read_either(
        settings, "guiding", m_guiding, "on", "off",
        {"on, off",
         "Path guiding of the remainder paths: each pass's remainders are guided by what the "
         "remainders before them learned (path.guiding's tree), without Russian roulette."});
    m_tree_by_depth =
        read_either(settings, "vsp_tree", m_tree_by_depth, "depth", "position",
                    {"depth, position",
                     "The VSP tree splits VSPs by eye depth before position (depth) or by "
                     "position alone (position)."});
    m_emission_mis =
        read_either(settings, "emission", m_emission_mis, "mis", "hit",
                    {"mis, hit",
                     "The emitter met by the eye path: BSDF samples and a light sample "
                     "weighed by MIS (mis), or BSDF samples alone (hit)."});
    m_emission_samples = settings.get_int("emission_samples", m_emission_samples,
                                          {">= 1",
                                           "BSDF samples for the emission met from a glossy eye "
                                           "vertex, weighed against the light sample by MIS."});
    if (m_emission_samples < 1) throw UsageError("bdlightcuts.emission_samples must be at least 1");
    m_error = settings.get_float(
        "error", m_error,
        {">= 0",
         "Relative error bound of each VSP-light pair against the pixel's estimate (with "
         "refine=bounds, its eye paths' part)."});
    m_max_cut = settings.get_int("max_cut", m_max_cut, {">= 1", "Most pairs in one product cut."});
    m_refine_by_bounds = read_either(
        settings, "refine", m_refine_by_bounds, "bounds", "estimates",
        {"bounds, estimates",
         "Which pair the cut splits next: the largest bound, with a tolerance relative to the eye "
         "paths' part (bounds: the cut's mean does not depend on max_cut), or the largest of "
         "bound and estimate, relative to the running estimate (estimates, as mdlightcuts)."});
    m_vpl_region = read_either(
        settings, "vpl_region", m_vpl_region, "view", "scene",
        {"view, scene",
         "Where the VPLs are, in a scene lit by distant or infinite lights (with eye_length 1, "
         "rest=path and no media): only within the sphere around what the camera sees, the light "
         "of the rest path traced by the remainders (view), or everywhere (scene)."});
    m_set_share = settings.get_float(
        "vpl.set_share", m_set_share,
        {"0 to 1",
         "With vpl.sets=pass under a time limit, where the cuts are small (at most 8 pairs: the "
         "VPLs carry little of the image): the most share of a pass that making its VPL set and "
         "light tree may take; a set that costs more serves as many passes as keep it within "
         "that share (0: a new set every pass)."});
    if (!(m_set_share >= 0 && m_set_share <= 1)) throw UsageError("vpl.set_share must be 0 to 1");
    m_floor = settings.get_float("floor", m_floor, {">= 0", "Error floor, as lightcuts.floor."});
    m_adaptive = settings.get_bool("adaptive", m_adaptive,
                                   {"",
                                    "After the first pass each pixel takes a share of the later "
                                    "passes' samples from its neighbours' noise."});
    m_weights.energy = settings.get_bool(
        "energy", m_weights.energy,
        {"", "The energy-conservation weight of each split (alone: the unbiased limit)."});
    m_weights.clamp = settings.get_bool(
        "clamp", m_weights.clamp,
        {"",
         "The clamping weight: a VSP-VPL join above c_clamp leaves the rest to longer eye paths."});
    m_weights.diffuse = settings.get_bool(
        "diffuse", m_weights.diffuse,
        {"", "The diffuse weight: VPLs whose lobe towards the VSP exceeds c_d are weighted down."});
    m_weights.variance = settings.get_bool(
        "variance", m_weights.variance,
        {"",
         "The variance weight: eye paths of large directional spread are left to longer splits."});
    m_weights.c_clamp = settings.get_float("c_clamp", m_weights.c_clamp,
                                           {"> 0", "C_clamp of the clamping weight."});
    m_weights.c_d = settings.get_float("c_d", m_weights.c_d, {"> 0", "C_D of the diffuse weight."});
    m_weights.spread =
        settings.get_float("spread", m_weights.spread,
                           {"> 0",
                            "Directional spread of the eye path (radians) at which the variance "
                            "weight falls to 0; it is 1 up to half of it."});
    if (m_samples < 1) throw UsageError("bdlightcuts.samples must be at least 1");
    if (m_eye_length < 1) throw UsageError("bdlightcuts.eye_length must be at least 1");
    if (!(m_error >= 0) || m_max_cut < 1)
        throw UsageError("bdlightcuts: error must be >= 0 and max_cut >= 1");
    if (!(m_floor >= 0)) throw UsageError("bdlightcuts.floor must be >= 0");
    if (!(m_weights.c_clamp > 0) || !(m_weights.c_d > 0) || !(m_weights.spread > 0))
        throw UsageError("bdlightcuts: c_clamp, c_d and spread must be > 0");
}

RGB BdLightcutsIntegrator::trace_eye(const Scene& scene, Ray ray, Sampler& sampler, ThreadState& ts,
                                     float filter_weight, bool* rested) const {
    RGB L;
    EyeState s;
    int vsps = 0;
    SurfaceInteraction si;
    // The share of the emission met at this hit that this path carries: 1 / the previous
    // vertex's BSDF samples for emission (the others are traced there, emission_samples).
    float emission_share = 1;
    // In a scene with media: the medium the path is in, and whether this vertex is a scattering
    // inside it (its BSDF the phase function) rather than on a surface.
    const bool media = scene.has_media();
    const Medium* medium = media ? scene.camera_medium() : nullptr;
    for (int depth = 0;; ++depth) {  // depth: scattering vertices before this hit
        bool hit, in_medium = false;
        Bsdf phase;
        // The last stretch through a grey homogeneous medium, for the MIS of a VSP drawn on it.
        GreyTracking grey;
        UnitRay stretch_ray{};
        if (media) {
            // On each stretch through a homogeneous medium of grey extinction, where the next
            // vertex can be a VSP: one point drawn equiangularly towards a point or spot light
            // (chosen by power), joined to it with the split weight a VSP there would have,
            // weighed by MIS against delta tracking's VSPs of the stretch joined to it (their
            // 1 / d^2 next to the light is unbounded; the equiangular density cancels it).
            StretchFn stretch;
            if (!m_eq_lights.empty() && vsps < m_eye_length && depth < m_settings.max_depth)
                stretch = [&](const Medium& m, const UnitRay& u, const RGB& beta) {
                    grey = GreyTracking(m, beta);
                    stretch_ray = u;
                    const float u_select = sampler.get_1d(), u_t = sampler.get_1d();
                    if (!grey.valid) return;
                    float pmf = 0;
                    const PointLight& pl =
                        m_set.lights[m_eq_lights[m_eq_choice.sample_discrete(u_select, &pmf)]];
                    const Equiangular eq(u.ray, u.tmax, pl.p);
                    if (!eq.valid || !(pmf > 0)) return;
                    const float t = eq.sample(u_t);
                    if (!(t >= 0 && t < u.tmax)) return;
                    const float p_eq = pmf * eq.pdf_length(t), p_track = grey.pdf_length(t);
                    const MediumProperties mp = m.at(u.ray.at(t));
                    GatherPoint g = medium_gather_point(
                        u.ray.at(t), u.ray.d, ray.time, &m,
                        beta * mp.sigma_s * (std::exp(-grey.sigma_t * t) / p_eq), ts.scratch);
                    g.sampler = &sampler;
                    Vsp v;
                    v.prefix = s.prefix;
                    v.pending_mu = s.pending_mu;
                    v.mu = spread_mu(m_weights, s.theta);
                    v.depth = depth + 1;
                    if (s.pending)
                        v.pending_mt =
                            s.pending_m / std::max(1e-12f, length_squared(g.si.p - s.pending_p));
                    L += visible_point_light(scene, m_set, m_settings, pl, g, nullptr,
                                             [&](const PointLightTerms& terms) {
                                                 return ts.weighting.weight(v, g, pl, terms) *
                                                        power_heuristic(p_eq, p_track);
                                             });
                };
            // Light emitted by the media: no split reaches it (no light path starts in a
            // medium), so the eye path takes all it meets, as `path` counts it.
            RGB glow;
            const bool glows = m_glowing && depth < m_settings.max_depth;
            const EyeHit h = next_eye_hit(scene, &ray, sampler, ts.scratch, &medium, &s.beta, &si,
                                          &phase, stretch, glows ? &glow : nullptr);
            L += glow;
            if (h == EyeHit::Absorbed) break;
            hit = h != EyeHit::Escaped;
            in_medium = h == EyeHit::Medium;
        } else {
            hit = scene.intersect(ray, &si);
        }
        float t_prev = 1.f;
        if (s.pending && hit) t_prev = 1.f / std::max(1e-12f, length_squared(si.p - s.pending_p));
        if (!in_medium)
            L += met_emission(scene, ray, hit ? &si : nullptr, s, t_prev, m_weights,
                              m_nee_lights.get()) *
                 emission_share;
        emission_share = 1;
        if (!hit || depth >= m_settings.max_depth) break;
        if (vsps >= m_eye_length) {
            // The remainder: paths through x_{J+1} = si longer than the eye path, weighted by
            // what splits 1 ... J leave (trace_eye's prefix and pending split are r's inputs).
            float pending_mt = s.pending ? s.pending_m * t_prev : -1.f;
            // No VPL outside the VPL region (render()): split J weighs 0 on the paths whose
            // x_{J+1} is there, and the remainder takes their whole share.
            if (m_settings.lights.vpl_region.excludes(si.p)) pending_mt = -1.f;
            // (With glowing media it goes on for their light even where r vanishes.)
            if (m_rest_path && (m_glowing || !remainder_vanishes(m_weights, s.prefix, pending_mt,
                                                                 kInfinity, s.pending_mu))) {
                RemainderWeight r(m_weights, s.prefix, pending_mt, s.pending_mu, in_medium);
                // `rest_paths` of them, averaged (each with the whole throughput, which their
                // Russian roulette looks at).
                PathTraceOptions options{m_settings.max_depth, 1};
                if (m_guide) {
                    options.guide = m_guide.get();
                    options.guide_record = true;
                    options.rr_depth = std::numeric_limits<int>::max();  // as path.guiding's
                    m_guide_paths.fetch_add(uint64_t(m_rest_paths), std::memory_order_relaxed);
                }
                for (int i = 0; i < m_rest_paths; ++i) {
                    RGB rp = media ? continue_volumetric(scene, VolumeVertex{si, medium, in_medium},
                                                         depth, s.beta, sampler, ts.scratch,
                                                         *m_nee_lights, options, &r)
                                   : continue_path(scene, si, depth, s.beta, sampler, ts.scratch,
                                                   *m_nee_lights, options, &r);
                    L += rp / float(m_rest_paths);
                }
                *rested = true;
            }
            break;
        }
        Bsdf bsdf = in_medium ? phase : hit_bsdf(si, ts.scratch);
        if (!bsdf) break;
        Vec3 n = bsdf.frame().n;
        // Where the vertex is, for the transmittance of its shadow rays through the media.
        const DirectMedia here{medium, in_medium, &sampler};
        const DirectMedia* through = media ? &here : nullptr;
        if (bsdf.has_nonspecular()) {
            // A VSP whose pairs all weigh 0 stays out of the VSP tree (vsp_weight_bound).
            float u_rep = sampler.get_1d();
            float mu = spread_mu(m_weights, s.theta),
                  pending_mt = s.pending ? s.pending_m * t_prev : -1.f;
            if (vsp_weight_bound(m_weights, s.prefix, pending_mt, max_vsp_density(bsdf, si.wo),
                                 s.pending_mu, mu) > 0) {
                Vsp v;
                v.prefix = s.prefix;
                v.pending_mt = pending_mt;
                v.pending_mu = s.pending_mu;
                v.mu = mu;
                v.depth = depth + 1;
                if (in_medium && grey.valid) {
                    v.eq_o = stretch_ray.ray.o;
                    v.eq_d = stretch_ray.ray.d;
                    v.eq_tmax = stretch_ray.tmax;
                    v.eq_t = dot(si.p - v.eq_o, v.eq_d);
                    v.eq_track = grey.pdf_length(v.eq_t);
                }
                ts.vsps.push_back(v);
                GatherPoint g{si, bsdf, s.beta};
                if (media) {
                    g.medium = medium;
                    g.in_medium = in_medium;
                    g.sampler = &sampler;
                }
                ts.points.push_back({g, filter_weight, RGB(), int32_t(ts.vsps.size() - 1)});
                ts.uniforms.push_back(u_rep);
            }
            ++vsps;
        }
        // Split j to an emitter by a light sample (`lights.direct=sample`). The weight is split
        // j's for that point (SplitWeighting::weight's for an emitter's point). f_ls:
        // bsdf.eval(si.wo, ls.wi), as estimate_direct has it.
        auto split_to_light = [&](const Light& light, const LightLiSample& ls, const RGB& f_ls,
                                  float* pre_j) {
            float f = f_ls.max_component();
            float pre = s.prefix;
            if (s.pending) {
                float d = eye_lobe_density(f, si.wo, ls.wi, n, in_medium);
                pre += split_weight(m_weights, pre, s.pending_m * t_prev * d, d, s.pending_mu);
            }
            float m = f * abs_dot(ls.wi, si.ns), dk = 0, t = 1;
            if (light.type() == LightType::Area) {
                dk = abs_dot(ls.n_light, ls.wi) / kPi;
                t = 1.f / std::max(1e-12f, length_squared(ls.p_light - si.p));
            }
            *pre_j = pre;
            return split_weight(m_weights, pre, m * t * dk, dk, spread_mu(m_weights, s.theta));
        };
        // The last split's weight for the emitter met from x_j along wi (x_{j+1} on it), w_j
        // being split j's for that point and pre the weights before it.
        auto last_split = [&](float pre, float w_j) {
            return emission_weight(m_weights, pre + w_j);
        };
        // Whether split j's light sample is weighed by MIS, and whether it also carries the last
        // split's weight (emission=mis: the same path, x_j joined to a point of the emitter).
        bool direct_mis = false, last_by_light = false;
        // BSDF samples for the emission met from here: more than one at a glossy eye vertex,
        // whose reflections of small bright emitters the light sample rarely finds
        // (bdlightcuts.emission_samples).
        int bsdf_samples = 1;
        if (m_direct_sample && bsdf.has_nonspecular()) {
            direct_mis = m_settings.direct_mis || (bsdf.flags() & kBxdfGlossy);
            last_by_light = m_emission_mis && direct_mis;
            if (last_by_light && (bsdf.flags() & kBxdfGlossy)) bsdf_samples = m_emission_samples;
            float u_select = sampler.get_1d();
            Vec2 u_light = sampler.get_2d();
            if (auto sl = m_nee_lights->sample(vertex_context(si, in_medium), u_select);
                sl && !is_delta_light(sl->light->type())) {
                const Light& light = *sl->light;
                auto split_j = [&](const LightLiSample& ls, const RGB& f_ls) {
                    float pre;
                    float w = split_to_light(light, ls, f_ls, &pre);
                    return last_by_light ? w + last_split(pre, w) : w;
                };
                L += s.beta *
                     estimate_direct(scene, si, bsdf, light, u_light, direct_mis, sl->pmf, split_j,
                                     bsdf_samples, {}, through) /
                     sl->pmf;
            }
        }
        // The last split's own light sample (`bdlightcuts.emission=mis` with
        // `lights.direct=points`): the emitter met from x_j along a light sample instead of the
        // BSDF's, with the same weight as there (w_{j-1} with D_j towards it, then what w_j
        // leaves).
        if (m_emission_mis && !m_direct_sample && bsdf.has_nonspecular()) {
            float u_select = sampler.get_1d();
            Vec2 u_light = sampler.get_2d();
            if (auto sl = m_nee_lights->sample(vertex_context(si, in_medium), u_select);
                sl && !is_delta_light(sl->light->type())) {
                const Light& light = *sl->light;
                auto last_only = [&](const LightLiSample& ls, const RGB& f_ls) {
                    float pre;
                    const float w_j = split_to_light(light, ls, f_ls, &pre);
                    return last_split(pre, w_j);
                };
                L += s.beta *
                     estimate_direct(scene, si, bsdf, *sl->light, u_light, true, sl->pmf, last_only,
                                     1, {}, through) /
                     sl->pmf;
            }
        }
        // The other BSDF samples for the emission met from here: each finds the next hit alone,
        // and every sample's emission there counts 1 / bsdf_samples (MIS by the counts).
        for (int k = 1; k < bsdf_samples; ++k) {
            float uc = sampler.get_1d();
            Vec2 u = sampler.get_2d();
            auto bs = bsdf.sample(si.wo, uc, u);
            if (!bs) continue;
            EyeState e = s;
            if (!scatter(e, si, in_medium, bsdf, *bs, direct_mis, last_by_light, bsdf_samples,
                         t_prev, m_weights, m_direct_sample, m_emission_mis))
                continue;
            Ray r = spawn_ray(si, bs->wi);
            SurfaceInteraction next;
            bool next_hit;
            // Through media, the emission met on the first surface past their interfaces, times
            // the transmittance up to it (the main path's own scattering there is its own).
            RGB tr(1.f);
            if (media)
                tr = transmittance_to_surface(scene, r,
                                              in_medium ? medium : medium_after(si, bs->wi, medium),
                                              sampler, &next, &next_hit);
            else
                next_hit = scene.intersect(r, &next);
            if (tr.is_black()) continue;
            float t_next = 1.f;
            if (e.pending && next_hit)
                t_next = 1.f / std::max(1e-12f, length_squared(next.p - e.pending_p));
            L += tr *
                 met_emission(scene, r, next_hit ? &next : nullptr, e, t_next, m_weights,
                              m_nee_lights.get()) /
                 float(bsdf_samples);
        }
        float uc = sampler.get_1d();
        Vec2 u = sampler.get_2d();
        auto bs = bsdf.sample(si.wo, uc, u);
        if (!bs) break;
        if (!scatter(s, si, in_medium, bsdf, *bs, direct_mis, last_by_light, bsdf_samples, t_prev,
                     m_weights, m_direct_sample, m_emission_mis))
            break;
        emission_share = 1.f / float(bsdf_samples);
        ray = spawn_ray(si, bs->wi);
        if (media && !in_medium) medium = medium_after(si, bs->wi, medium);
    }
    return L;
}

RenderResult BdLightcutsIntegrator::render(const RenderContext& ctx) {
    // pbrt-v4's invisible light (an emitter of alpha 0): no eye path meets it, so the last split
    // (the emitter met) must come from light samples alone, each of MIS weight 1: with
    // emission=mis and light samples weighed by MIS at every VSP (lights.direct_mis=always, with
    // lights.direct=sample), the defaults. Else the part the BSDF's hits would have taken is lost
    // (tests/scenes/light_invisible with emission=hit or direct_mis=glossy: -18%).
    const bool last_split_by_light = m_emission_mis && (!m_direct_sample || m_settings.direct_mis);
    for (const auto& l : ctx.scene.lights())
        if (l->type() == LightType::Area && !l->met_by_rays() && !last_split_by_light)
            throw UsageError(
                "bdlightcuts: an invisible light (an emitting shape of \"alpha\" 0) needs "
                "bdlightcuts.emission=mis and lights.direct_mis=always (the defaults): no eye path "
                "meets it");
    if (m_guiding && ctx.scene.has_media())
        throw UsageError(
            "bdlightcuts.guiding: the remainder paths are not guided in participating media "
            "(the guide learns surface directions); render with bdlightcuts.guiding=off");
    m_glowing = ctx.scene.has_emitting_media();
    if (m_glowing && !m_rest_path)
        throw UsageError(
            "bdlightcuts.rest=drop: the scene's media emit light, which only the eye paths and "
            "their remainders carry; render with bdlightcuts.rest=path");
    m_settings.use_render_seed(ctx.seed);
    m_settings.lights.camera = &ctx.camera;
    // The VPL region: light paths from the sun and the sky start on a disk over the whole scene
    // and mostly end far from what the camera sees (the classroom's ground, 220 m across, holds
    // 99% of its VPLs), where the few that light the view make each set's light uncertain by
    // about 5%. Within the region the VPLs are many (vpl.focus sends half the paths there); the
    // light of paths through the rest is the remainders'.
    VplRegion& region = m_settings.lights.vpl_region;
    region = VplRegion{};
    if (m_vpl_region && m_rest_path && m_eye_length == 1 && !ctx.scene.has_media() &&
        has_disk_light(ctx.scene) &&
        !camera_focus_sphere(ctx.scene, ctx.camera, kRegionPoints,
                             hash_ints(ctx.seed, 0x726567696f6eULL), &region.center,
                             &region.radius))
        region = VplRegion{};
    RenderResult result;
    m_guide.reset();
    m_guide_paths = 0;
    if (m_guiding && m_rest_path) {
        if (ctx.ranks() > 1)
            result.warnings.push_back(
                "bdlightcuts: guiding runs in one process; rendered without it");
        else
            m_guide = std::make_unique<SDTree>(ctx.scene.bounds());
    }
    double guide_seconds = 0;
    m_settings.use_time_limit(ctx, true);
    SampledDirectLight unused_direct;
    if (m_rest_path || m_emission_mis || m_direct_sample)
        m_nee_lights = std::make_unique<LightSampler>("tree", ctx.scene.lights());
    // The point-light set, its tree and each light node's flux: the first pass's, then each
    // pass's own (vpl.sets=pass), made between passes while no thread shades.
    int sets = 0;  // the VPL sets drawn
    auto build_set = [&] {
        ++sets;
        build_many_lights(ctx.scene, m_settings, &m_set, &unused_direct);
        m_tree = build_light_tree(ctx.scene, m_settings, m_set, &m_tree_seconds);
        m_node_flux = light_node_flux(m_set, m_tree);
        // The point and spot lights, by power, for the equiangular samples in grey media.
        m_eq_lights.clear();
        m_eq_pmf.assign(ctx.scene.has_media() ? m_set.lights.size() : 0, 0.f);
        std::vector<float> power;
        for (size_t i = 0; i < m_eq_pmf.size(); ++i)
            if (point_emitter(m_set.lights[i])) {
                m_eq_lights.push_back(uint32_t(i));
                power.push_back(std::max(1e-20f, m_set.lights[i].intensity.luminance()));
            }
        if (!m_eq_lights.empty()) {
            m_eq_choice = Distribution1D(power);
            for (size_t k = 0; k < m_eq_lights.size(); ++k)
                m_eq_pmf[m_eq_lights[k]] = m_eq_choice.pmf(k);
        }
    };
    // A resumed render takes the first run's plan (many_lights.h: read_pass_plan) and figures.
    Checkpoint* checkpoint = ctx.checkpoint;
    const ResumedPasses resumed_passes = resume_passes(ctx, m_settings);
    const nlohmann::json* resumed = resumed_passes.state;
    const bool planned = resumed_passes.planned;
    const CutCapPlan& resumed_plan = resumed_passes.plan;
    int first_set_vpls = resumed_passes.first_set_vpls;
    build_set();
    if (!planned && m_settings.lights.vpl_budget.seconds > 0) first_set_vpls = int(m_set.vpls);
    m_pair_sum = 0, m_pixel_passes = 0, m_vsps = 0, m_capped = 0, m_rests = 0;
    std::atomic<uint64_t>* counters[] = {&m_pair_sum, &m_pixel_passes, &m_vsps, &m_capped,
                                         &m_rests};
    const char* counter_names[] = {"pair_sum", "pixel_passes", "vsps", "capped", "rests"};
    for (size_t i = 0; resumed && i < std::size(counters); ++i) {
        if (!resumed->contains(counter_names[i]))
            throw UsageError("--resume: a damaged checkpoint (no bdlightcuts figures)");
        *counters[i] = resumed->at(counter_names[i]).get<uint64_t>();
    }
    ThreadLocal<ThreadState> states([&] {
        SplitWeighting w(m_set, m_weights, m_settings.max_depth);
        w.node_flux = &m_node_flux;
        w.eq_pmf = &m_eq_pmf;
        return ThreadState(ctx.sampler.clone(), ProductCut(ctx.scene, m_set, m_tree, m_settings),
                           std::move(w));
    });
    m_floor_luminance = 0;
    if (m_floor > 0)
        m_floor_luminance = float(
            m_floor * pilot_mean_luminance(ctx.film.width(), ctx.film.height(), [&](Point2i pixel) {
                return estimate_pass(ctx, states.local(), pixel, 0, kPilotMaxCut).value;
            }));
    // Under a time limit, the cut cap that lets the first pass end in time (manylight/pilot.h).
    m_pass_samples = m_samples;
    const CutCapPlan cap_plan =
        planned ? resumed_plan
                : plan_pass_cut_cap(
                      ctx, m_max_cut, m_samples, [&](Point2i pixel, int cap, int samples) {
                          return estimate_pass(ctx, states.local(), pixel, 0, cap, samples).pairs;
                      });
    const int pass_cap = cap_plan.cap;
    m_pass_samples = pass_samples(m_samples, cap_plan);
    // The passes each VPL set serves: under a time limit, where the cuts are small, as many as
    // keep making the sets within m_set_share of the passes' time (passes that cost little
    // beside their sets would otherwise spend much of the limit on them: coffee's 12%);
    // passes_per_set says where. 1 without a limit, so that an image rendered to a sample count
    // does not depend on the machine's speed.
    int set_period = 1;
    if (planned) {
        const auto it = resumed->find("set_period");
        if (it != resumed->end()) {
            if (!it->is_number_integer() || it->get<int64_t>() < 1)
                throw UsageError("--resume: a damaged checkpoint (bdlightcuts' set_period)");
            set_period = int(std::min<int64_t>(it->get<int64_t>(), 1000000));
        }
    } else if (m_settings.set_per_pass) {
        set_period = passes_per_set(m_set.seconds + m_tree_seconds, cap_plan.capped_seconds,
                                    m_set_share, cap_plan.mean_full_size);
        // Every rank draws the same sets (its own timings differ).
        if (ctx.ranks() > 1) set_period = int(ctx.world->all_min(int64_t(set_period)));
    }
    if (checkpoint)
        checkpoint->set_state([&] {
            nlohmann::json state = {{"pass_plan", pass_plan_json(cap_plan, first_set_vpls)},
                                    {"set_period", set_period}};
            for (size_t i = 0; i < std::size(counters); ++i)
                state[counter_names[i]] = counters[i]->load();
            return state;
        });
    // The cap of the pass being shaded: pass_cap, then the last pass's (manylight/pilot.h).
    int cap = pass_cap;
    // One pixel pass, into the film and the figures.
    auto shade = [&](Point2i pixel, int first, int samples) {
        PassEstimate e = estimate_pass(ctx, states.local(), pixel, first, cap, samples);
        if (e.weight_sum == 0) return e;
        ctx.film.add_sample(pixel, e.value, float(e.weight_sum));
        m_pair_sum.fetch_add(uint64_t(e.pairs), std::memory_order_relaxed);
        m_pixel_passes.fetch_add(1, std::memory_order_relaxed);
        m_vsps.fetch_add(e.vsps, std::memory_order_relaxed);
        m_rests.fetch_add(uint64_t(e.rests), std::memory_order_relaxed);
        if (e.pairs >= pass_cap) m_capped.fetch_add(1, std::memory_order_relaxed);
        return e;
    };
    auto last = [&](const LastPass& plan) {
        cap = last_pass_cap(
            plan, double(m_pair_sum.load()) / double(std::max<uint64_t>(1, m_pixel_passes.load())),
            pass_cap);
    };
    // Adaptive sampling: the later passes' samples by each pixel's share (sample_shares.h), from
    // the first pass's variance of the eye paths' part; a high share as several passes, whose
    // cuts' noise then averages too (bench/RESULTS.md, "Issue 17, session 17").
    float max_share = 1;
    auto begin_pass = [&](int64_t pass) {
        if (pass % set_period == 0 && m_settings.use_set(pass / set_period, m_set)) build_set();
        // What the remainders so far learned (before the first pass: the pilots') guides the
        // pass's.
        if (m_guide && m_guide_paths > 0) {
            const double start = ctx.elapsed();
            m_guide->refine(double(m_guide_paths.exchange(0)));
            guide_seconds += ctx.elapsed() - start;
        }
    };
    const SamplePasses done_passes =
        m_adaptive
            ? render_adaptive_passes(
                  ctx, m_pass_samples, cap_plan.fixed_share,
                  [&](Point2i pixel, int first, int samples) {
                      PassEstimate e = shade(pixel, first, samples);
                      return relative_variance(e.known_variance, e.value.luminance());
                  },
                  last, &max_share, begin_pass)
            : render_sample_passes(
                  ctx, m_pass_samples, cap_plan.fixed_share,
                  [&](Point2i pixel, int first, int samples) { shade(pixel, first, samples); },
                  last, {}, begin_pass);
    const int done = int(done_passes.whole);
    if (checkpoint) checkpoint->set_state({});

    result.spp = int(done_passes.samples);
    result.point_lights = m_set.lights.size();
    result.vpls = m_set.vpls;
    if (std::string w = vpl_budget_warning(m_set); !w.empty()) result.warnings.push_back(w);
    double pixel_passes = double(std::max<uint64_t>(1, m_pixel_passes.load()));
    double pixels = double(ctx.film.width()) * ctx.film.height();
    nlohmann::json figures = {{"samples", m_samples},
                              {"pass_samples", m_pass_samples},
                              {"eye_length", m_eye_length},
                              {"rest", m_rest_path ? "path" : "drop"},
                              {"rest_paths", m_rest_paths},
                              {"guiding", m_guide ? "on" : "off"},
                              {"guide_regions", m_guide ? m_guide->regions() : 0},
                              {"guide_refine_seconds", guide_seconds},
                              {"vsp_tree", m_tree_by_depth ? "depth" : "position"},
                              {"emission", m_emission_mis ? "mis" : "hit"},
                              {"emission_samples", m_emission_samples},
                              {"error", m_error},
                              {"max_cut", m_max_cut},
                              {"refine", m_refine_by_bounds ? "bounds" : "estimates"},
                              {"vpl_region_radius", m_settings.lights.vpl_region.radius},
                              {"set_period", set_period},
                              {"vpl_sets", sets},
                              {"time_cap", cut_cap_json(cap_plan)},
                              {"floor", m_floor},
                              {"adaptive", m_adaptive},
                              {"max_sample_share", max_share},
                              {"floor_luminance", m_floor_luminance},
                              {"weights",
                               {{"energy", m_weights.energy},
                                {"clamp", m_weights.clamp},
                                {"diffuse", m_weights.diffuse},
                                {"variance", m_weights.variance},
                                {"c_clamp", m_weights.c_clamp},
                                {"c_d", m_weights.c_d},
                                {"spread", m_weights.spread}}},
                              {"passes", done},
                              {"last_pass_samples", done_passes.last_samples},
                              {"last_pass_cap", cap},
                              {"pass_seconds", done_passes.pass_seconds},
                              {"avg_cut_size", double(m_pair_sum.load()) / pixel_passes},
                              {"capped_fraction", double(m_capped.load()) / pixel_passes},
                              {"vsps_per_pixel_pass", double(m_vsps.load()) / pixel_passes},
                              {"rest_paths_per_pixel_pass", double(m_rests.load()) / pixel_passes},
                              {"shadow_rays_per_pixel", double(stats::total().shadow) / pixels},
                              {"tree_build_seconds", m_tree_seconds}};
    figures.update(many_light_figures(m_set, unused_direct));
    result.stats["bdlightcuts"] = figures;
    double capped = double(m_capped.load()) / pixel_passes;
    std::string warning =
        capped_cut_warning(name(), "pixel passes", capped, m_max_cut, m_set, pass_cap);
    if (!warning.empty()) result.warnings.push_back(warning);
    return result;
}

BdLightcutsIntegrator::PassEstimate BdLightcutsIntegrator::estimate_pass(
    const RenderContext& ctx, ThreadState& ts, Point2i pixel, int first_sample, int max_cut,
    int samples) const {
    const Scene& scene = ctx.scene;
    Sampler& sampler = *ts.sampler;
    ts.points.clear();
    ts.vsps.clear();
    ts.uniforms.clear();
    // 1. The pass's eye paths: their VSPs, and the emission they meet, weighted by filter.
    RGB known;
    // For the variance of the known part: sums of w^2, w^2 l and w^2 l^2 (l: a sample's luminance).
    double weight_sum = 0, w2 = 0, w2l = 0, w2l2 = 0;
    int rests = 0;
    const int n = samples > 0 ? samples : m_pass_samples;
    for (int s = 0; s < n; ++s) {
        sampler.start_pixel_sample(pixel, first_sample + s);
        float weight, camera_weight;
        Ray ray = pixel_sample_ray(ctx, pixel, sampler, &weight, &camera_weight);
        size_t first = ts.points.size();
        bool rested = false;
        // The camera ray's weight scales what the path meets and its VSPs' shares; a
        // vignetted ray (weight 0) is a sample of black.
        RGB L = camera_weight > 0
                    ? trace_eye(scene, ray, sampler, ts, weight * camera_weight, &rested) *
                          camera_weight
                    : RGB();
        rests += rested;
        if (!L.is_finite()) {
            ts.points.resize(first);
            ts.uniforms.resize(first);
            continue;
        }
        known += L * weight;
        weight_sum += weight;
        const double l = L.luminance(), ww = double(weight) * double(weight);
        w2 += ww, w2l += ww * l, w2l2 += ww * l * l;
    }
    PassEstimate out;
    if (weight_sum == 0) {
        ts.scratch.reset();
        return out;
    }
    float inv_weight = float(1.0 / weight_sum);
    known *= inv_weight;
    // sum_s w_s^2 (l_s - m)^2 / W^2, the variance of the weighted mean m.
    const double m = known.luminance(), inv2 = 1.0 / (weight_sum * weight_sum);
    out.known_variance = float(std::max(0.0, (w2l2 - 2 * m * w2l + m * m * w2) * inv2));

    // 2. The VSP tree (the gather tree over the pass's VSPs, weighted by their share of the
    // pixel), and 3. the product cut with every pair weighted by its split weight.
    ts.positions.clear();
    ts.weights.clear();
    ts.groups.clear();
    for (WeightedGatherPoint& p : ts.points) {
        p.a *= inv_weight;
        p.w = p.g.beta * p.a;
        ts.positions.push_back(p.g.si.p);
        ts.weights.push_back(p.w);
        if (m_tree_by_depth)
            ts.groups.push_back(uint8_t(std::min(255, ts.vsps[size_t(p.tag)].depth)));
    }
    int spare = ts.tree.build(ts.positions, ts.weights, ts.uniforms, ts.groups);
    RGB C;
    int pairs = 0;
    if (spare >= 0) {
        ts.weighting.vsps = &ts.vsps;
        ts.cut.set_pair_weight(&ts.weighting);
        // The fixed cones' BSDF bounds cost more than they save here (product_cut.h).
        ts.cut.set_direction_bins(false);
        ts.cut.set_draw_free(m_refine_by_bounds);
        int k = rep_index(ts.uniforms[size_t(spare)], m_tree.reps());
        C = ts.cut.refine(ts.points, ts.tree, k, known, m_error, max_cut, CutCriterion::Max, 1,
                          m_floor_luminance);
        pairs = int(ts.cut.pairs().size());
    }
    ts.scratch.reset();
    out.value = known + C;
    out.weight_sum = weight_sum;
    out.pairs = pairs;
    out.vsps = ts.points.size();
    out.rests = rests;
    return out;
}

}  // namespace ml
