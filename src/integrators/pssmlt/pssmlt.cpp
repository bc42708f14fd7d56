#include "integrators/pssmlt/pssmlt.h"

#include "core/parallel.h"
#include "integrators/pssmlt/chain.h"
#include "render/render_loop.h"
#include "render/splats.h"

namespace ml {

PssmltIntegrator::PssmltIntegrator(const Settings& settings) {
    m_max_depth = settings.get_int(
        "maxdepth", 5, {">= 0", "Longest path, in bounces; each chain keeps one depth."});
    // pbrt-v4's "mlt" is this integrator (Kelemen's MLT over BDPT's paths): its names set the
    // defaults of ours (its "mutationsperpixel" is the samples per pixel: render_job.cpp).
    m_params.large_step_prob = settings.get_float(
        "large_step_prob",
        settings.get_float("largestepprobability", 0.3f,
                           {"0 to 1", "pbrt-v4's name for large_step_prob (its \"mlt\")."}),
        {"0 to 1", "Probability of a large step (fresh primary samples)."});
    settings.get_bool("regularize", false, {"", "Accepted for pbrt-v4 scenes; no effect."});
    m_params.sigma = settings.get_float(
        "sigma", 0.01f,
        {"> 0", "Standard deviation of a small step's perturbation in primary sample space."});
    m_bootstrap = settings.get_int(
        "bootstrap",
        settings.get_int("bootstrapsamples", 100000, {">= 1", "pbrt-v4's name for bootstrap."}),
        {">= 1",
         "Primary samples per depth whose BDPT paths estimate the "
         "image's brightness; the chains start from them, resampled."});
    m_chains = settings.get_int("chains", 1000,
                                {">= 1", "Chains in primary sample space, sharing the mutations."});
    m_estimator = settings.get_string("estimator", "bdpt",
                                      {"bdpt, path",
                                       "What turns a primary sample into a contribution: BDPT "
                                       "(bdpt) or the path tracer (path, a cross-check)."});
    if (m_max_depth < 0) throw UsageError("pssmlt: maxdepth must be >= 0");
    if (!(m_params.large_step_prob >= 0 && m_params.large_step_prob <= 1))
        throw UsageError("pssmlt: large_step_prob must be in [0, 1]");
    if (!(m_params.sigma > 0)) throw UsageError("pssmlt: sigma must be positive");
    if (m_bootstrap < 1) throw UsageError("pssmlt: bootstrap must be >= 1");
    if (m_chains < 1) throw UsageError("pssmlt: chains must be >= 1");
    if (m_estimator != "bdpt" && m_estimator != "path")
        throw UsageError("pssmlt: estimator must be bdpt or path");
}

namespace {

// Mutations per segment: chains run a segment in parallel, then their splats are summed in
// chain order. Bounds the splat lists (two per mutation at most, 20 bytes each).
constexpr int64_t kMaxSegmentMutations = int64_t(1) << 20;
constexpr int64_t kFirstTimedSegmentMutations = int64_t(1) << 14;

}  // namespace

RenderResult PssmltIntegrator::render(const RenderContext& ctx) {
    const int w = ctx.film.width(), h = ctx.film.height();
    const int64_t pixels = int64_t(w) * h;
    const bool timed = ctx.time_limit > 0;
    MltParams params = m_params;
    params.seed = seed_from(ctx.sampler);
    auto estimator = make_primary_estimator(m_estimator, ctx.scene, ctx.camera, m_max_depth);

    // 1. Bootstrap: the image's mean luminance b and the chains' starting paths.
    // Under a time limit the bootstrap takes at most its share of the time.
    std::function<bool()> bootstrap_stop;
    if (timed)
        // Every rank runs the same bootstrap (the same seed): rank 0 says when it stops.
        bootstrap_stop = [&] {
            return ctx.world_or_local().root_decides(ctx.elapsed() >
                                                     kBootstrapTimeShare * ctx.time_limit);
        };
    // A resumed render restores its chains and b from the checkpoint: its bootstrap is only
    // what the chains are made from before that, so it is the least one (a first chunk).
    Checkpoint* checkpoint = ctx.checkpoint;
    const nlohmann::json* saved =
        checkpoint && checkpoint->resuming() ? &checkpoint->integrator_state() : nullptr;
    if (saved) bootstrap_stop = [] { return true; };
    Bootstrap bootstrap(*estimator, params, m_bootstrap, bootstrap_stop);
    double seconds_bootstrap = ctx.elapsed();
    const double b = saved ? saved->at("b").get<double>() : bootstrap.b();
    const double b_stderr = saved ? saved->at("b_stderr").get<double>() : bootstrap.b_stderr();
    const int bootstrap_paths =
        saved ? saved->at("bootstrap").get<int>() : bootstrap.paths_per_stratum();
    RenderResult result;
    auto stats_json = [&](int64_t mutations, int64_t accepted, int64_t chains) {
        return nlohmann::json{
            {"estimator", m_estimator},
            {"b", b},
            {"b_stderr", b_stderr},
            {"bootstrap", bootstrap_paths},
            {"chains", chains},
            {"mutations", mutations},
            {"mutations_per_pixel", double(mutations) / double(pixels)},
            {"acceptance", mutations ? double(accepted) / double(mutations) : 0.0},
            {"large_step_prob", params.large_step_prob},
            {"sigma", params.sigma},
            {"seconds_bootstrap", seconds_bootstrap}};
    };
    if (!(b > 0)) {
        // No path carries light: the image is black, whatever the budget.
        result.spp = timed ? 0 : ctx.spp;
        result.stats["pssmlt"] = stats_json(0, 0, 0);
        return result;
    }

    // 2. Chains: the mutation budget split as evenly as it goes.
    const int64_t total = int64_t(ctx.spp) * pixels;
    const int64_t n_chains = std::min<int64_t>(m_chains, total);
    std::vector<MarkovChain> chains;
    std::vector<int64_t> remaining(size_t(n_chains), total / n_chains);
    chains.reserve(size_t(n_chains));
    for (int64_t i = 0; i < n_chains; ++i) {
        // Every chain is made (its starting path is cheap); across ranks each runs its own.
        chains.emplace_back(*estimator, bootstrap, params, uint64_t(i), uint64_t(n_chains));
        if (i < total % n_chains) ++remaining[size_t(i)];
    }

    // 3. Segments: every chain runs up to `units / n_chains` mutations in parallel, then the
    //    splats are summed in chain order (run_and_merge), so the sum never depends on the
    //    schedule; under a time limit the render loop sizes the segments to end in time.
    std::vector<std::vector<Splat>> lists(static_cast<size_t>(n_chains));
    const SplatFilter spread(ctx.filter, w, h, ctx.film.splat_clamp());
    SplatSums sums(w, h, spread);
    ThreadLocal<ScratchBuffer> scratch;
    RoundPlan plan;
    plan.total = total;
    plan.most = std::max<int64_t>(1, kMaxSegmentMutations / n_chains) * n_chains;
    plan.first_timed = std::max<int64_t>(1, kFirstTimedSegmentMutations / n_chains) * n_chains;
    std::vector<int64_t> ran(size_t(n_chains), 0);
    if (checkpoint) {
        // The chains' states, their budgets left and the splat sums: a resumed render goes on
        // exactly as the first would have. Segments of at most 1/16 of the budget, so that a
        // save or a stop comes between them.
        if (saved) {
            const nlohmann::json& states = saved->at("chains");
            if (states.size() != chains.size())
                throw UsageError("--resume: the checkpoint holds another number of chains");
            for (size_t k = 0; k < chains.size(); ++k)
                if (!states[k].is_null()) chains[k].restore(states[k]);
            remaining = from_binary<int64_t>(saved->at("remaining"), size_t(n_chains));
            sums.set_sums(-1, from_binary<double>(saved->at("sums"), size_t(pixels) * 3));
            plan.done = std::min(checkpoint->units(), total);
        }
        checkpoint->set_state([&] {
            nlohmann::json states = nlohmann::json::array();
            for (int64_t i = 0; i < n_chains; ++i)
                states.push_back(ctx.owns(i) ? chains[size_t(i)].state() : nlohmann::json());
            return nlohmann::json{{"b", b},
                                  {"b_stderr", b_stderr},
                                  {"bootstrap", bootstrap_paths},
                                  {"chains", states},
                                  {"remaining", to_binary(remaining)},
                                  {"sums", to_binary(sums.sums(-1))}};
        });
        plan.most = std::min(plan.most, std::max<int64_t>(1, total / 16 / n_chains) * n_chains);
        plan.after_round = [&](int64_t done) { checkpoint->round_done(done, ctx.elapsed()); };
    }
    const int64_t done = run_rounds(ctx, plan, [&](int64_t, int64_t units) {
        const int64_t per_chain = units / n_chains;
        if (per_chain < 1) return int64_t(0);
        run_and_merge(0, n_chains, lists, sums, [&](int64_t i, SplatList& splats) {
            size_t k = size_t(i);
            if (!ctx.owns(i)) return;  // across ranks, each runs the chains it owns
            ran[k] = std::min(per_chain, remaining[k]);
            chains[k].run(ran[k], splats, scratch.local());
            remaining[k] -= ran[k];
        });
        int64_t segment = 0;
        for (int64_t r : ran) segment += r;
        if (ctx.ranks() > 1) segment = ctx.world->all_sum(segment);  // every rank's mutations
        return segment;
    });

    if (checkpoint) checkpoint->save(done, ctx.elapsed());

    // 4. The image: each mutation splatted a total importance of 1, so b * pixels / done
    //    scales the splats to mean luminance b. Added once per pixel, from one thread.
    if (done > 0) sums.add_to_film(ctx.film, b * double(pixels) / double(done));
    int64_t accepted = 0;
    for (const MarkovChain& c : chains) accepted += c.accepted();
    if (ctx.ranks() > 1) accepted = ctx.world->all_sum(accepted);
    result.spp = int(done / pixels);
    result.stats["pssmlt"] = stats_json(done, accepted, n_chains);
    return result;
}

}  // namespace ml
