#include "integrators/pssmlt/chain.h"

namespace ml {

namespace {

// The bootstrap path chain `index` of `count` starts from: jittered stratified over the
// bootstrap's distribution (the chains together start exactly in proportion to the importance,
// and each stratum gets its share of chains to within one; a chain alone starts anywhere in its
// slice). The ensemble of starts is distributed as the target, so it stays so under mutation.
uint64_t starting_path(const Bootstrap& bootstrap, uint64_t index, uint64_t count, Rng& rng) {
    double jitter = (double(rng.next_u32()) + double(rng.next_u32()) * 0x1p32) * 0x1p-64;
    return bootstrap.pick(std::min((double(index) + jitter) / double(count), 1 - 0x1p-53));
}

}  // namespace

MarkovChain::MarkovChain(const PrimaryEstimator& estimator, const Bootstrap& bootstrap,
                         const MltParams& params, uint64_t index, uint64_t count)
    : m_estimator(estimator),
      m_rng(hash_ints(params.seed, index, 0x636861696e /* "chain" */), 0),
      m_start(starting_path(bootstrap, index, count, m_rng)),
      m_sampler(bootstrap_sampler(params, estimator, m_start)),
      m_depth(int(m_start % uint64_t(estimator.depth_count()))) {}

void MarkovChain::splat(const PrimaryPathSample& s, float weight, SplatList& out) const {
    if (weight > 0) out.add(s.p_raster, s.L * weight);
}

void MarkovChain::run(int64_t n, SplatList& out, ScratchBuffer& scratch) {
    if (!m_started) {
        // 1. Re-evaluate the starting path: the sampler replays the bootstrap's numbers.
        m_current = m_estimator.sample(m_sampler, m_depth, scratch);
        m_current_importance = mlt_importance(m_current.L);
        scratch.reset();
        m_started = true;
    }
    for (int64_t i = 0; i < n; ++i) {
        // 2. Propose: a small or large step of every coordinate the path reads.
        m_sampler.start_iteration();
        PrimaryPathSample proposed = m_estimator.sample(m_sampler, m_depth, scratch);
        scratch.reset();
        float importance = mlt_importance(proposed.L);

        // 3. Splat both states by their probability of being the next state.
        float accept =
            m_current_importance > 0 ? std::min(1.f, importance / m_current_importance) : 1.f;
        if (importance > 0) splat(proposed, accept / importance, out);
        if (m_current_importance > 0) splat(m_current, (1 - accept) / m_current_importance, out);

        // 4. Move.
        ++m_proposed;
        if (m_rng.next_float() < accept) {
            m_current = proposed;
            m_current_importance = importance;
            m_sampler.accept();
            ++m_accepted;
        } else {
            m_sampler.reject();
        }
    }
}

nlohmann::json MarkovChain::state() const {
    return {{"rng", rng_state(m_rng)},
            {"start", m_start},
            {"depth", m_depth},
            {"sampler", m_sampler.state()},
            {"started", m_started},
            {"L", {m_current.L.r, m_current.L.g, m_current.L.b}},
            {"p", {m_current.p_raster.x, m_current.p_raster.y}},
            {"importance", m_current_importance},
            {"proposed", m_proposed},
            {"accepted", m_accepted}};
}

void MarkovChain::restore(const nlohmann::json& j) {
    set_rng_state(m_rng, j.at("rng").get<std::array<uint64_t, 2>>());
    m_start = j.at("start").get<uint64_t>();
    m_depth = j.at("depth").get<int>();
    m_sampler.restore(j.at("sampler"));
    m_started = j.at("started").get<bool>();
    auto L = j.at("L").get<std::array<float, 3>>();
    auto p = j.at("p").get<std::array<float, 2>>();
    m_current.L = RGB(L[0], L[1], L[2]);
    m_current.p_raster = Vec2(p[0], p[1]);
    m_current_importance = j.at("importance").get<float>();
    m_proposed = j.at("proposed").get<int64_t>();
    m_accepted = j.at("accepted").get<int64_t>();
}

}  // namespace ml
