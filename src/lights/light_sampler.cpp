#include "lights/light_sampler.h"

#include <algorithm>

#include "core/error.h"
#include "sampling/warps.h"

namespace ml {
namespace {

// Directions per unbounded light for its irradiance table.
constexpr uint32_t kIrradianceSamples = 2048;

// The receiver's normal the importances use: the shading normal (its cosine is the
// integrand's), else the geometric one, else none (zero).
inline Vec3 receiver_normal(const LightSampleContext& ctx) {
    return length_squared(ctx.ns) > 0 ? ctx.ns : ctx.ng;
}

}  // namespace

LightSampler::LightSampler(const std::string& name, std::span<const Light* const> lights)
    : m_name(name), m_lights(lights.begin(), lights.end()) {
    build();
}

LightSampler::LightSampler(const std::string& name,
                           const std::vector<std::unique_ptr<Light>>& lights)
    : m_name(name) {
    m_lights.reserve(lights.size());
    for (const auto& l : lights) m_lights.push_back(l.get());
    build();
}

void LightSampler::build() {
    if (m_name != "uniform" && m_name != "power" && m_name != "tree")
        throw UsageError("unknown light sampler \"" + m_name + "\"");
    if (m_lights.empty()) return;
    std::vector<float> w(m_lights.size(), 1.f);
    if (m_name != "uniform")
        for (size_t i = 0; i < m_lights.size(); ++i) {
            RGB phi = clamp_zero(m_lights[i]->power());
            // Luminance weights are all positive: any positive channel gives a positive weight.
            w[i] = phi.is_finite() ? phi.luminance() : 0.f;
        }
    m_dist = Distribution1D(w);
    if (m_name != "tree") return;

    m_tree = true;
    std::vector<LightBounds> bounds;
    m_tree_item.assign(m_lights.size(), -1);
    m_top_slot.assign(m_lights.size(), -1);
    for (size_t i = 0; i < m_lights.size(); ++i) {
        if (auto b = m_lights[i]->bounds()) {
            // LightBvh leaves out lights that emit nothing: they can never be chosen.
            if (b->phi > 0 && !b->box.empty()) m_tree_item[i] = int(m_bounded.size());
            m_bounded.push_back(int(i));
            bounds.push_back(*b);
        } else if (w[i] > 0) {
            m_top_slot[i] = int(m_unbounded.size());
            m_unbounded.push_back(int(i));
        }
    }
    m_bvh = LightBvh(bounds);

    // The irradiance tables of the unbounded lights: E(n) = integral of L |cos(n, w)| dw, by
    // their own sample_li over a Hammersley set (deterministic, so every run builds the same).
    m_irradiance.resize(m_unbounded.size());
    m_irradiance_mean.resize(m_unbounded.size());
    std::vector<Vec3> dirs;
    std::vector<float> weights;
    for (size_t k = 0; k < m_unbounded.size(); ++k) {
        const Light* light = m_lights[size_t(m_unbounded[k])];
        dirs.clear();
        weights.clear();
        // A delta light has its one direction, weight L (pdf 1); others kIrradianceSamples.
        uint32_t m = is_delta_light(light->type()) ? 1 : kIrradianceSamples;
        for (uint32_t j = 0; j < m; ++j) {
            auto ls =
                light->sample_li(LightSampleContext{}, shifted_hammersley(j, m, Vec2(0.5f, 0.5f)));
            if (!ls || !(ls->pdf_solid_angle > 0)) continue;
            float l = std::max(0.f, ls->L.luminance()) / ls->pdf_solid_angle / float(m);
            if (!std::isfinite(l) || l <= 0) continue;
            dirs.push_back(ls->wi);
            weights.push_back(l);
        }
        double mean = 0;
        for (int y = 0; y < kIrradianceRes; ++y)
            for (int x = 0; x < kIrradianceRes; ++x) {
                Vec3 n = equal_area_square_to_sphere(
                    {(x + 0.5f) / kIrradianceRes, (y + 0.5f) / kIrradianceRes});
                double e = 0;
                for (size_t j = 0; j < dirs.size(); ++j)
                    e += weights[j] * std::abs(dot(n, dirs[j]));
                m_irradiance[k][size_t(y * kIrradianceRes + x)] = float(e);
                mean += e;
            }
        m_irradiance_mean[k] = float(mean / (kIrradianceRes * kIrradianceRes));
        // A cell's centre may see none of the light (a sun at right angles) while other
        // normals in the cell do: no entry is zero, so the light stays a choice everywhere.
        float floor = 1e-3f * m_irradiance_mean[k];
        if (!(floor > 0)) floor = 1e-30f;
        for (float& e : m_irradiance[k]) e = std::max(e, floor);
    }
}

std::optional<SampledLight> LightSampler::sample(float u) const {
    if (m_lights.empty()) return std::nullopt;
    float pmf;
    size_t i = m_dist.sample_discrete(u, &pmf);
    if (pmf == 0) return std::nullopt;
    return SampledLight{m_lights[i], int(i), pmf};
}

int LightSampler::top_level(const LightSampleContext& ctx, float* p) const {
    int n_unbounded = int(m_unbounded.size());
    int count = n_unbounded + (m_bvh.empty() ? 0 : 1);
    if (count == 0) return 0;
    if (count > kMaxTopLevel) return count;  // the caller chooses uniformly
    if (count == 1) {  // nothing to weigh (the tree alone: its descent finds out the rest)
        p[0] = 1;
        return 1;
    }
    Vec3 n = receiver_normal(ctx);
    bool has_n = length_squared(n) > 0;
    int cell = 0;
    if (has_n) {
        Vec2 uv = equal_area_sphere_to_square(normalize(n));
        int x = std::clamp(int(uv.x * kIrradianceRes), 0, kIrradianceRes - 1);
        int y = std::clamp(int(uv.y * kIrradianceRes), 0, kIrradianceRes - 1);
        cell = y * kIrradianceRes + x;
    }
    float sum = 0;
    for (int k = 0; k < n_unbounded; ++k) {
        p[k] = has_n ? m_irradiance[size_t(k)][size_t(cell)] : m_irradiance_mean[size_t(k)];
        sum += p[k];
    }
    if (!m_bvh.empty()) {
        p[n_unbounded] = m_bvh.node(0).bounds.importance(ctx.p, n);
        sum += p[n_unbounded];
    }
    if (!(sum > 0) || !std::isfinite(sum)) {
        for (int k = 0; k < count; ++k) p[k] = 1.f / float(count);
        return count;
    }
    // The uniform share goes to the choices with some importance: one with none cannot light
    // the point (the tree's root and the tables are conservative).
    int positive = 0;
    for (int k = 0; k < count; ++k) positive += p[k] > 0 ? 1 : 0;
    float uniform = kTopLevelUniform / float(positive);
    for (int k = 0; k < count; ++k)
        p[k] = p[k] > 0 ? (1 - kTopLevelUniform) * (p[k] / sum) + uniform : 0.f;
    return count;
}

std::optional<SampledLight> LightSampler::sample(const LightSampleContext& ctx, float u) const {
    if (!m_tree) return sample(u);
    float p[kMaxTopLevel];
    int count = top_level(ctx, p);
    if (count == 0) return std::nullopt;
    // The top-level slot: the first whose cumulative probability exceeds u (the last takes the
    // rest, so rounding in the sum cannot lose a sample).
    int slot = count - 1;
    float p_slot;
    if (count > kMaxTopLevel) {
        slot = std::min(int(u * float(count)), count - 1);
        p_slot = 1.f / float(count);
        u = std::min(u * float(count) - float(slot), kOneMinusEpsilon);
    } else {
        float cdf = 0;
        for (int k = 0; k < count; ++k)
            if (u < cdf + p[k] || k == count - 1) {
                slot = k;
                break;
            } else {
                cdf += p[k];
            }
        p_slot = p[slot];
        if (!(p_slot > 0)) return std::nullopt;
        u = std::clamp((u - cdf) / p_slot, 0.f, kOneMinusEpsilon);
    }
    if (slot < int(m_unbounded.size())) {
        int i = m_unbounded[size_t(slot)];
        return SampledLight{m_lights[size_t(i)], i, p_slot};
    }
    auto s = m_bvh.sample(ctx.p, receiver_normal(ctx), u);
    if (!s) return std::nullopt;
    int i = m_bounded[size_t(s->item)];
    return SampledLight{m_lights[size_t(i)], i, p_slot * s->pmf};
}

float LightSampler::pmf(const LightSampleContext& ctx, const Light* light) const {
    if (!light) return 0;
    if (!m_tree) return pmf(light->index);
    int i = light->index;
    if (i < 0 || size_t(i) >= m_lights.size()) return 0;
    float p[kMaxTopLevel];
    int count = top_level(ctx, p);
    if (count == 0) return 0;
    int slot = m_top_slot[size_t(i)];
    bool in_tree = m_tree_item[size_t(i)] >= 0;
    if (slot < 0 && !in_tree) return 0;
    if (in_tree) slot = int(m_unbounded.size());
    float p_slot = count > kMaxTopLevel ? 1.f / float(count) : p[slot];
    if (!in_tree) return p_slot;
    return p_slot * m_bvh.pmf(ctx.p, receiver_normal(ctx), m_tree_item[size_t(i)]);
}

}  // namespace ml
