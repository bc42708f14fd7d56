#include "manylight/product_cut.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "core/cone.h"
#include "manylight/bounds.h"
#include "manylight/pilot.h"
#include "manylight/representative.h"

namespace ml {

namespace {

// Luminance of a bound; NaN (an infinite bound times zero) counts as infinite.
float bound_luminance(const RGB& b) {
    float l = b.luminance();
    return std::isnan(l) ? kInfinity : l;
}

// A pair's error bound from a bound of its exact value: both the estimate and the exact value lie
// in [0, max(estimate, bound)] channel by channel, so that bounds their difference. The bound
// alone would not: a gather representative that sees much more of L than the other members
// (the one nearest a light, or the only one not in shadow) is scaled to the whole strength
// of G, and its estimate may exceed the sum's bound many times.
float error_bound(const RGB& value_bound, const RGB& estimate) {
    RGB b;
    for (int c = 0; c < 3; ++c) b[c] = std::max(value_bound[c], estimate[c]);
    return bound_luminance(b);
}

// The sum of the clustered pairs' bounds, infinite ones counted apart (an infinite bound added
// and taken out again would leave NaN).
struct BoundSums {
    double sum = 0;
    int infinite = 0;
    void add(float b, double sign) {
        if (std::isinf(b))
            infinite += int(sign);
        else
            sum += sign * b;
    }
    bool within(float tolerance) const { return infinite == 0 && sum <= tolerance; }
};

// The light node's box grown by the gather box's extent about its centre c: seen from c it holds
// every vector from a member x to a light p (p - x = (p + c - x) - c), which is all the bounds
// of bounds.h look at, so they bound every member at once.
LightTreeNode grown_node(const LightTreeNode& L, const Bounds3& g) {
    LightTreeNode grown = L;
    if (L.kind == PointLightKind::Directional) return grown;
    Vec3 c = g.center();
    grown.bounds.lo = L.bounds.lo - (g.hi - c);
    grown.bounds.hi = L.bounds.hi + (c - g.lo);
    return grown;
}

// The fixed cones of directions: 26 axes (the cube's faces, edges and corners), every direction
// within 27.6 degrees of one, each with a half-angle of kDirectionBinAngle.
const std::array<Vec3, kDirectionBins>& direction_bins() {
    static const std::array<Vec3, kDirectionBins> bins = [] {
        std::array<Vec3, kDirectionBins> b;
        int n = 0;
        for (int i = -1; i <= 1; ++i)
            for (int j = -1; j <= 1; ++j)
                for (int k = -1; k <= 1; ++k)
                    if (i || j || k) b[size_t(n++)] = normalize(Vec3(float(i), float(j), float(k)));
        return b;
    }();
    return bins;
}

int nearest_direction_bin(const Vec3& w) {
    int best = 0;
    float best_dot = -2;
    for (int j = 0; j < kDirectionBins; ++j) {
        float d = dot(w, direction_bins()[size_t(j)]);
        if (d > best_dot) best_dot = d, best = j;
    }
    return best;
}

// cos(kDirectionBinAngle - 2e-4 rad): a bin holds a cone only with this margin, which covers the
// rounding of the cosines and sines below.
constexpr float kDirectionBinCosPadded = 0.7072482f;

// The fixed cone that holds every direction from x towards the grown light node (the cone
// node_direction_cone gives), or -1 when none does. With the cone's half-angle c and the angle a
// between its axis and the nearest bin's, the bin holds it when a + c is within the bin's
// half-angle: cos(a + c) = cos a cos c - sin a sin c, with no inverse trigonometry.
int enclosing_direction_bin(const LightTreeNode& grown, const Vec3& x) {
    Vec3 axis;
    float cos_c, sin_c;
    if (grown.kind == PointLightKind::Directional) {
        if (grown.cone.is_empty() || !(grown.cone.cos_theta > 0)) return -1;
        axis = -grown.cone.axis;
        cos_c = grown.cone.cos_theta;
        sin_c = std::sqrt(std::max(0.f, 1 - cos_c * cos_c));
    } else {
        if (grown.bounds.empty()) return -1;
        Vec3 c;
        float r;
        grown.bounds.bounding_sphere(&c, &r);
        r = r * (1 + 1e-6f) + 1e-30f;
        float d2 = distance_squared(x, c);
        // Within sqrt(2) r of the centre the half-angle is at least a bin's.
        if (!(d2 > 2 * r * r)) return -1;
        float d = std::sqrt(d2);
        axis = (c - x) / d;
        sin_c = r / d;
        cos_c = std::sqrt(std::max(0.f, 1 - sin_c * sin_c));
    }
    int bin = nearest_direction_bin(axis);
    const Vec3& b = direction_bins()[size_t(bin)];
    float cos_a = dot(axis, b), sin_a = length(cross(axis, b));
    // Both angles are below a right angle here (a <= 27.6 deg, c < 45 deg).
    return cos_a * cos_c - sin_a * sin_c >= kDirectionBinCosPadded ? bin : -1;
}

}  // namespace

RGB ProductCut::value(const WeightedGatherPoint& p, int32_t light) const {
    const PointLight& pl = m_set.lights[size_t(light)];
    if (!m_pair_weight) return visible_point_light(m_scene, m_set, m_settings, pl, p.g);
    // The weight from the contribution's own terms (one BSDF evaluation), the shadow ray last.
    return visible_point_light(
        m_scene, m_set, m_settings, pl, p.g, nullptr,
        [&](const PointLightTerms& t) { return m_pair_weight->weight(p, pl, t); });
}

RGB ProductCut::tight_bound(const std::vector<WeightedGatherPoint>& points, const GatherTree& gtree,
                            int32_t gather, int32_t light) const {
    const GatherTreeNode& G = gtree.node(gather);
    LightNodeRef L = m_tree.ref(light);
    RGB b;
    for (int32_t m = G.begin; m < G.end; ++m) {
        const WeightedGatherPoint& p = points[size_t(gtree.members()[size_t(m)])];
        RGB nb = node_error_bound(L, p.g.si.p, p.g.bsdf, p.g.si.wo);
        for (int c = 0; c < 3; ++c)
            if (p.w[c] != 0 && nb[c] != 0) b[c] += p.w[c] * nb[c];
    }
    return b;
}

const RGB& ProductCut::bin_strength(const std::vector<WeightedGatherPoint>& points,
                                    const GatherTree& gtree, int32_t gather, int bin) const {
    size_t i = size_t(gather) * kDirectionBins + size_t(bin);
    if (m_bin_done[i]) return m_bin_strength[i];
    const GatherTreeNode& G = gtree.node(gather);
    RGB m;
    if (G.is_leaf()) {
        const WeightedGatherPoint& p = points[size_t(G.point)];
        RGB b = p.g.bsdf.max_value_bound(p.g.si.wo,
                                         DirectionCone(direction_bins()[bin], kDirectionBinCos));
        for (int c = 0; c < 3; ++c) m[c] = (p.w[c] == 0 || b[c] == 0) ? 0.f : p.w[c] * b[c];
    } else {
        m = bin_strength(points, gtree, G.children[0], bin) +
            bin_strength(points, gtree, G.children[1], bin);
    }
    m_bin_done[i] = 1;
    m_bin_strength[i] = m;
    return m_bin_strength[i];
}

RGB ProductCut::loose_bound(const std::vector<WeightedGatherPoint>& points, const GatherTree& gtree,
                            int32_t gather, int32_t light) const {
    // sum_i w_i f_i(wo_i, wi) |cos| I / d^2 <= (sum_i w_i M_i) G_ub I_L, with G_ub over the
    // grown box and M_i the BSDF's bound over a fixed cone of directions holding every
    // direction from the members to the lights (the cone towards the grown box), else over
    // every direction. The fixed cones' bounds are summed per gather node once per pass, so this
    // is O(1) per pair, where the tight bound costs a material bound per member.
    const GatherTreeNode& G = gtree.node(gather);
    const LightTreeNode& L = m_tree.node(light);
    RGB b;
    LightTreeNode grown = grown_node(L, G.bounds);
    Vec3 x = G.bounds.center();
    float gb = geometric_bound({grown, m_tree.falloff(light)}, x);
    if (gb == 0) return b;
    RGB m = m_material_strength[size_t(gather)];
    int bin = m_direction_bins ? enclosing_direction_bin(grown, x) : -1;
    if (bin >= 0) {
        const RGB& mb = bin_strength(points, gtree, gather, bin);
        for (int c = 0; c < 3; ++c) m[c] = std::min(m[c], mb[c]);
    }
    for (int c = 0; c < 3; ++c)
        if (m[c] != 0 && L.bound_intensity[c] != 0) b[c] = m[c] * gb * L.bound_intensity[c];
    return b;
}

RGB ProductCut::weighted(const RGB& bound, const GatherTreeNode& g, int32_t light) const {
    if (!m_pair_weight) return bound;
    RGB w = m_pair_weight->cluster_bound(g, light);
    return RGB(std::min(bound.r, w.r), std::min(bound.g, w.g), std::min(bound.b, w.b));
}

ProductPair ProductCut::make_pair(const std::vector<WeightedGatherPoint>& points,
                                  const GatherTree& gtree, int32_t gather, int32_t light,
                                  int32_t grep, int32_t lrep, const RGB& rep_value) const {
    const GatherTreeNode& G = gtree.node(gather);
    const LightTreeNode& L = m_tree.node(light);
    const WeightedGatherPoint& gp = points[size_t(grep)];
    ProductPair p{gather, light, grep, lrep, rep_value, RGB(), 0.f, true};
    // The representative pair's value, weighted by the representative's share of the pixel and
    // scaled to both clusters by their selection weights over the representatives' (the same
    // factor in every channel, representative.h): a c (W_G / w_grep) (W_L / w_lrep). Its
    // expectation over the two representatives is the pair's exact sum, whatever the colours.
    float scale = gp.a;
    if (!G.is_leaf()) scale *= representative_scale(G.weight, selection_weight(gp.w));
    if (!L.is_leaf())
        scale *= representative_scale(m_tree.weight(light),
                                      selection_weight(m_set.lights[size_t(lrep)].intensity));
    p.estimate = rep_value * scale;
    if (G.is_leaf() && L.is_leaf()) return p;  // exact
    p.bound = pair_bound(weighted(loose_bound(points, gtree, gather, light), G, light), p.estimate);
    p.tight = p.bound == 0;
    return p;
}

float ProductCut::pair_bound(const RGB& value_bound, const RGB& estimate) const {
    return m_draw_free ? bound_luminance(value_bound) : error_bound(value_bound, estimate);
}

bool ProductCut::split_gather(const GatherTree& gtree, const ProductPair& p) const {
    const GatherTreeNode& G = gtree.node(p.gather);
    const LightTreeNode& L = m_tree.node(p.light);
    if (G.is_leaf()) return false;
    if (L.is_leaf()) return true;
    if (L.kind == PointLightKind::Directional) return false;
    return length_squared(G.bounds.diagonal()) > length_squared(L.bounds.diagonal());
}

RGB ProductCut::refine(const std::vector<WeightedGatherPoint>& points, const GatherTree& gtree,
                       int k, const RGB& known, float error, int max_cut, CutCriterion criterion,
                       int tighten_members, float floor_luminance) {
    m_cut.clear();
    int32_t groot = gtree.root();
    if (groot < 0) return RGB();
    // Per gather node: sum over its members of w_i times their BSDF's bound over every
    // direction (children come after their parent).
    m_material_strength.resize(gtree.node_count());
    m_bin_strength.resize(gtree.node_count() * kDirectionBins);
    m_bin_done.assign(gtree.node_count() * kDirectionBins, 0);
    for (size_t n = gtree.node_count(); n-- > 0;) {
        const GatherTreeNode& G = gtree.node(int32_t(n));
        if (G.is_leaf()) {
            const WeightedGatherPoint& p = points[size_t(G.point)];
            RGB m = p.g.bsdf.max_value_bound(p.g.si.wo, DirectionCone::entire_sphere());
            for (int c = 0; c < 3; ++c) m[c] = p.w[c] == 0 ? 0.f : p.w[c] * m[c];
            m_material_strength[n] = m;
        } else {
            m_material_strength[n] = m_material_strength[size_t(G.children[0])] +
                                     m_material_strength[size_t(G.children[1])];
        }
    }

    // 1. The first cut: the gather root with each light tree's root. The pairs live in m_cut;
    // the heap holds (bound, index) entries, cheap to move.
    RGB total = known;
    BoundSums sums;
    m_heap.clear();
    auto push = [&](const ProductPair& p, size_t slot) {
        total += p.estimate;
        sums.add(p.bound, 1);
        if (slot == m_cut.size())
            m_cut.push_back(p);
        else
            m_cut[slot] = p;
        m_heap.push_back({p.bound, int32_t(slot)});
        std::push_heap(m_heap.begin(), m_heap.end());
    };
    // Splits pair p (taken out of the cut at `slot`) into its two children: one node is split;
    // the child that holds the pair's representative keeps its value (no new shadow ray): node
    // representatives are always one of their children's.
    auto split = [&](const ProductPair& p, size_t slot) {
        bool gather_side = split_gather(gtree, p);
        const GatherTreeNode& G = gtree.node(p.gather);
        std::array<int32_t, 2> children = gather_side
                                              ? std::array<int32_t, 2>{G.children[0], G.children[1]}
                                              : m_tree.node(p.light).children();
        for (int c = 0; c < 2; ++c) {
            int32_t child = children[size_t(c)];
            ProductPair q;
            if (gather_side) {
                int32_t r =
                    gtree.holds(child, p.grep) ? p.grep : gtree.rep(child, uint32_t(p.lrep));
                RGB v = r == p.grep ? p.rep_value : value(points[size_t(r)], p.lrep);
                q = make_pair(points, gtree, child, p.light, r, p.lrep, v);
            } else {
                // The gather representative goes with the light representative (the key).
                int32_t r = m_tree.rep(child, k);
                int32_t g = r == p.lrep ? p.grep : gtree.rep(p.gather, uint32_t(r));
                RGB v = r == p.lrep ? p.rep_value : value(points[size_t(g)], r);
                q = make_pair(points, gtree, p.gather, child, g, r, v);
            }
            push(q, c == 0 ? slot : m_cut.size());
        }
    };
    for (PointLightKind kind : kAllPointLightKinds) {
        int32_t lroot = m_tree.root(kind);
        if (lroot < 0) continue;
        int32_t lrep = m_tree.rep(lroot, k);
        int32_t grep = gtree.rep(groot, uint32_t(lrep));
        push(make_pair(points, gtree, groot, lroot, grep, lrep, value(points[size_t(grep)], lrep)),
             m_cut.size());
    }

    // 2. Refine the pair with the largest bound until every bound is within the error, or the
    // cut has max_cut pairs. The cap stops refining whatever the estimates are: a rule that went
    // on splitting the pairs whose estimate was a spike (a rare representative scaled to its
    // whole cluster) took light away on average, since it split the high draws and kept the low
    // ones (the classroom was 10% dark at a cut of 300 with it: bench/RESULTS.md, "Many-light
    // images that converge"). The spikes are noise the later passes average away.
    while (!m_heap.empty() && int(m_cut.size()) < max_cut) {
        float top = m_heap.front().bound;
        float tolerance = cut_tolerance(error, m_draw_free ? known : total, floor_luminance);
        if (top <= 0.f) break;
        if (criterion == CutCriterion::Max ? top <= tolerance : sums.within(tolerance)) break;
        std::pop_heap(m_heap.begin(), m_heap.end());
        size_t slot = size_t(m_heap.back().slot);
        m_heap.pop_back();
        ProductPair p = m_cut[slot];
        total = total - p.estimate;
        sums.add(p.bound, -1);
        if (!p.tight) {
            // Tighten the bound and look again: the pair may no longer be the worst.
            p.tight = true;
            if (gtree.node(p.gather).end - gtree.node(p.gather).begin <= tighten_members) {
                float b = pair_bound(weighted(tight_bound(points, gtree, p.gather, p.light),
                                              gtree.node(p.gather), p.light),
                                     p.estimate);
                p.bound = std::min(p.bound, b);
                push(p, slot);
                continue;
            }
        }
        split(p, slot);
    }
    // Sum the cut afresh: the running total drifts by float cancellation.
    RGB L;
    for (const ProductPair& p : m_cut) L += p.estimate;
    return L;
}

RGB ProductCut::exact(const std::vector<WeightedGatherPoint>& points, const GatherTree& gtree,
                      int32_t gather, int32_t light) const {
    const GatherTreeNode& G = gtree.node(gather);
    RGB sum;
    std::vector<int32_t> stack;
    for (int32_t m = G.begin; m < G.end; ++m) {
        const WeightedGatherPoint& p = points[size_t(gtree.members()[size_t(m)])];
        stack.assign(1, light);
        while (!stack.empty()) {
            int32_t n = stack.back();
            stack.pop_back();
            if (m_tree.node(n).is_leaf())
                sum += p.a * value(p, m_tree.light(n));
            else
                stack.insert(stack.end(),
                             {m_tree.node(n).children()[0], m_tree.node(n).children()[1]});
        }
    }
    return sum;
}

}  // namespace ml
