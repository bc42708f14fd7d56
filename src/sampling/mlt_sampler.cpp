#include "sampling/mlt_sampler.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <type_traits>

#include "core/error.h"

namespace ml {

double standard_normal_quantile(double u) {
    // Acklam's rational approximations (relative error 1.2e-9) in the centre and both tails,
    // then one Halley step on Phi(x) - u to reach double precision.
    constexpr double a[] = {-3.969683028665376e+01, 2.209460984245205e+02,  -2.759285104469687e+02,
                            1.383577518672690e+02,  -3.066479806614716e+01, 2.506628277459239e+00};
    constexpr double b[] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                            6.680131188771972e+01, -1.328068155288572e+01};
    constexpr double c[] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                            -2.549732539343734e+00, 4.374664141464968e+00,  2.938163982698783e+00};
    constexpr double d[] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
                            3.754408661907416e+00};
    constexpr double kLow = 0.02425;
    u = std::clamp(u, 1e-300, 1.0 - 1e-16);
    auto tail = [&](double q) {
        return (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
               ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1);
    };
    double x;
    if (u < kLow) {
        x = tail(std::sqrt(-2 * std::log(u)));
    } else if (u > 1 - kLow) {
        x = -tail(std::sqrt(-2 * std::log1p(-u)));
    } else {
        double q = u - 0.5, r = q * q;
        x = (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
            (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1);
    }
    double e = 0.5 * std::erfc(-x / std::sqrt(2.0)) - u;
    double step = e * std::sqrt(2 * kPi) * std::exp(0.5 * x * x);
    return x - step / (1 + 0.5 * x * step);
}

MltSampler::MltSampler(uint64_t seed, uint64_t index, float sigma, float large_step_prob,
                       int stream_count, int mutations_per_pixel)
    : m_rng(hash_ints(seed, index, 0x6d6c74 /* "mlt" */), 0),
      m_sigma(sigma),
      m_large_step_prob(large_step_prob),
      m_stream_count(stream_count),
      m_mutations_per_pixel(mutations_per_pixel) {
    if (!(sigma > 0) || !std::isfinite(sigma))
        throw UsageError("MltSampler: sigma must be positive");
    if (!(large_step_prob >= 0 && large_step_prob <= 1))
        throw UsageError("MltSampler: large step probability must be in [0, 1]");
    if (stream_count < 1) throw UsageError("MltSampler: needs at least one stream");
}

void MltSampler::start_iteration() {
    ++m_iteration;
    m_large_step = m_rng.next_float() < m_large_step_prob;
}

void MltSampler::accept() {
    if (m_large_step) m_last_large_step = m_iteration;
}

void MltSampler::reject() {
    for (PrimarySample& x : m_x)
        if (x.last_modified == m_iteration) {
            x.value = x.value_backup;
            x.last_modified = x.modified_backup;
        }
    // The next proposal starts from the same iteration count, so lazily applied small steps
    // count only the accepted history.
    --m_iteration;
}

void MltSampler::start_stream(int index) {
    if (index < 0 || index >= m_stream_count)
        throw InternalError("MltSampler: stream index out of range");
    m_stream = index;
    m_stream_sample = 0;
}

void MltSampler::start_pixel_sample(Point2i, int, int dimension) {
    start_stream(0);
    m_stream_sample = dimension;
}

float MltSampler::get_1d() {
    size_t i = size_t(m_stream + int64_t(m_stream_count) * m_stream_sample++);
    ensure_ready(i);
    return m_x[i].value;
}

Vec2 MltSampler::get_2d() {
    float x = get_1d();
    return {x, get_1d()};
}

std::unique_ptr<Sampler> MltSampler::clone() const { return std::make_unique<MltSampler>(*this); }

void MltSampler::ensure_ready(size_t i) {
    if (i >= m_x.size()) m_x.resize(i + 1);
    PrimarySample& x = m_x[i];

    // 1. A coordinate read for the first time, or one that an accepted large step has replaced
    //    since it was last read, takes a fresh uniform value (drawn now, lazily): the chain's
    //    stationary distribution leaves unread coordinates uniform.
    if (x.last_modified < m_last_large_step) {
        x.value = m_rng.next_float();
        x.last_modified = m_last_large_step;
    }
    // 2. Already brought up to this iteration (read twice, or first drawn just now at the
    //    chain's start): nothing to do.
    if (x.last_modified == m_iteration) return;

    // 3. Mutate, keeping the old value for reject(): afresh for a large step, else one normal
    //    step standing for every small step since the last change, wrapped into [0, 1).
    x.value_backup = x.value;
    x.modified_backup = x.last_modified;
    if (m_large_step) {
        x.value = m_rng.next_float();
    } else {
        int64_t n_small = m_iteration - x.last_modified;
        double sd = double(m_sigma) * std::sqrt(double(n_small));
        double v = x.value + sd * standard_normal_quantile(m_rng.next_float());
        v -= std::floor(v);
        x.value = std::min(float(v), kOneMinusEpsilon);
    }
    x.last_modified = m_iteration;
}

// Rng keeps its two words private; it is trivially copyable, so its bytes are its state.
static_assert(std::is_trivially_copyable_v<Rng> && sizeof(Rng) == 2 * sizeof(uint64_t));

std::array<uint64_t, 2> rng_state(const Rng& rng) {
    std::array<uint64_t, 2> s;
    std::memcpy(s.data(), &rng, sizeof rng);
    return s;
}

void set_rng_state(Rng& rng, const std::array<uint64_t, 2>& state) {
    std::memcpy(static_cast<void*>(&rng), state.data(), sizeof rng);
}

nlohmann::json MltSampler::state() const {
    std::vector<float> value, backup;
    std::vector<int64_t> modified, modified_backup;
    for (const PrimarySample& x : m_x) {
        value.push_back(x.value);
        backup.push_back(x.value_backup);
        modified.push_back(x.last_modified);
        modified_backup.push_back(x.modified_backup);
    }
    return {{"rng", rng_state(m_rng)},
            {"value", value},
            {"value_backup", backup},
            {"modified", modified},
            {"modified_backup", modified_backup},
            {"iteration", m_iteration},
            {"last_large_step", m_last_large_step},
            {"large_step", m_large_step},
            {"stream", m_stream},
            {"stream_sample", m_stream_sample}};
}

void MltSampler::restore(const nlohmann::json& j) {
    set_rng_state(m_rng, j.at("rng").get<std::array<uint64_t, 2>>());
    auto value = j.at("value").get<std::vector<float>>();
    auto backup = j.at("value_backup").get<std::vector<float>>();
    auto modified = j.at("modified").get<std::vector<int64_t>>();
    auto modified_backup = j.at("modified_backup").get<std::vector<int64_t>>();
    if (backup.size() != value.size() || modified.size() != value.size() ||
        modified_backup.size() != value.size())
        throw Error("checkpoint: a Metropolis sampler's arrays differ in size");
    m_x.resize(value.size());
    for (size_t i = 0; i < m_x.size(); ++i)
        m_x[i] = PrimarySample{value[i], backup[i], modified[i], modified_backup[i]};
    m_iteration = j.at("iteration").get<int64_t>();
    m_last_large_step = j.at("last_large_step").get<int64_t>();
    m_large_step = j.at("large_step").get<bool>();
    m_stream = j.at("stream").get<int>();
    m_stream_sample = j.at("stream_sample").get<int64_t>();
}

}  // namespace ml
