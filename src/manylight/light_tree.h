// The Lightcuts light tree (Walter et al. 2005): one binary tree per kind of point light (omni,
// oriented, directional, glossy) over the indices of a light vector. Every node is a cluster of
// lights with a representative light, the summed RGB intensity, the bounding box of the positions
// and the bounding cone of directions; the lightcuts integrator walks a cut through it using the
// error bounds of manylight/bounds.h.
//
// Built bottom-up by Parallel Locally-Ordered Clustering (Meister & Bittner 2018) under the
// Lightcuts metric I * (alpha^2 + c^2 (1 - cos beta)^2), in O(N log N).
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "core/color.h"
#include "core/cone.h"
#include "core/math.h"
#include "lights/point_lights.h"

namespace ml {

// Independent representatives kept per node (LightTreeOptions::reps, this many by default): rep
// k of a node is picked among its lights with probability proportional to their selection
// weight (representative.h: the intensity's luminance), independently for each k, so a gather
// point that shades with rep k (k drawn from its sampler) makes an error of zero mean in every
// channel, and the samples of a pixel make independent errors that average out (rep 0 is
// LightTree::light). Every pixel draws from the same k, so their errors also add up over the
// image: the image's mean moves with the tree's seed, less with more (bench/RESULTS.md, "Issue
// 17, session 19").
constexpr int kLightTreeReps = 8;
constexpr int kLightTreeMaxReps = 256;
// Which of `reps` representatives a uniform u in [0, 1) draws.
inline int rep_index(float u, int reps) { return std::min(reps - 1, int(u * float(reps))); }

// The hot part of a node: what a cut's bounds (bounds.h) and refinement read at every node it
// visits, in one cache line. What only a node whose estimate is made needs (its weight and
// representatives), or only some kinds and users (intensity, falloff), lives in the tree's side
// arrays, indexed by node (LightTree's accessors), so that a cut's walk through a large tree
// pulls one line per node rather than two or three (bench/RESULTS.md, "Issue 13, session 10").
struct alignas(64) LightTreeNode {
    Bounds3 bounds;  // positions of the node's lights (directional lights: unused, empty)
    DirectionCone
        cone;  // oriented, glossy: lobe axes; directional: travel directions; omni: the sphere
    // Channel by channel, at least both the sum of the lights' intensities and any
    // representative's intensity scaled to the node (I_rep weight / w_rep): weight times the
    // lights' largest I_c / w_i. Bounds built on it (bounds.h) hold the exact sum and every
    // possible estimate alike, so they do not depend on which representative was drawn. Equal
    // to the intensity where the lights share one colour; larger where they mix colours, as
    // the estimate's spread is.
    RGB bound_intensity;
    // The children are first_child and first_child + 1 (the tree is laid out with siblings
    // side by side); -1 for a leaf.
    int32_t first_child = -1;
    // How many lights the node holds when they are all VPLs, whose contributions vpl.clamp caps
    // (so the node's is at most this many times the clamp); 0 for a leaf that is not a VPL, -1
    // for a cluster with one.
    int32_t clampable = 0;
    PointLightKind kind = PointLightKind::Omni;

    bool is_leaf() const { return first_child < 0; }
    // Both children's indices ({-1, -1} for a leaf).
    std::array<int32_t, 2> children() const {
        return is_leaf() ? std::array<int32_t, 2>{-1, -1}
                         : std::array<int32_t, 2>{first_child, first_child + 1};
    }
};
static_assert(sizeof(LightTreeNode) == 64, "a light-tree node's hot part is one cache line");

// A node as the bounds of bounds.h read it: its hot part and its falloff table (kFalloffBins
// entries from the tree's side array, read for glossy nodes only).
struct LightNodeRef {
    const LightTreeNode& node;
    const uint8_t* falloff;
};

struct LightTreeOptions {
    uint64_t seed = 0;  // representative choices; the same seed gives the same tree
    // c of the metric for oriented lights is half the scene's bounding-box diagonal, given here.
    // <= 0: half the diagonal of the oriented lights' own bounding box.
    float scene_diagonal = 0;
    int window_radius = 16;     // PLOC's search radius (neighbours on each side)
    int reps = kLightTreeReps;  // representatives per node, 1 to kLightTreeMaxReps
};

namespace detail {
struct LightTreeBuild;  // the nodes while they are built (light_tree.cpp)
}

class LightTree {
public:
    LightTree() = default;
    explicit LightTree(const std::vector<PointLight>& lights, const LightTreeOptions& opts = {});

    // Root node of the tree of one kind, or -1 when there is no light of that kind.
    int32_t root(PointLightKind kind) const { return m_roots[int(kind)]; }
    const LightTreeNode& node(int32_t i) const { return m_nodes[size_t(i)]; }
    LightNodeRef ref(int32_t i) const { return {m_nodes[size_t(i)], falloff(i)}; }
    // Representatives per node.
    int reps() const { return m_rep_count; }
    // Representative k (0 <= k < reps()) of node i; 0 is light(i). Stored node by node: the
    // pixels beside one another draw different k, and read one cache line per node rather than
    // one per k (with 8 the same CPU as k by k, with 32 to 64 2% less).
    int32_t rep(int32_t i, int k) const {
        return m_reps[size_t(i) * size_t(m_rep_count) + size_t(k)];
    }
    // The node's representative light (a leaf: its light), an index into the lights.
    int32_t light(int32_t i) const { return rep(i, 0); }
    // Sum of the lights' selection weights: rep k is light i with probability w_i / weight, and
    // stands for the node scaled by weight / w_i (representative.h).
    float weight(int32_t i) const { return m_weight[size_t(i)]; }
    // Sum of the lights' intensities.
    const RGB& intensity(int32_t i) const { return m_intensity[size_t(i)]; }
    // Glossy: the largest falloff of the node's lights, bin by bin (kFalloffBins entries).
    const uint8_t* falloff(int32_t i) const { return m_falloff[size_t(i)].data(); }
    size_t node_count() const { return m_nodes.size(); }
    size_t light_count() const { return m_light_count; }

private:
    void lay_out(detail::LightTreeBuild& build);

    std::vector<LightTreeNode> m_nodes;  // depth-first, siblings side by side
    // Side arrays, per node.
    std::vector<int32_t> m_reps;  // reps() planes of node_count() entries
    int m_rep_count = kLightTreeReps;
    std::vector<float> m_weight;
    std::vector<RGB> m_intensity;
    std::vector<std::array<uint8_t, kFalloffBins>> m_falloff;
    int32_t m_roots[kPointLightKinds] = {-1, -1, -1, -1};
    size_t m_light_count = 0;
};

// The Lightcuts clustering metric of a cluster: I (alpha^2 + c^2 (1 - cos beta)^2), I its
// selection weight (the luminance of its intensity), alpha the diagonal of its box (0 when no_box),
// beta its cone's half-angle. Exposed for tests.
float light_cluster_metric(float luminance, const Bounds3& b, float cone_theta, float c,
                           bool no_box);

}  // namespace ml
