#include "integrators/pssmlt/pssmlt.h"

#include <fmt/format.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <bit>
#include <chrono>

#include "integrators/pssmlt/chain.h"

namespace ml {

PssmltIntegrator::PssmltIntegrator(const Settings& settings) {
    m_max_depth = settings.get_int("maxdepth", 5);
    m_params.large_step_prob = settings.get_float("large_step_prob", 0.3f);
    m_params.sigma = settings.get_float("sigma", 0.01f);
    m_bootstrap = settings.get_int("bootstrap", 100000);
    m_chains = settings.get_int("chains", 1000);
    m_estimator = settings.get_string("estimator", "bdpt");
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

// The render's seed, read through its sampler (the only source of randomness): the first
// numbers of pixel (0, 0), which every sampler derives from its seed.
uint64_t seed_from(const Sampler& prototype) {
    auto s = prototype.clone();
    s->start_pixel_sample(Point2i{0, 0}, 0, 0);
    uint32_t a = std::bit_cast<uint32_t>(s->get_1d());
    uint32_t b = std::bit_cast<uint32_t>(s->get_1d());
    uint32_t c = std::bit_cast<uint32_t>(s->get_1d());
    return hash_ints(a, b, c);
}

// Mutations per segment: chains run a segment in parallel, then their splats are summed in
// chain order. Bounds the splat lists (two per mutation at most, 16 bytes each).
constexpr int64_t kMaxSegmentMutations = int64_t(1) << 20;
constexpr int64_t kFirstTimedSegmentMutations = int64_t(1) << 14;

}  // namespace

RenderResult PssmltIntegrator::render(const RenderContext& ctx) {
    const int w = ctx.film.width(), h = ctx.film.height();
    const int64_t pixels = int64_t(w) * h;
    const bool timed = ctx.time_limit > 0;
    auto start = std::chrono::steady_clock::now();
    auto elapsed = [&] {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    };
    MltParams params = m_params;
    params.seed = seed_from(ctx.sampler);
    auto estimator = make_primary_estimator(m_estimator, ctx.scene, ctx.camera, m_max_depth);

    // 1. Bootstrap: the image's mean luminance b and the chains' starting paths.
    // Under a time limit the bootstrap takes at most its share of the time.
    std::function<bool()> bootstrap_stop;
    if (timed) bootstrap_stop = [&] { return elapsed() > kBootstrapTimeShare * ctx.time_limit; };
    Bootstrap bootstrap(*estimator, params, m_bootstrap, bootstrap_stop);
    double seconds_bootstrap = elapsed();
    RenderResult result;
    auto stats_json = [&](int64_t mutations, int64_t accepted, int64_t chains) {
        return fmt::format(
            "\"pssmlt\": {{\"estimator\": \"{}\", \"b\": {:.6g}, \"b_stderr\": {:.4g}, "
            "\"bootstrap\": {}, \"chains\": {}, \"mutations\": {}, "
            "\"mutations_per_pixel\": {:.4g}, \"acceptance\": {:.4f}, "
            "\"large_step_prob\": {}, \"sigma\": {}, \"seconds_bootstrap\": {:.3f}}}",
            m_estimator, bootstrap.b(), bootstrap.b_stderr(), bootstrap.paths_per_stratum(), chains,
            mutations, double(mutations) / double(pixels),
            mutations ? double(accepted) / mutations : 0.0, params.large_step_prob, params.sigma,
            seconds_bootstrap);
    };
    if (!(bootstrap.b() > 0)) {
        // No path carries light: the image is black, whatever the budget.
        result.spp = timed ? 0 : ctx.spp;
        result.extra_json = stats_json(0, 0, 0);
        return result;
    }

    // 2. Chains: the mutation budget split as evenly as it goes.
    const int64_t total = int64_t(ctx.spp) * pixels;
    const int64_t n_chains = std::min<int64_t>(m_chains, total);
    std::vector<MarkovChain> chains;
    std::vector<int64_t> remaining(size_t(n_chains), total / n_chains);
    chains.reserve(size_t(n_chains));
    for (int64_t i = 0; i < n_chains; ++i) {
        chains.emplace_back(*estimator, bootstrap, params, uint64_t(i), uint64_t(n_chains), w, h);
        if (i < total % n_chains) ++remaining[size_t(i)];
    }

    // 3. Segments: every chain runs up to `per_chain` mutations in parallel, then the splats
    //    are summed in chain order, so the sum never depends on the schedule. Under a time
    //    limit, segments grow (at most 4x) to fill what is left of the time.
    std::vector<std::vector<ChainSplat>> splats(static_cast<size_t>(n_chains));
    std::vector<double> sum(size_t(pixels) * 3, 0.0);
    tbb::enumerable_thread_specific<ScratchBuffer> scratch;
    int64_t per_chain = std::max<int64_t>(
        1, (timed ? kFirstTimedSegmentMutations : kMaxSegmentMutations) / n_chains);
    int64_t done = 0;
    for (;;) {
        double segment_start = elapsed();
        std::vector<int64_t> ran(size_t(n_chains), 0);
        tbb::parallel_for(tbb::blocked_range<int64_t>(0, n_chains, 1),
                          [&](const tbb::blocked_range<int64_t>& r) {
                              for (int64_t i = r.begin(); i < r.end(); ++i) {
                                  size_t k = size_t(i);
                                  ran[k] = std::min(per_chain, remaining[k]);
                                  chains[k].run(ran[k], splats[k], scratch.local());
                                  remaining[k] -= ran[k];
                              }
                          });
        int64_t segment = 0;
        for (size_t k = 0; k < size_t(n_chains); ++k) {
            for (const ChainSplat& s : splats[k])
                for (int c = 0; c < 3; ++c) sum[3 * size_t(s.pixel) + c] += s.v[c];
            splats[k].clear();
            segment += ran[k];
        }
        done += segment;
        if (done >= total || segment == 0) break;
        if (ctx.progress)
            ctx.progress->set_fraction(timed ? elapsed() / ctx.time_limit
                                             : double(done) / double(total));
        if (timed) {
            double per_mutation = (elapsed() - segment_start) / double(segment);
            double left = ctx.time_limit - elapsed();
            double next = std::min(
                {4.0 * double(segment), 0.95 * left / per_mutation, double(kMaxSegmentMutations)});
            per_chain = int64_t(next / double(n_chains));
            if (per_chain < 1) break;
        }
    }

    // 4. The image: each mutation splatted a total importance of 1, so b * pixels / done
    //    scales the splats to mean luminance b. Added once per pixel, from one thread.
    double scale = bootstrap.b() * double(pixels) / double(done);
    for (int64_t p = 0; p < pixels; ++p) {
        RGB v(float(sum[3 * size_t(p)] * scale), float(sum[3 * size_t(p) + 1] * scale),
              float(sum[3 * size_t(p) + 2] * scale));
        if (!v.is_black()) ctx.film.add_splat(Vec2(float(p % w) + 0.5f, float(p / w) + 0.5f), v);
    }
    int64_t accepted = 0;
    for (const MarkovChain& c : chains) accepted += c.accepted();
    result.spp = int(done / pixels);
    result.extra_json = stats_json(done, accepted, n_chains);
    return result;
}

}  // namespace ml
