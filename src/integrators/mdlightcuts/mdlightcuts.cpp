#include "integrators/mdlightcuts/mdlightcuts.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>

#include "core/parallel.h"
#include "core/stats.h"
#include "manylight/gather.h"
#include "manylight/gather_tree.h"
#include "manylight/pilot.h"
#include "manylight/product_cut.h"
#include "manylight/vpl_memory.h"
#include "render/render_loop.h"

namespace ml {

struct MdLightcutsIntegrator::ThreadState {
    ThreadState(std::unique_ptr<Sampler> s, ProductCut c)
        : sampler(std::move(s)), cut(std::move(c)) {}
    std::unique_ptr<Sampler> sampler;
    ScratchBuffer scratch;  // the pass's BSDFs: reset after each pixel pass
    ProductCut cut;
    GatherTree tree;
    std::vector<WeightedGatherPoint> points;
    std::vector<Vec3> positions;
    std::vector<RGB> weights;
    std::vector<float> uniforms;
};

MdLightcutsIntegrator::MdLightcutsIntegrator(const Settings& settings)
    : m_settings(ManyLightSettings::read(settings)) {
    read_vpl_sets(settings, &m_settings);
    m_samples = settings.get_int("samples", m_samples,
                                 {">= 1",
                                  "Camera samples of a pixel shaded together by one product cut (a "
                                  "pixel pass); --spp rounds up to whole passes."});
    m_error = settings.get_float(
        "error", m_error,
        {">= 0", "Relative error bound of each gather-light pair against the pixel's estimate."});
    m_max_cut = settings.get_int("max_cut", m_max_cut,
                                 {">= 1",
                                  "Most pairs in one cut; a cut stopped there has no error bound "
                                  "(--stats: capped_fraction)."});
    m_tighten = settings.get_int("tighten", 1,
                                 {">= 0",
                                  "Pairs whose gather node holds at most this many gather points "
                                  "get the tight per-point bound."});
    m_floor = settings.get_float("floor", m_floor, {">= 0", "Error floor, as lightcuts.floor."});
    if (!(m_floor >= 0)) throw UsageError("mdlightcuts.floor must be >= 0");
    std::string criterion = settings.get_string(
        "criterion", "max",
        {"max, sum",
         "When a cut stops: each pair's bound below error (max) or the sum of the bounds (sum)."});
    if (criterion == "max")
        m_criterion = CutCriterion::Max;
    else if (criterion == "sum")
        m_criterion = CutCriterion::Sum;
    else
        throw UsageError("mdlightcuts.criterion must be max or sum, not " + criterion);
    if (m_samples < 1) throw UsageError("mdlightcuts.samples must be at least 1");
    if (!(m_error >= 0) || m_max_cut < 1)
        throw UsageError("mdlightcuts: error must be >= 0 and max_cut >= 1");
}

void MdLightcutsIntegrator::prepare(const Scene& scene) {
    // A pass's new set (vpl.sets=pass) replaces the last: that one goes first, so that two sets
    // and trees are never held at once (manylight/vpl_memory.h).
    m_tree = LightTree();
    m_set = PointLightSet();
    build_many_lights(scene, m_settings, &m_set, &m_direct);
    m_tree = build_light_tree(scene, m_settings, m_set, &m_tree_seconds);
}

RenderResult MdLightcutsIntegrator::render(const RenderContext& ctx) {
    m_settings.use_render_seed(ctx.seed);
    m_settings.use_scene(ctx.scene);
    m_settings.lights.camera = &ctx.camera;
    m_settings.use_time_limit(ctx, true);
    // A resumed render takes the first run's plan (many_lights.h: read_pass_plan) and figures.
    Checkpoint* checkpoint = ctx.checkpoint;
    const ResumedPasses resumed_passes = resume_passes(ctx, m_settings);
    const nlohmann::json* resumed = resumed_passes.state;
    const bool planned = resumed_passes.planned;
    const CutCapPlan& resumed_plan = resumed_passes.plan;
    int first_set_vpls = resumed_passes.first_set_vpls;
    check_vpl_memory(m_settings, true, name());
    prepare(ctx.scene);
    if (!planned && m_settings.lights.vpl_budget.seconds > 0) first_set_vpls = int(m_set.vpls);
    const int w = ctx.film.width(), h = ctx.film.height();
    m_pixel_pairs.assign(size_t(w) * h, 0.f);
    m_pixel_passes_done.assign(m_pixel_pairs.size(), 0);
    m_pair_sum = 0, m_pixel_passes = 0, m_gather_points = 0, m_gather_tree_ns = 0, m_pair_max = 0;
    m_capped = 0;
    if (resumed) restore_figures(*resumed, m_pixel_pairs.size());
    ThreadLocal<ThreadState> states([&] {
        return ThreadState(ctx.sampler.clone(), ProductCut(ctx.scene, m_set, m_tree, m_settings));
    });
    // The error floor, from a pilot of small cuts on pass 0's samples.
    m_floor_luminance = 0;
    if (m_floor > 0)
        m_floor_luminance = float(
            m_floor * pilot_mean_luminance(ctx.film.width(), ctx.film.height(), [&](Point2i pixel) {
                PassEstimate e = estimate_pass(ctx, states.local(), pixel, 0, kPilotMaxCut);
                return e.value;
            }));
    m_pass_samples = m_samples;
    m_cap_plan =
        planned ? resumed_plan
                : plan_pass_cut_cap(
                      ctx, m_max_cut, m_samples, [&](Point2i pixel, int cap, int samples) {
                          return estimate_pass(ctx, states.local(), pixel, 0, cap, samples).pairs;
                      });
    m_pass_cap = m_cap_plan.cap;
    m_pass_samples = pass_samples(m_samples, m_cap_plan);
    if (checkpoint)
        checkpoint->set_state([&] {
            nlohmann::json state = figures_state();
            state["pass_plan"] = pass_plan_json(m_cap_plan, first_set_vpls);
            return state;
        });
    // Passes of m_pass_samples samples per pixel, in the render loop's rounds (as
    // PixelIntegrator takes samples), and under a time limit a last, smaller one that fills it.
    // The cap of the pass being shaded: m_pass_cap, then the last pass's (manylight/pilot.h).
    m_cap = m_pass_cap;
    const SamplePasses done_passes = render_sample_passes(
        ctx, m_pass_samples, m_cap_plan.fixed_share,
        [&](Point2i pixel, int first, int samples) {
            render_pixel_pass(ctx, states.local(), pixel, first, samples);
        },
        [&](const LastPass& last) {
            m_cap = last_pass_cap(
                last,
                double(m_pair_sum.load()) / double(std::max<uint64_t>(1, m_pixel_passes.load())),
                m_pass_cap);
        },
        {},
        [&](int64_t pass) {
            if (m_settings.use_set(pass, m_set)) prepare(ctx.scene);
        });
    const int done = int(done_passes.whole);
    if (checkpoint) checkpoint->set_state({});

    RenderResult result;
    result.spp = int(done_passes.samples);
    result.point_lights = m_set.lights.size();
    result.vpls = m_set.vpls;
    if (std::string w = vpl_budget_warning(m_set); !w.empty()) result.warnings.push_back(w);
    result.stats["mdlightcuts"] = figures_json(ctx, done);
    result.stats["mdlightcuts"]["last_pass_samples"] = done_passes.last_samples;
    result.stats["mdlightcuts"]["last_pass_cap"] = m_cap;
    result.stats["mdlightcuts"]["pass_seconds"] = done_passes.pass_seconds;
    double capped = double(m_capped.load()) / double(std::max<uint64_t>(1, m_pixel_passes.load()));
    std::string warning =
        capped_cut_warning(name(), "pixel passes", capped, m_max_cut, m_set, m_pass_cap);
    if (!warning.empty()) result.warnings.push_back(warning);
    // The cut-size heat map: the mean number of pairs of each pixel's passes.
    Image cut(w, h);
    for (size_t i = 0; i < m_pixel_pairs.size(); ++i)
        cut.pixels[i] =
            RGB(m_pixel_passes_done[i] ? m_pixel_pairs[i] / float(m_pixel_passes_done[i]) : 0.f);
    result.aovs["cutsize"] = std::move(cut);
    return result;
}

void MdLightcutsIntegrator::render_pixel_pass(const RenderContext& ctx, ThreadState& ts,
                                              Point2i pixel, int first, int samples) const {
    PassEstimate e = estimate_pass(ctx, ts, pixel, first, m_cap, samples);
    if (e.weight_sum == 0) return;
    ctx.film.add_sample(pixel, e.value, float(e.weight_sum));

    // Figures.
    int pairs = e.pairs;
    m_pair_sum.fetch_add(uint64_t(pairs), std::memory_order_relaxed);
    m_pixel_passes.fetch_add(1, std::memory_order_relaxed);
    if (pairs >= m_pass_cap) m_capped.fetch_add(1, std::memory_order_relaxed);
    m_gather_points.fetch_add(e.gather_points, std::memory_order_relaxed);
    int prev = m_pair_max.load(std::memory_order_relaxed);
    while (pairs > prev && !m_pair_max.compare_exchange_weak(prev, pairs)) {
    }
    size_t i = size_t(pixel.y) * ctx.film.width() + pixel.x;
    m_pixel_pairs[i] += float(pairs);
    ++m_pixel_passes_done[i];
}

MdLightcutsIntegrator::PassEstimate MdLightcutsIntegrator::estimate_pass(
    const RenderContext& ctx, ThreadState& ts, Point2i pixel, int first_sample, int max_cut,
    int samples) const {
    const Scene& scene = ctx.scene;
    Sampler& sampler = *ts.sampler;
    ts.points.clear();

    // 1. The pass's camera samples, exactly as PixelIntegrator takes them, each followed to its
    // gather points; emission and sampled direct light are summed here, weighted by filter.
    RGB known;
    double weight_sum = 0;
    ts.uniforms.clear();
    const int n = samples > 0 ? samples : m_pass_samples;
    for (int s = 0; s < n; ++s) {
        sampler.start_pixel_sample(pixel, first_sample + s);
        float weight, camera_weight;
        Ray ray = pixel_sample_ray(ctx, pixel, sampler, &weight, &camera_weight);
        if (camera_weight == 0) {  // vignetted: a sample of black
            weight_sum += weight;
            continue;
        }
        size_t first = ts.points.size();
        RGB L = gather_along(scene, ray, sampler, ts.scratch, m_settings.gather(),
                             [&](const GatherPoint& g, float u) {
                                 // `a` holds the raw filter weight (times the camera ray's)
                                 // until normalised below.
                                 ts.points.push_back({g, weight * camera_weight, RGB()});
                                 ts.uniforms.push_back(u);
                                 return m_direct.estimate(scene, g, sampler);
                             });
        if (!L.is_finite()) {
            // What the film does with such a sample: drop it, weight and all.
            ts.points.resize(first);
            ts.uniforms.resize(first);
            continue;
        }
        known += L * (weight * camera_weight);
        weight_sum += weight;
    }
    PassEstimate out;
    if (weight_sum == 0) {
        ts.scratch.reset();
        return out;
    }
    float inv_weight = float(1.0 / weight_sum);
    known *= inv_weight;

    // 2. The gather tree over the pass's gather points, weighted by their share of the pixel.
    auto t0 = std::chrono::steady_clock::now();
    ts.positions.clear();
    ts.weights.clear();
    for (WeightedGatherPoint& p : ts.points) {
        p.a *= inv_weight;
        p.w = p.g.beta * p.a;
        ts.positions.push_back(p.g.si.p);
        ts.weights.push_back(p.w);
    }
    int spare = ts.tree.build(ts.positions, ts.weights, ts.uniforms);
    m_gather_tree_ns.fetch_add(uint64_t(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                            std::chrono::steady_clock::now() - t0)
                                            .count()),
                               std::memory_order_relaxed);

    // 3. The product cut, with the light representative drawn from the uniform the gather
    // tree left.
    RGB C;
    int pairs = 0;
    if (spare >= 0) {
        int k = rep_index(ts.uniforms[size_t(spare)], m_tree.reps());
        C = ts.cut.refine(ts.points, ts.tree, k, known, m_error, max_cut, m_criterion, m_tighten,
                          m_floor_luminance);
        pairs = int(ts.cut.pairs().size());
    }
    ts.scratch.reset();
    out.value = known + C;
    out.weight_sum = weight_sum;
    out.pairs = pairs;
    out.gather_points = ts.points.size();
    return out;
}

nlohmann::json MdLightcutsIntegrator::figures_state() const {
    return {{"pair_sum", m_pair_sum.load()},
            {"pixel_passes", m_pixel_passes.load()},
            {"gather_points", m_gather_points.load()},
            {"gather_tree_ns", m_gather_tree_ns.load()},
            {"capped", m_capped.load()},
            {"pair_max", m_pair_max.load()},
            {"pixel_pairs", to_binary(m_pixel_pairs)},
            {"pixel_passes_done", to_binary(m_pixel_passes_done)}};
}

void MdLightcutsIntegrator::restore_figures(const nlohmann::json& state, size_t pixels) {
    try {
        m_pair_sum = state.at("pair_sum").get<uint64_t>();
        m_pixel_passes = state.at("pixel_passes").get<uint64_t>();
        m_gather_points = state.at("gather_points").get<uint64_t>();
        m_gather_tree_ns = state.at("gather_tree_ns").get<uint64_t>();
        m_capped = state.at("capped").get<uint64_t>();
        m_pair_max = state.at("pair_max").get<int>();
        m_pixel_pairs = from_binary<float>(state.at("pixel_pairs"), pixels);
        m_pixel_passes_done = from_binary<uint32_t>(state.at("pixel_passes_done"), pixels);
    } catch (const std::exception& e) {
        throw UsageError(std::string("--resume: a damaged checkpoint (") + e.what() + ")");
    }
}

nlohmann::json MdLightcutsIntegrator::figures_json(const RenderContext& ctx, int passes) const {
    double pixel_passes = double(std::max<uint64_t>(1, m_pixel_passes.load()));
    double pixels = double(ctx.film.width()) * ctx.film.height();
    double shadow = double(stats::total().shadow);
    nlohmann::json figures = {
        {"samples", m_samples},
        {"pass_samples", m_pass_samples},
        {"error", m_error},
        {"criterion", m_criterion == CutCriterion::Max ? "max" : "sum"},
        {"max_cut", m_max_cut},
        {"time_cap", cut_cap_json(m_cap_plan)},
        {"tighten", m_tighten},
        {"floor", m_floor},
        {"floor_luminance", m_floor_luminance},
        {"passes", passes},
        {"avg_cut_size", double(m_pair_sum.load()) / pixel_passes},
        {"max_cut_size", m_pair_max.load()},
        {"capped_fraction", double(m_capped.load()) / pixel_passes},
        {"gather_points_per_pixel_pass", double(m_gather_points.load()) / pixel_passes},
        {"shadow_rays_per_pixel", shadow / pixels},
        {"shadow_rays_per_pixel_pass", shadow / pixel_passes},
        {"tree_build_seconds", m_tree_seconds},
        {"gather_tree_seconds", double(m_gather_tree_ns.load()) * 1e-9}};
    figures.update(many_light_figures(m_set, m_direct));
    return figures;
}

}  // namespace ml
