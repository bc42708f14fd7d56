// The weights Bidirectional Lightcuts puts on its paths (split_weights.h) as the product cut and
// the remainder take them: the split weight of each (VSP, point light) pair of a pass, with the
// bound of a cluster pair, the remainder's weight by the direction its paths leave in, and what
// they need of the point lights (each one's lobe and flux).
#pragma once

#include <vector>

#include "core/color.h"
#include "integrators/bdlightcuts/split_weights.h"
#include "manylight/light_tree.h"
#include "manylight/point_light_set.h"
#include "manylight/product_cut.h"
#include "transport/path_tracer.h"

namespace ml {

// What a VSP at eye vertex x_j keeps for its pairs' weights.
struct VspWeightState {
    float prefix = 0;       // w_1 + ... + w_{j-2}: the weights fixed by the eye path alone
    float pending_mt = -1;  // M_{j-1} T_{j-1,j}, for w_{j-1} (< 0: split j-1 is impossible)
    float pending_mu = 1;   // mu_{j-1}
    float mu = 1;           // mu_j
    int depth = 1;          // scattering vertices of the eye path up to x_j
    // A VSP in a homogeneous medium of grey extinction: the stretch of the eye path it was
    // drawn on (the unit ray from eq_o along eq_d, up to eq_tmax), its distance eq_t along
    // it, and delta tracking's density of drawing it there (per unit length; 0: none). Its
    // joins to lights at a point are weighed by MIS against the stretch's equiangular
    // sample (trace_eye), as `path` weighs its single scattering.
    Vec3 eq_o, eq_d;
    float eq_tmax = 0, eq_t = 0, eq_track = 0;
};

// A light at a point of the set (point and spot lights), which the equiangular samples in media
// draw towards.
inline bool point_emitter(const PointLight& pl) {
    return !pl.is_vpl && pl.kind == PointLightKind::Omni;
}

// An upper bound of D_j, the VSP's lobe towards the eye f(wo, wi) |cos wo|, over every light
// direction wi (SplitWeighting::weight): exact for Lambertian lobes alone (f is the same for
// every wi on a side) and for the phase function (its largest value, along the arrival),
// +infinity for the others.
float max_vsp_density(const Bsdf& bsdf, const Vec3& wo);

// Each light node's flux, children before parents (whatever order the tree stores them).
std::vector<RGB> light_node_flux(const PointLightSet& set, const LightTree& tree);

// The split weight of each (VSP, point light) pair of a pass.
class SplitWeighting final : public PairWeight {
public:
    SplitWeighting(const PointLightSet& set, const SplitWeightOptions& o, int max_depth)
        : m_set(set), m_o(o), m_max_depth(max_depth) {}
    const std::vector<VspWeightState>* vsps = nullptr;
    // Each set light's probability of the equiangular samples' choice (empty: none).
    const std::vector<float>* eq_pmf = nullptr;
    // Per light-tree node: its lights' summed flux (the integrator's, redone with each set).
    const std::vector<RGB>* node_flux = nullptr;

    // The pair's split weight, weighed by MIS against the equiangular samples in media.
    float weight(const WeightedGatherPoint& p, const PointLight& pl,
                 const PointLightTerms& t) const override;
    // The split weight of VSP v (gather point g) joined to pl.
    float weight(const VspWeightState& v, const GatherPoint& g, const PointLight& pl,
                 const PointLightTerms& t) const;
    // With the clamping weight, w M T D <= C_clamp, so a VSP with throughput beta and a light
    // with flux Phi give at most C_clamp beta Phi (channel by channel, M and D being the largest
    // channels of the BSDFs' values): a cluster pair at most C_clamp (the VSP node's strength)
    // (the light node's flux).
    RGB cluster_bound(const GatherTreeNode& g, int32_t light_node) const override;

private:
    const PointLightSet& m_set;
    const SplitWeightOptions& m_o;
    int m_max_depth;
};

// The remainder r of the paths that leave x_{J+1} (the vertex after the last VSP, x_J) along wi:
// D_{J+1} is x_{J+1}'s lobe between x_J and wi (trace_eye's D for w_J; in_medium: x_{J+1} is a
// scattering point in a medium); a delta lobe's sample makes split J weigh 0 (pending_mt < 0).
class RemainderWeight final : public FirstBounceWeight {
public:
    RemainderWeight(const SplitWeightOptions& o, float prefix, float pending_mt, float pending_mu,
                    bool in_medium)
        : m_o(o),
          m_prefix(prefix),
          m_pending_mt(pending_mt),
          m_pending_mu(pending_mu),
          m_in_medium(in_medium) {}
    float weight(const Bsdf& bsdf, const Vec3& wo, const Vec3& wi, bool specular,
                 const RGB* f) const override;
    bool vanishes(const Bsdf& bsdf, const Vec3& wo) const override;
    // No split reaches light emitted by a medium (no light path starts in one): the remainder
    // takes all of it.
    bool weighs_media_emission() const override { return false; }

private:
    const SplitWeightOptions& m_o;
    float m_prefix, m_pending_mt, m_pending_mu;
    bool m_in_medium;
};

}  // namespace ml
