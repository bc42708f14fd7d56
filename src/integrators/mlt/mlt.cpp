#include "integrators/mlt/mlt.h"

#include <algorithm>
#include <numeric>

#include "core/parallel.h"
#include "integrators/mlt/bidir_mutation.h"
#include "integrators/mlt/coherent.h"
#include "integrators/mlt/mutations.h"
#include "lights/light_sampler.h"
#include "render/render_loop.h"
#include "render/splats.h"

namespace ml {

MltIntegrator::MltIntegrator(const Settings& settings, bool coherent) : m_coherent(coherent) {
    m_max_depth = settings.get_int(
        "maxdepth", 5, {">= 0", "Longest path, in bounces; each chain keeps one depth."});
    m_bootstrap = settings.get_int(
        "bootstrap", 100000,
        {">= 1",
         "Bootstrap paths per depth that estimate the image's brightness and start the chains."});
    m_chains = settings.get_int("chains", 256,
                                {">= 1", "Markov chains; the mutations are shared among them."});
    m_bidirectional_prob = settings.get_float(
        "bidirectional_prob", 0.3f,
        {"> 0, sum with lens_prob <= 1", "Probability of a bidirectional mutation."});
    m_lens_prob = settings.get_float("lens_prob", 0.4f,
                                     {">= 0",
                                      "Probability of a lens perturbation; what bidirectional_prob "
                                      "and lens_prob leave are caustic perturbations."});
    std::string bidirectional =
        settings.get_string("bidirectional", "partial",
                            {"partial, whole",
                             "The bidirectional mutation deletes and regrows a subpath (partial, "
                             "Veach) or always replaces the whole path (whole)."});
    if (bidirectional != "partial" && bidirectional != "whole")
        throw UsageError(name() + ": bidirectional must be \"partial\" or \"whole\", not \"" +
                         bidirectional + "\"");
    m_partial = bidirectional == "partial";
    m_whole_prob = settings.get_float(
        "whole_prob", 0.5f,
        {"0 to 1",
         "Share of partial bidirectional mutations that replace the whole path by a BDPT path."});
    if (!(m_whole_prob >= 0 && m_whole_prob <= 1))
        throw UsageError(name() + ": whole_prob must be in [0, 1]");
    if (m_max_depth < 0) throw UsageError(name() + ": maxdepth must be >= 0");
    if (m_bootstrap < 1 || m_chains < 1)
        throw UsageError(name() + ": bootstrap and chains must be >= 1");
    if (!(m_bidirectional_prob > 0 && m_lens_prob >= 0 && m_bidirectional_prob + m_lens_prob <= 1))
        throw UsageError(
            name() + ": bidirectional_prob must be > 0, lens_prob >= 0, and their sum at most 1");
}

namespace {

// Streams of the chains' sampler: bootstrap paths and chain mutations never share numbers.
constexpr int kBootstrapRow = 1 << 20;

// Mutations per segment: chains run a segment in parallel, then their splats are summed in
// chain order. Bounds the splat lists (three per mutation at most, 20 bytes each).
constexpr int64_t kMaxSegmentMutations = int64_t(1) << 20;
constexpr int64_t kFirstTimedSegmentMutations = int64_t(1) << 14;

float importance_of(const RGB& c) {
    float y = c.luminance();
    return std::isfinite(y) && y > 0 ? y : 0.f;
}

// One chain: its current path (BSDFs in one of two scratch buffers; proposals are made in the
// other, and the buffers trade places when a proposal is accepted).
struct Chain {
    MltPath x;
    RGB colour;        // f(x) / luminance(f(x))
    RGB W;             // f(x) / q(x), black when not known
    int64_t next = 0;  // index of the next mutation
    int64_t accepted = 0;
    // Per mutation (partial bidirectional, lens, caustic, whole-path bidirectional): times
    // chosen, times accepted.
    int64_t chosen_by[4] = {0, 0, 0, 0}, accepted_by[4] = {0, 0, 0, 0};
    std::unique_ptr<ScratchBuffer> current, spare;
};

}  // namespace

RenderResult MltIntegrator::render(const RenderContext& ctx) {
    for (const auto& l : ctx.scene.lights())
        if (l->type() == LightType::Infinite || l->type() == LightType::DeltaDirection)
            throw UsageError(name() + ": environment and distant lights are not supported");
    const int w = ctx.film.width(), h = ctx.film.height();
    const int64_t pixels = int64_t(w) * h;
    LightSampler light_sampler("power", ctx.scene.lights());
    BdptScene bctx(ctx.scene, ctx.camera, light_sampler);
    const int depths = m_max_depth + 1;
    // Chains draw many numbers per path: an independent sampler seeded from the render's.
    auto prototype = create_sampler("independent", 1, seed_from(ctx.sampler));
    ThreadLocal<std::unique_ptr<Sampler>> samplers([&] { return prototype->clone(); });
    ThreadLocal<ScratchBuffer> scratches;
    RenderResult result;
    result.spp = ctx.spp;

    // 1. Bootstrap: per depth, independent BDPT paths; b is the sum over depths of the mean
    //    luminance of f / q.
    //    Under a time limit, in chunks, keeping the paths done once its share of the time is
    //    spent: any prefix of the paths is as valid a bootstrap.
    int n_bootstrap = m_bootstrap;
    // Grown chunk by chunk: a bootstrap the time limit stops early never allocates (and the
    // kernel never zeroes) the whole array, hundreds of MB for 20M paths.
    std::vector<float> weight;
    const int chunk = ctx.time_limit > 0 ? 4096 : n_bootstrap;
    for (int i0 = 0; i0 < n_bootstrap; i0 += chunk) {
        const int i1 = std::min(n_bootstrap, i0 + chunk);
        weight.resize(size_t(i1) * depths, 0.f);
        parallel_for(i0, i1, [&](int i) {
            Sampler& sampler = *samplers.local();
            ScratchBuffer& scratch = scratches.local();
            for (int d = 0; d < depths; ++d) {
                sampler.start_pixel_sample(Point2i{i, kBootstrapRow + d}, 0);
                int strategy = -1;
                if (auto x = sample_bdpt_path(bctx, sampler, d, scratch, &strategy))
                    weight[size_t(i) * depths + d] =
                        importance_of(proposal_weight(bctx, *x, strategy));
                scratch.reset();
            }
        });
        // Every rank runs the same bootstrap (the same seed): rank 0 says when it stops.
        if (i1 < n_bootstrap && ctx.time_limit > 0 &&
            ctx.world_or_local().root_decides(ctx.elapsed() >
                                              kBootstrapTimeShare * ctx.time_limit)) {
            n_bootstrap = i1;
            weight.resize(size_t(n_bootstrap) * depths);
        }
    }
    std::vector<double> cdf(weight.size());
    double acc = 0;
    for (size_t i = 0; i < weight.size(); ++i) cdf[i] = acc += weight[i];
    const double b = acc / n_bootstrap;
    if (!(b > 0)) return result;

    // 2. Chains start at bootstrap paths picked in proportion to their luminance.
    const int64_t total = int64_t(ctx.spp) * pixels;
    const int n_chains = int(std::min<int64_t>(m_chains, total));
    std::vector<Chain> chains(static_cast<size_t>(n_chains));
    for (int c = 0; c < n_chains; ++c) {
        if (!ctx.owns(c)) continue;  // across ranks, each runs the chains it owns
        Chain& ch = chains[size_t(c)];
        ch.current = std::make_unique<ScratchBuffer>();
        ch.spare = std::make_unique<ScratchBuffer>();
        double u = (c + 0.5) / n_chains * acc;
        size_t k = size_t(std::upper_bound(cdf.begin(), cdf.end(), u) - cdf.begin());
        k = std::min(k, cdf.size() - 1);
        int i = int(k / depths), d = int(k % depths);
        Sampler& sampler = *samplers.local();
        sampler.start_pixel_sample(Point2i{i, kBootstrapRow + d}, 0);
        int strategy = -1;
        auto x = sample_bdpt_path(bctx, sampler, d, *ch.current, &strategy);
        if (!x) throw InternalError(name() + ": a bootstrap path could not be made again");
        ch.x = std::move(*x);
        ch.W = proposal_weight(bctx, ch.x, strategy);
        ch.colour = ch.W / importance_of(ch.W);
    }

    // 3. Mutations, in segments: chains run in parallel, their splats are summed in chain
    //    order afterwards, so the image does not depend on the schedule.
    std::vector<int64_t> budget(static_cast<size_t>(n_chains), total / n_chains);
    for (int c = 0; c < int(total % n_chains); ++c) ++budget[size_t(c)];
    std::vector<std::vector<Splat>> lists(static_cast<size_t>(n_chains));
    const SplatFilter spread(ctx.filter, w, h, ctx.film.splat_clamp());
    SplatSums sums(w, h, spread);
    RoundPlan plan;
    plan.total = total;
    plan.most = std::max<int64_t>(1, kMaxSegmentMutations / n_chains) * n_chains;
    plan.first_timed = std::max<int64_t>(1, kFirstTimedSegmentMutations / n_chains) * n_chains;
    const int64_t done = run_rounds(ctx, plan, [&](int64_t done_before, int64_t units) {
        const int64_t per_chain = units / n_chains;
        if (per_chain < 1) return int64_t(0);
        run_and_merge(0, n_chains, lists, sums, [&](int64_t c, SplatList& splats) {
            if (!ctx.owns(c)) return;
            Chain& ch = chains[size_t(c)];
            Sampler& sampler = *samplers.local();
            int64_t end = std::min(budget[size_t(c)], ch.next + per_chain);
            for (; ch.next < end; ++ch.next) {
                sampler.start_pixel_sample(Point2i{int(c), 0}, int(ch.next % (int64_t(1) << 30)),
                                           0);
                ch.spare->reset();
                float u = sampler.get_1d();
                std::optional<Proposal> p;
                int kind = u < m_bidirectional_prob                 ? 0
                           : u < m_bidirectional_prob + m_lens_prob ? 1
                                                                    : 2;
                // Bidirectional: the whole path replaced with probability whole_prob (or
                // always, bidirectional=whole), else Veach's partial mutation.
                if (kind == 0 && (!m_partial || u < m_bidirectional_prob * m_whole_prob)) kind = 3;
                if (kind == 0)
                    p = mutate_bidirectional_partial(bctx, ch.x, sampler, *ch.spare);
                else if (kind == 3)
                    p = mutate_bidirectional(bctx, ch.x, &ch.W, sampler, *ch.spare);
                else if (kind == 1)
                    p = m_coherent ? mutate_lens_multiple_try(bctx, ch.x, sampler, *ch.spare)
                                   : mutate_lens(bctx, ch.x, sampler, *ch.spare);
                else
                    p = mutate_caustic(bctx, ch.x, sampler, *ch.spare);
                ++ch.chosen_by[kind];
                float a = p ? p->accept : 0.f, share = p && p->n_tries ? p->tries_share : a;
                if (p && p->n_tries)
                    for (int i = 0; i < p->n_tries; ++i)
                        splats.add(p->tries[i].p_raster, p->tries[i].v);
                else if (p)
                    splats.add(p->y.p_raster, p->colour * a);
                splats.add(ch.x.p_raster, ch.colour * (1 - share));
                if (p && sampler.get_1d() < a) {
                    ch.x = std::move(p->y);
                    ch.colour = p->colour;
                    ch.W = p->W;
                    std::swap(ch.current, ch.spare);
                    ++ch.accepted;
                    ++ch.accepted_by[kind];
                }
            }
        });
        int64_t now = 0;
        for (const Chain& ch : chains) now += ch.next;
        if (ctx.ranks() > 1) now = ctx.world->all_sum(now);  // the mutations of every rank
        return now - done_before;
    });

    // 4. Each mutation splatted a total of one: b * pixels / mutations scales to the image.
    sums.add_to_film(ctx.film, b * double(pixels) / double(done));
    int64_t accepted = 0, chosen_by[4] = {0, 0, 0, 0}, accepted_by[4] = {0, 0, 0, 0};
    for (const Chain& c : chains) {
        accepted += c.accepted;
        for (int k = 0; k < 4; ++k)
            chosen_by[k] += c.chosen_by[k], accepted_by[k] += c.accepted_by[k];
    }
    if (ctx.ranks() > 1) {
        accepted = ctx.world->all_sum(accepted);
        for (int k = 0; k < 4; ++k)
            chosen_by[k] = ctx.world->all_sum(chosen_by[k]),
            accepted_by[k] = ctx.world->all_sum(accepted_by[k]);
    }
    auto rate = [](int64_t n, int64_t d) { return double(n) / double(std::max<int64_t>(d, 1)); };
    // Per mutation: how often it was chosen and the share of those accepted ("bidirectional" is
    // the partial one, "whole" the whole-path replacement).
    const char* names[4] = {"bidirectional", "lens", "caustic", "whole"};
    nlohmann::json proposed = nlohmann::json::object(), acceptance = nlohmann::json::object();
    for (int k = 0; k < 4; ++k) {
        proposed[names[k]] = chosen_by[k];
        acceptance[names[k]] = rate(accepted_by[k], chosen_by[k]);
    }
    result.stats[name()] = {{"b", b},
                            {"chains", n_chains},
                            {"mutations", done},
                            {"acceptance", rate(accepted, done)},
                            {"bidirectional", m_partial ? "partial" : "whole"},
                            {"whole_prob", m_partial ? m_whole_prob : 1.f},
                            {"proposed", proposed},
                            {"acceptance_by_mutation", acceptance}};
    result.spp = int(done / pixels);
    return result;
}

}  // namespace ml
