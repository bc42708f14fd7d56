// The Lightcuts light tree (Walter et al. 2005): one binary tree per kind of point light (omni,
// oriented, directional, glossy) over the indices of a light vector. Every node is a cluster of
// lights with a representative light, the summed RGB intensity, the bounding box of the positions
// and the bounding cone of directions; the lightcuts integrator walks a cut through it using the
// error bounds of manylight/bounds.h.
//
// Built bottom-up by Parallel Locally-Ordered Clustering (Meister & Bittner 2018) under the
// Lightcuts metric I * (alpha^2 + c^2 (1 - cos beta)^2), in O(N log N).
#pragma once

#include <cstdint>
#include <vector>

#include "core/color.h"
#include "core/cone.h"
#include "core/math.h"
#include "lights/point_lights.h"

namespace ml {

// Independent representatives kept per node: rep k of a node is picked among its lights with
// probability proportional to their selection weight (representative.h: the intensity's
// luminance), independently for each k, so a gather point that shades with rep k (k drawn from
// its sampler) makes an error of zero mean in every channel, and the samples of a pixel make
// independent errors that average out (rep 0 is the node's `light`).
constexpr int kLightTreeReps = 8;

struct LightTreeNode {
    Bounds3 bounds;  // positions of the node's lights (directional lights: unused, empty)
    DirectionCone
        cone;       // oriented, glossy: lobe axes; directional: travel directions; omni: the sphere
    RGB intensity;  // sum of the lights' intensities
    // Sum of the lights' selection weights: rep k is light i with probability w_i / weight, and
    // stands for the node scaled by weight / w_i (representative.h).
    float weight = 0;
    // Channel by channel, at least both `intensity` and any representative's intensity scaled
    // to the node (I_rep weight / w_rep): weight times the lights' largest I_c / w_i. Bounds
    // built on it (bounds.h) hold the exact sum and every possible estimate alike, so they do not
    // depend on which representative was drawn. Equal to `intensity` where the lights share one
    // colour; larger where they mix colours, as the estimate's spread is.
    RGB bound_intensity;
    int32_t children[2] = {-1, -1};  // node indices; both -1 for a leaf
    int32_t light = -1;  // the representative light (a leaf: its light), index into the lights
    PointLightKind kind = PointLightKind::Omni;
    // How many lights the node holds when they are all VPLs, whose contributions vpl.clamp caps
    // (so the node's is at most this many times the clamp); 0 for a leaf that is not a VPL, -1
    // for a cluster with one.
    int32_t clampable = 0;
    int32_t reps[kLightTreeReps] = {};   // representatives per sample (reps[0] == light)
    uint8_t falloff[kFalloffBins] = {};  // glossy: the largest falloff of its lights, bin by bin

    bool is_leaf() const { return children[0] < 0; }
};

struct LightTreeOptions {
    uint64_t seed = 0;  // representative choices; the same seed gives the same tree
    // c of the metric for oriented lights is half the scene's bounding-box diagonal, given here.
    // <= 0: half the diagonal of the oriented lights' own bounding box.
    float scene_diagonal = 0;
    int window_radius = 16;  // PLOC's search radius (neighbours on each side)
};

class LightTree {
public:
    LightTree() = default;
    explicit LightTree(const std::vector<PointLight>& lights, const LightTreeOptions& opts = {});

    // Root node of the tree of one kind, or -1 when there is no light of that kind.
    int32_t root(PointLightKind kind) const { return m_roots[int(kind)]; }
    // Representative k (0 <= k < kLightTreeReps) of node i; 0 is node(i).light.
    int32_t rep(int32_t i, int k) const { return m_nodes[size_t(i)].reps[k]; }
    const LightTreeNode& node(int32_t i) const { return m_nodes[size_t(i)]; }
    const std::vector<LightTreeNode>& nodes() const { return m_nodes; }
    size_t node_count() const { return m_nodes.size(); }
    size_t light_count() const { return m_light_count; }

private:
    void build_kind(const std::vector<PointLight>& lights, PointLightKind kind,
                    const LightTreeOptions& opts);
    void order_depth_first();

    std::vector<LightTreeNode> m_nodes;
    std::vector<int32_t> m_reps;  // kLightTreeReps per node while building (then in the nodes)
    std::vector<RGB> m_chroma;    // per node while building: its lights' largest I_c / w_i
    int32_t m_roots[kPointLightKinds] = {-1, -1, -1, -1};
    size_t m_light_count = 0;
};

// The Lightcuts clustering metric of a cluster: I (alpha^2 + c^2 (1 - cos beta)^2), I its
// selection weight (the luminance of its intensity), alpha the diagonal of its box (0 when no_box),
// beta its cone's half-angle. Exposed for tests.
float light_cluster_metric(float luminance, const Bounds3& b, float cone_theta, float c,
                           bool no_box);

}  // namespace ml
