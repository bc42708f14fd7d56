#include "lights/light_bvh.h"

#include <algorithm>
#include <cmath>

#include "core/assert.h"

namespace ml {
namespace {

// pbrt-v4's orientation measure M_omega of bounds: the solid angle their emission covers,
// weighted by the cosine falloff.
float orientation_measure(const LightBounds& b) {
    float theta_o = safe_acos(b.cos_theta_o), theta_e = safe_acos(b.cos_theta_e);
    float theta_w = std::min(theta_o + theta_e, kPi);
    float sin_o = safe_sqrt(1 - sqr(b.cos_theta_o));
    return 2 * kPi * (1 - b.cos_theta_o) +
           kPi / 2 *
               (2 * theta_w * sin_o - std::cos(theta_o - 2 * theta_w) - 2 * theta_o * sin_o +
                b.cos_theta_o);
}

float surface_area(const Bounds3& b) {
    if (b.empty()) return 0;
    Vec3 d = b.diagonal();
    return 2 * (d.x * d.y + d.y * d.z + d.z * d.x);
}

// The cost of a cluster in the surface-area-orientation heuristic (pbrt-v4's
// EvaluateCost): power times orientation measure times surface area, the area stretched by how
// thin the parent is along the split axis (kr) so that long clusters are cut across.
float cluster_cost(const LightBounds& b, float kr) {
    return b.phi * orientation_measure(b) * surface_area(b.box) * kr;
}

constexpr int kBuckets = 12;
// Below this depth splits follow the heuristic; from it on, medians, so that no path from the
// root is longer than 64 steps (the trail's bits) for any number of items below 2^31.
constexpr int kMedianDepth = 32;

}  // namespace

LightBvh::LightBvh(std::span<const LightBounds> items) {
    std::vector<std::pair<int32_t, LightBounds>> v;
    for (size_t i = 0; i < items.size(); ++i)
        if (items[i].phi > 0 && !items[i].box.empty()) v.push_back({int32_t(i), items[i]});
    m_trail.assign(items.size(), 0);
    m_depth.assign(items.size(), -1);
    if (v.empty()) return;
    m_nodes.reserve(2 * v.size());
    build(v, 0, v.size(), 0, 0);
}

int32_t LightBvh::build(std::vector<std::pair<int32_t, LightBounds>>& items, size_t begin,
                        size_t end, uint64_t trail, int depth) {
    ML_ASSERT(depth < 64, "light BVH deeper than its trail bits");
    int32_t index = int32_t(m_nodes.size());
    m_nodes.emplace_back();
    if (end - begin == 1) {
        auto& [item, bounds] = items[begin];
        m_nodes[size_t(index)].bounds = ImportanceBounds(bounds);
        m_nodes[size_t(index)].item = item;
        m_trail[size_t(item)] = trail;
        m_depth[size_t(item)] = int8_t(depth);
        return index;
    }

    LightBounds all;
    Bounds3 centroids;
    for (size_t i = begin; i < end; ++i) {
        all = union_bounds(all, items[i].second);
        centroids.expand(items[i].second.box.center());
    }
    Vec3 extent = centroids.diagonal();
    size_t mid = begin + (end - begin) / 2;
    int best_dim =
        extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    if (depth < kMedianDepth) {
        // The bucket split of least cost over the three axes.
        float best_cost = kInfinity;
        int best_bucket = -1, best_bucket_dim = -1;
        Vec3 d = all.box.diagonal();
        float dmax = std::max({d.x, d.y, d.z});
        for (int dim = 0; dim < 3; ++dim) {
            if (!(extent[dim] > 0)) continue;
            LightBounds buckets[kBuckets];
            for (size_t i = begin; i < end; ++i) {
                float c = items[i].second.box.center()[dim];
                int b =
                    std::min(kBuckets - 1, int(kBuckets * (c - centroids.lo[dim]) / extent[dim]));
                buckets[std::max(0, b)] = union_bounds(buckets[std::max(0, b)], items[i].second);
            }
            float kr = d[dim] > 0 ? dmax / d[dim] : 1.f;
            for (int split = 0; split < kBuckets - 1; ++split) {
                LightBounds lo, hi;
                for (int b = 0; b <= split; ++b) lo = union_bounds(lo, buckets[b]);
                for (int b = split + 1; b < kBuckets; ++b) hi = union_bounds(hi, buckets[b]);
                if (lo.phi <= 0 || hi.phi <= 0) continue;
                float cost = cluster_cost(lo, kr) + cluster_cost(hi, kr);
                if (cost < best_cost) best_cost = cost, best_bucket = split, best_bucket_dim = dim;
            }
        }
        if (best_bucket >= 0) {
            int dim = best_bucket_dim;
            auto it = std::partition(
                items.begin() + ptrdiff_t(begin), items.begin() + ptrdiff_t(end), [&](auto& x) {
                    float c = x.second.box.center()[dim];
                    int b = std::min(kBuckets - 1,
                                     int(kBuckets * (c - centroids.lo[dim]) / extent[dim]));
                    return std::max(0, b) <= best_bucket;
                });
            size_t m = size_t(it - items.begin());
            if (m > begin && m < end) mid = m, best_dim = -1;
        }
    }
    if (best_dim >= 0)  // no split found (or below kMedianDepth): the median of the long axis
        std::nth_element(items.begin() + ptrdiff_t(begin), items.begin() + ptrdiff_t(mid),
                         items.begin() + ptrdiff_t(end), [&](auto& a, auto& b) {
                             return a.second.box.center()[best_dim] <
                                    b.second.box.center()[best_dim];
                         });
    build(items, begin, mid, trail, depth + 1);
    int32_t second = build(items, mid, end, trail | uint64_t(1) << depth, depth + 1);
    m_nodes[size_t(index)].bounds = ImportanceBounds(all);
    m_nodes[size_t(index)].second = second;
    return index;
}

std::optional<LightBvhSample> LightBvh::sample(const Vec3& p, const Vec3& n, float u,
                                               int32_t from) const {
    if (m_nodes.empty()) return std::nullopt;
    int32_t i = from;
    float pmf = 1;
    while (!m_nodes[size_t(i)].is_leaf()) {
        int32_t c0 = i + 1, c1 = m_nodes[size_t(i)].second;
        float p0 = first_child_probability(m_nodes[size_t(c0)].bounds.importance(p, n),
                                           m_nodes[size_t(c1)].bounds.importance(p, n));
        if (p0 < 0) return std::nullopt;
        if (u < p0) {
            i = c0;
            pmf *= p0;
            u = std::min(u / p0, kOneMinusEpsilon);
        } else {
            i = c1;
            pmf *= 1 - p0;
            u = std::min((u - p0) / (1 - p0), kOneMinusEpsilon);
        }
    }
    return LightBvhSample{m_nodes[size_t(i)].item, pmf};
}

float LightBvh::pmf(const Vec3& p, const Vec3& n, int32_t item) const {
    if (item < 0 || size_t(item) >= m_depth.size() || m_depth[size_t(item)] < 0) return 0;
    uint64_t trail = m_trail[size_t(item)];
    int32_t i = 0;
    float pmf = 1;
    for (int depth = 0; !m_nodes[size_t(i)].is_leaf(); ++depth) {
        int32_t c0 = i + 1, c1 = m_nodes[size_t(i)].second;
        float p0 = first_child_probability(m_nodes[size_t(c0)].bounds.importance(p, n),
                                           m_nodes[size_t(c1)].bounds.importance(p, n));
        if (p0 < 0) return 0;
        bool second = (trail >> depth) & 1;
        pmf *= second ? 1 - p0 : p0;
        i = second ? c1 : c0;
    }
    return pmf;
}

}  // namespace ml
