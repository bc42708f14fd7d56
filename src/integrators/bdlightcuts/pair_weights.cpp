#include "integrators/bdlightcuts/pair_weights.h"

#include <algorithm>

#include "integrators/bdlightcuts/eye_path.h"
#include "transport/mis.h"
#include "transport/volume_path.h"

namespace ml {

namespace {

// D of a point light towards unit direction w (from the light): the light side's lobe as in
// split_weights.h. VPLs: f(w, wi) |cos| of their surface (the largest channel of f);
// emitters: their emission's density. Every channel of the light's intensity towards w is at
// most D times the light's flux (light_flux). Delta emitters (point and spot lights, the
// emitters' omni points) count as D = 0, as distant lights do: no later split can take a path
// that ends at them (no eye path meets them), so clamping their connections would only lose
// the clamped part (bench/RESULTS.md, "Issue 17, session 14").
bool delta_emitter(const PointLight& pl) {
    return !pl.is_vpl &&
           (pl.kind == PointLightKind::Directional || pl.kind == PointLightKind::Omni);
}

float light_density(const PointLightSet& set, const PointLight& pl, const Vec3& w) {
    if (delta_emitter(pl)) return 0.f;
    if (pl.is_vpl) {
        if (pl.surface >= 0) {
            const VplSurface& s = set.surfaces[size_t(pl.surface)];
            RGB f = s.diffuse_only ? s.bsdf.eval_diffuse(w, s.wi) : s.bsdf.eval(w, s.wi);
            return f.max_component() * abs_dot(w, s.bsdf.frame().n);
        }
        return pl.diffuse_f * std::max(0.f, dot(pl.n, w));
    }
    return std::max(0.f, dot(pl.n, w)) / kPi;  // an area light's oriented point
}

// The flux Phi of a point light, channel by channel, with I(w) <= Phi D(w) (light_density);
// +infinity for directional lights, which have no D.
RGB light_flux(const PointLightSet& set, const PointLight& pl) {
    if (delta_emitter(pl)) return RGB(kInfinity);
    if (pl.is_vpl) {
        if (pl.surface >= 0) return set.surfaces[size_t(pl.surface)].flux;
        return pl.diffuse_f > 0 ? pl.intensity * (1.f / pl.diffuse_f) : RGB();
    }
    return pl.intensity * kPi;
}

// The MIS weight of VSP v's join to point emitter pl (chosen with probability pmf by the
// equiangular samples) against the equiangular sample of v's stretch: the power heuristic of
// delta tracking's density of v's distance against the equiangular one. 1 where v has none.
float equiangular_mis(const VspWeightState& v, const PointLight& pl, float pmf) {
    if (!(v.eq_track > 0) || !(pmf > 0)) return 1.f;
    const Equiangular eq(Ray{v.eq_o, v.eq_d, kInfinity, 0}, v.eq_tmax, pl.p);
    if (!eq.valid) return 1.f;
    return power_heuristic(v.eq_track, pmf * eq.pdf_length(v.eq_t));
}

}  // namespace

float max_vsp_density(const Bsdf& bsdf, const Vec3& wo) {
    if ((bsdf.flags() & (kBxdfGlossy | kBxdfSpecular)) || !(bsdf.flags() & kBxdfDiffuse))
        return kInfinity;
    const Vec3& n = bsdf.frame().n;
    float f = std::max(bsdf.eval(wo, n).max_component(), bsdf.eval(wo, -n).max_component());
    return f * abs_dot(wo, n);
}

float SplitWeighting::weight(const WeightedGatherPoint& p, const PointLight& pl,
                             const PointLightTerms& t) const {
    const VspWeightState& v = (*vsps)[size_t(p.tag)];
    float w = weight(v, p.g, pl, t);
    if (v.eq_track > 0 && w > 0 && point_emitter(pl) && eq_pmf && !eq_pmf->empty()) {
        const size_t i = size_t(&pl - m_set.lights.data());
        if (i < eq_pmf->size()) w *= equiangular_mis(v, pl, (*eq_pmf)[i]);
    }
    return w;
}

float SplitWeighting::weight(const VspWeightState& v, const GatherPoint& g, const PointLight& pl,
                             const PointLightTerms& t) const {
    if (pl.depth > 0 && v.depth + int(pl.depth) > m_max_depth) return 0.f;
    const SurfaceInteraction& si = g.si;
    const Vec3& wi = t.wi;
    const float inv_d2 = t.inv_d2;
    float f = t.f.max_component();
    if (!(f > 0)) return 0.f;
    // w_{j-1} needs D_j, the VSP's lobe between the eye and this light; M_j has the
    // connection's cosine (point_light_contribution's).
    float dj = eye_lobe_density(f, si.wo, wi, g.bsdf.frame().n, g.in_medium),
          mj = f * abs_dot(wi, si.ns);
    float prefix = v.prefix;
    if (v.pending_mt >= 0) prefix += split_weight(m_o, prefix, v.pending_mt * dj, dj, v.pending_mu);
    float dl = light_density(m_set, pl, -wi);
    return split_weight(m_o, prefix, mj * inv_d2 * dl, dl, v.mu);
}

RGB SplitWeighting::cluster_bound(const GatherTreeNode& g, int32_t light_node) const {
    if (!m_o.clamp || !node_flux || node_flux->empty()) return RGB(kInfinity);
    const RGB& phi = (*node_flux)[size_t(light_node)];
    RGB b;
    for (int c = 0; c < 3; ++c)
        b[c] = (g.strength[c] == 0 || phi[c] == 0) ? 0.f : m_o.c_clamp * g.strength[c] * phi[c];
    return b;
}

float RemainderWeight::weight(const Bsdf& bsdf, const Vec3& wo, const Vec3& wi, bool specular,
                              const RGB* f) const {
    if (specular) return remainder_weight(m_o, m_prefix, -1.f, 0.f, m_pending_mu);
    const float d = eye_lobe_density((f ? *f : bsdf.eval(wo, wi)).max_component(), wo, wi,
                                     bsdf.frame().n, m_in_medium);
    return remainder_weight(m_o, m_prefix, m_pending_mt, d, m_pending_mu);
}

bool RemainderWeight::vanishes(const Bsdf& bsdf, const Vec3& wo) const {
    if ((bsdf.flags() & kBxdfSpecular) &&
        !remainder_vanishes(m_o, m_prefix, -1.f, 0.f, m_pending_mu))
        return false;
    return remainder_vanishes(m_o, m_prefix, m_pending_mt, max_vsp_density(bsdf, wo), m_pending_mu);
}

std::vector<RGB> light_node_flux(const PointLightSet& set, const LightTree& tree) {
    std::vector<RGB> node_flux(tree.node_count());
    std::vector<uint8_t> summed(tree.node_count(), 0);
    for (PointLightKind kind : kAllPointLightKinds) {
        if (tree.root(kind) < 0) continue;
        std::vector<int32_t> stack{tree.root(kind)};
        while (!stack.empty()) {
            int32_t n = stack.back();
            const LightTreeNode& L = tree.node(n);
            if (L.is_leaf()) {
                node_flux[size_t(n)] = light_flux(set, set.lights[size_t(tree.light(n))]);
            } else if (!summed[size_t(L.children()[0])] || !summed[size_t(L.children()[1])]) {
                for (int32_t c : L.children())
                    if (!summed[size_t(c)]) stack.push_back(c);
                continue;
            } else {
                node_flux[size_t(n)] =
                    node_flux[size_t(L.children()[0])] + node_flux[size_t(L.children()[1])];
            }
            summed[size_t(n)] = 1;
            stack.pop_back();
        }
    }
    return node_flux;
}

}  // namespace ml
