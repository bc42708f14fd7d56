// The product cut of Multidimensional Lightcuts (Walter et al. 2006), restricted to one pixel
// pass: a cut through the implicit product of the pass's gather tree and the light tree. A pair
// (G, L) of a gather node and a light node stands for sum_{i in G} sum_{j in L} w_i c_i(j), the
// light of L's lights at G's gather points weighted by their share w_i of the pixel; it is
// shaded by its representative pair alone (one shadow ray) and scaled to the strengths of G and
// L. sum_{i in G} w_i * node_error_bound(L, x_i) is a true upper bound of that sum (bounds.h);
// the pair's error bound is the larger of it and the estimate, channel by channel, since both
// the estimate and the exact sum lie between 0 and that. The cut is refined, always splitting the
// pair with the largest bound, until every bound is below the error times the pixel's estimate or
// the cut holds max_cut pairs (past which only pairs whose bound is a quarter of the estimate
// are split, up to 2 max_cut).
//
// Representatives: light node L uses its k-th (k drawn per pixel pass), gather node G the one
// keyed by that light representative (gather_tree.h), so the gather representatives of a cut's
// pairs are independent of one another. Both are drawn in proportion to their selection weights
// (luminance) and the pair's value is scaled by the clusters' weights over the
// representatives', one factor for every channel, so each pair's estimate has the pair's exact
// sum as its expectation in every channel, whatever the colours of lights and throughputs
// (manylight/representative.h).
//
// When the cut is fine enough (`mdlightcuts.criterion`, as `lightcuts.criterion`):
// - "max" (default): Walter et al.'s test, every pair's bound below the error times the estimate.
//   One cut shades the whole pixel, so its pairs' errors add up with no other samples' to average
//   with: the pixel's error is typically about the threshold, a few times it in 10% of pixels.
//   (A Hoeffding test on sqrt(sum of bounds^2), as `lightcuts.criterion=probable`, is unsound
//   here: the cut is refined where the estimates happen to be high, so the errors of the pairs
//   left are not zero-mean; with tens of thousands of pairs they added up to 80% in 1% of the
//   Cornell box's pixels.)
// - "sum": the sum of the bounds below the error: a certain bound, at the price of large cuts.
//
// Which node a pair splits: a leaf cannot be split, so a pair with one leaf splits the other.
// Otherwise the node with the larger bounding-box diagonal: both are measured against the same
// distance between the boxes, so the larger box is the larger relative size, the one whose
// spread loosens the bound most. A directional light node has no box (its geometric term does
// not depend on where the gather points are, only on its cone of directions): it is split first.
#pragma once

#include <cstdint>
#include <vector>

#include "manylight/gather.h"
#include "manylight/gather_tree.h"
#include "manylight/light_tree.h"
#include "manylight/many_lights.h"
#include "manylight/point_light_set.h"

namespace ml {

// Fixed cones of directions the loose bound uses (product_cut.cpp): 26 axes, half-angle 45 deg.
constexpr int kDirectionBins = 26;
constexpr float kDirectionBinAngle = 0.7853982f;
constexpr float kDirectionBinCos = 0.70710678f;

// A gather point of a pixel pass and its weight in the pass's pixel estimate.
struct WeightedGatherPoint {
    GatherPoint g;
    float a = 0;       // its camera sample's filter weight over the sum of the pass's
    RGB w;             // a * g.beta: the gather tree's strength of this point
    int32_t tag = -1;  // the integrator's own index for the point (bdlightcuts: its VSP data)
};

// An optional weight in [0, 1] of each (gather point, point light) pair, which multiplies the
// pair's value (bdlightcuts' split weights). Weights of at most 1 leave every bound valid.
class PairWeight {
public:
    virtual ~PairWeight() = default;
    // `t`: the pair's terms, as point_light_contribution gave them (the pair gives light).
    virtual float weight(const WeightedGatherPoint& p, const PointLight& pl,
                         const PointLightTerms& t) const = 0;
    // A bound, channel by channel, of the weighted sum of a gather node's points with a light
    // node's lights, which the cut takes where it is below its own (+infinity: none).
    virtual RGB cluster_bound(const GatherTreeNode& g, int32_t light_node) const {
        return RGB(kInfinity);
    }
};

enum class CutCriterion { Max, Sum };

struct ProductPair {
    int32_t gather = -1, light = -1;  // gather-tree and light-tree nodes
    int32_t grep = -1, lrep = -1;     // representatives: gather point and light indices
    RGB rep_value;  // c_grep(lrep): point_light_contribution (beta included), clamped, visible
    RGB estimate;   // the pair's estimate of its part of the pixel
    // Luminance of its error bound, max(estimate, bound of the exact value) channel by channel:
    // 0 when exact, may be +infinity.
    float bound = 0;
    bool tight = false;  // bound is from tight_bound (else from loose_bound)
};

// One thread's cut maker (it keeps its buffers from pixel to pixel; it caches no bound).
class ProductCut {
public:
    ProductCut(const Scene& scene, const PointLightSet& set, const LightTree& tree,
               const ManyLightSettings& settings)
        : m_scene(scene), m_set(set), m_tree(tree), m_settings(settings) {}

    // The cut of one pixel pass: the pixel's radiance from the point lights. Light
    // representative k (0 <= k < LightTree::reps()) of every light node. `known`: the rest of the
    // pixel's estimate (emission, sampled direct light), which counts in the estimate that the
    // error threshold is relative to. Clears the cut first. A pair whose gather node has at most
    // `tighten_members` members gets its tight bound when it reaches the top of the heap (as
    // Lightcuts does); a larger one is split on its loose bound, since the tight bound costs a
    // material bound per member (about as much as several shadow rays).
    // `floor_luminance`: the tolerance is error times the larger of the estimate's luminance and
    // this (manylight/pilot.h).
    RGB refine(const std::vector<WeightedGatherPoint>& points, const GatherTree& gtree, int k,
               const RGB& known, float error, int max_cut,
               CutCriterion criterion = CutCriterion::Max, int tighten_members = 1 << 30,
               float floor_luminance = 0);
    // Weights every pair's value by w (nullptr: none); w must outlive the cut maker's use.
    void set_pair_weight(const PairWeight* w) { m_pair_weight = w; }
    // Whether the loose bound takes the BSDFs' bounds over the fixed cones of directions (true,
    // the default) or over every direction alone. The fixed cones cost a BSDF bound per gather
    // point and cone: mdlightcuts' kitchen takes 11% more CPU without them, bdlightcuts' 7 to 10%
    // less at the same relMSE (bench/RESULTS.md, "Issue 17, session 18").
    void set_direction_bins(bool on) { m_direction_bins = on; }
    // Whether the refinement looks at no draw of its own (false: the default, as above). On: a
    // pair's place in the heap is its bound alone, not the larger of it and its estimate, and
    // the tolerance is relative to `known` (and the floor), not to the running estimate. Then
    // which pairs are split depends on the points, the trees and `known` only, so every pair's
    // estimate keeps its mean whatever max_cut stops the cut. Off, the two rules select the draws
    // they keep (a spike is split, a low draw stays: darker where the cap binds; a pixel whose
    // draws are high stops earlier: brighter), and the mean rests on their cancelling
    // (bench/RESULTS.md, "Many-light images that converge").
    void set_draw_free(bool on) { m_draw_free = on; }
    // The cut refine() made (clustered pairs and exact ones alike).
    const std::vector<ProductPair>& pairs() const { return m_cut; }

    // The error bound of (G, L), RGB: sum over G's members of w_i * node_error_bound(L, x_i).
    RGB tight_bound(const std::vector<WeightedGatherPoint>& points, const GatherTree& gtree,
                    int32_t gather, int32_t light) const;
    // The exact sum the pair stands for: every member with every light, a shadow ray each.
    RGB exact(const std::vector<WeightedGatherPoint>& points, const GatherTree& gtree,
              int32_t gather, int32_t light) const;

    // A cheaper bound of the pair's exact value, never below tight_bound (valid after refine() with
    // the same points and tree); without the direction bins, never below the bound with them.
    RGB loose_bound(const std::vector<WeightedGatherPoint>& points, const GatherTree& gtree,
                    int32_t gather, int32_t light) const;

private:
    // c_i(j) with its shadow ray, VPL clamping applied.
    RGB value(const WeightedGatherPoint& p, int32_t light) const;
    // A bound of a pair's value, lowered to the pair weight's cluster bound where that is lower.
    RGB weighted(const RGB& bound, const GatherTreeNode& g, int32_t light) const;
    ProductPair make_pair(const std::vector<WeightedGatherPoint>& points, const GatherTree& gtree,
                          int32_t gather, int32_t light, int32_t grep, int32_t lrep,
                          const RGB& rep_value) const;
    // Sum over the node's members of w_i times the BSDF's bound over fixed cone `bin`.
    const RGB& bin_strength(const std::vector<WeightedGatherPoint>& points, const GatherTree& gtree,
                            int32_t gather, int bin) const;
    bool split_gather(const GatherTree& gtree, const ProductPair& p) const;

    const Scene& m_scene;
    const PointLightSet& m_set;
    const LightTree& m_tree;
    const ManyLightSettings& m_settings;
    const PairWeight* m_pair_weight = nullptr;
    bool m_direction_bins = true;
    bool m_draw_free = false;
    // A pair's key in the heap from the bound of its value and its estimate (set_draw_free).
    float pair_bound(const RGB& value_bound, const RGB& estimate) const;
    struct HeapEntry {
        float bound;
        int32_t slot;  // index into m_cut
        bool operator<(const HeapEntry& o) const { return bound < o.bound; }
    };
    std::vector<ProductPair> m_cut;
    std::vector<HeapEntry> m_heap;  // a max-heap on bound while refining
    // Per gather node: sum of w_i times the BSDF's bound over every direction.
    std::vector<RGB> m_material_strength;
    // Per gather node and fixed cone: bin_strength, computed on first use in the pass.
    mutable std::vector<RGB> m_bin_strength;
    mutable std::vector<uint8_t> m_bin_done;
};

}  // namespace ml
