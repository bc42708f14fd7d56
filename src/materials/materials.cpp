// Materials: texture lookups, bump mapping and Bxdf construction at a hit.
#include "materials/materials.h"

#include "core/rng.h"
#include "materials/bxdfs.h"
#include "materials/fresnel.h"
#include "materials/textures.h"

namespace ml {

Frame shading_frame(const SurfaceInteraction& si, const FloatTexture* displacement,
                    const ImageLookup* normal_map) {
    if (normal_map) {
        // pbrt-v4's NormalMap: the texel, 2c - 1, is a normal in the frame of the shading normal
        // and dpdu; the new normal stays on the side of the geometric one.
        const RGB c = normal_map->lookup({si.p, si.uv, si.ng});
        Vec3 local(2 * c.r - 1, 2 * c.g - 1, 2 * c.b - 1);
        const float l2 = length_squared(local);
        if (!(l2 > 0) || !std::isfinite(l2)) return Frame::from_normal_tangent(si.ns, si.dpdu);
        const Vec3 n = Frame::from_normal_tangent(si.ns, si.dpdu).to_world(local / std::sqrt(l2));
        return Frame::from_normal_tangent(face_forward(normalize(n), si.ng), si.dpdu);
    }
    if (!displacement) return Frame::from_normal_tangent(si.ns, si.dpdu);
    // Displace the surface along ns by d(u, v) and differentiate by finite differences.
    constexpr float kDelta = 0.0005f;
    TextureEvalContext ctx{si.p, si.uv, si.ng};
    TextureEvalContext cu{si.p + si.dpdu * kDelta, Vec2(si.uv.x + kDelta, si.uv.y), si.ng};
    TextureEvalContext cv{si.p + si.dpdv * kDelta, Vec2(si.uv.x, si.uv.y + kDelta), si.ng};
    float d = displacement->eval(ctx);
    float du = (displacement->eval(cu) - d) / kDelta;
    float dv = (displacement->eval(cv) - d) / kDelta;
    Vec3 dpdu = si.dpdu + si.ns * du, dpdv = si.dpdv + si.ns * dv;
    Vec3 n = cross(dpdu, dpdv);
    float l2 = length_squared(n);
    if (!(l2 > 0) || !std::isfinite(l2)) return Frame::from_normal_tangent(si.ns, si.dpdu);
    // The bumped normal stays on the side of the geometric normal (pbrt-v4 turns the shading
    // normal towards n unless the orientation is authoritative, which it is not here).
    n = face_forward(n / std::sqrt(l2), si.ng);
    return Frame::from_normal_tangent(n, dpdu);
}

Bsdf DiffuseMaterial::get_bsdf(const SurfaceInteraction& si, ScratchBuffer& scratch) const {
    RGB r = m_reflectance.eval(context(si));
    r = RGB(std::clamp(r.r, 0.f, 1.f), std::clamp(r.g, 0.f, 1.f), std::clamp(r.b, 0.f, 1.f));
    return Bsdf(frame(si), si.ng, scratch_new<DiffuseBxdf>(scratch, r));
}

namespace {
RGB clamp01(const RGB& c) {
    return {std::clamp(c.r, 0.f, 1.f), std::clamp(c.g, 0.f, 1.f), std::clamp(c.b, 0.f, 1.f)};
}
}  // namespace

Bsdf DiffuseTransmissionMaterial::get_bsdf(const SurfaceInteraction& si,
                                           ScratchBuffer& scratch) const {
    TextureEvalContext ctx = context(si);
    RGB r = clamp01(m_r.eval(ctx) * m_scale), t = clamp01(m_t.eval(ctx) * m_scale);
    return Bsdf(frame(si), si.ng, scratch_new<DiffuseTransmissionBxdf>(scratch, r, t));
}

namespace {
// A metal of the given normal-incidence reflectance (pbrt-v4's mapping): eta = 1,
// k = 2 sqrt(r) / sqrt(1 - r).
RGB k_for_reflectance(RGB r) {
    r = RGB(std::clamp(r.r, 0.f, 0.9999f), std::clamp(r.g, 0.f, 0.9999f),
            std::clamp(r.b, 0.f, 0.9999f));
    return RGB(2 * std::sqrt(r.r) / std::sqrt(1 - r.r), 2 * std::sqrt(r.g) / std::sqrt(1 - r.g),
               2 * std::sqrt(r.b) / std::sqrt(1 - r.b));
}
}  // namespace

Bsdf ConductorMaterial::get_bsdf(const SurfaceInteraction& si, ScratchBuffer& scratch) const {
    TextureEvalContext ctx = context(si);
    RGB eta, k;
    if (m_use_reflectance) {
        eta = RGB(1);
        k = k_for_reflectance(m_reflectance.eval(ctx));
    } else {
        eta = m_eta.eval(ctx);
        k = m_k.eval(ctx);
    }
    return Bsdf(frame(si), si.ng,
                scratch_new<ConductorBxdf>(scratch, m_roughness.distribution(ctx), eta, k));
}

Bsdf DielectricMaterial::get_bsdf(const SurfaceInteraction& si, ScratchBuffer& scratch) const {
    TextureEvalContext ctx = context(si);
    float eta = m_eta.eval(ctx);
    if (eta == 0) eta = 1;
    return Bsdf(frame(si), si.ng,
                scratch_new<DielectricBxdf>(scratch, m_roughness.distribution(ctx), eta));
}

Bsdf ThinDielectricMaterial::get_bsdf(const SurfaceInteraction& si, ScratchBuffer& scratch) const {
    float eta = m_eta.eval(context(si));
    if (eta == 0) eta = 1;
    return Bsdf(frame(si), si.ng, scratch_new<ThinDielectricBxdf>(scratch, eta));
}

const Material* MixMaterial::choose(const SurfaceInteraction& si) const {
    float amount = m_amount.eval({si.p, si.uv, si.ng});
    if (amount <= 0) return m_materials[0];
    if (amount >= 1) return m_materials[1];
    // A uniform number in [0, 1) from the point and the direction (24 bits of the hash).
    uint64_t h = hash_ints(float_bits(si.p.x, si.p.y), float_bits(si.p.z, si.wo.x),
                           float_bits(si.wo.y, si.wo.z), 0x6d6978 /* "mix" */);
    float u = float(h >> 40) * 0x1p-24f;
    return amount < u ? m_materials[0] : m_materials[1];
}

CoatedDiffuseMaterial::CoatedDiffuseMaterial(RGBParam reflectance, FloatParam eta,
                                             RoughnessParams roughness, float thickness,
                                             int maxdepth,
                                             std::shared_ptr<FloatTexture> displacement)
    : MaterialBase(std::move(displacement)),
      m_reflectance(std::move(reflectance)),
      m_eta(std::move(eta)),
      m_roughness(std::move(roughness)),
      m_thickness(std::max(thickness, 0.f)),
      m_base_visits(CoatLayer::visits_for_max_depth(maxdepth)) {
    if (!m_eta.tex) {
        m_round_trip_const =
            coat_internal_round_trip(m_eta.value == 0 ? 1.f : m_eta.value, m_thickness);
    } else {
        m_round_trip_table.reset(new float[kRoundTripTable]);
        for (int i = 0; i < kRoundTripTable; ++i)
            m_round_trip_table[i] = coat_internal_round_trip(
                std::exp2(-2 + 4.f * i / (kRoundTripTable - 1)), m_thickness);
    }
}

float CoatedDiffuseMaterial::round_trip(float eta) const {
    if (!m_round_trip_table) return m_round_trip_const;
    // Tabulated over log2(eta) in [-2, 2].
    float x = std::clamp((std::log2(eta) + 2) / 4, 0.f, 1.f) * (kRoundTripTable - 1);
    int i = std::min(int(x), kRoundTripTable - 2);
    float t = x - i;
    return (1 - t) * m_round_trip_table[i] + t * m_round_trip_table[i + 1];
}

Bsdf CoatedDiffuseMaterial::get_bsdf(const SurfaceInteraction& si, ScratchBuffer& scratch) const {
    TextureEvalContext ctx = context(si);
    float eta = m_eta.eval(ctx);
    if (eta == 0) eta = 1;
    RGB r = clamp01(m_reflectance.eval(ctx));
    CoatLayer layer{m_thickness, round_trip(eta), m_base_visits};
    return Bsdf(
        frame(si), si.ng,
        scratch_new<CoatedDiffuseBxdf>(scratch, m_roughness.distribution(ctx), eta, r, layer));
}

CoatedConductorMaterial::CoatedConductorMaterial(CoatedConductorParams params,
                                                 std::shared_ptr<FloatTexture> displacement)
    : MaterialBase(std::move(displacement)), m_params(std::move(params)) {
    const CoatedConductorParams& p = m_params;
    bool constant = !p.interface_roughness.u.tex && !p.interface_roughness.v.tex &&
                    !p.conductor_roughness.u.tex && !p.conductor_roughness.v.tex &&
                    !p.thickness.tex && !p.conductor_eta.tex && !p.conductor_k.tex &&
                    !p.reflectance.tex;
    if (constant)
        m_trap = std::make_unique<CoatedConductorTrap>(
            CoatedConductorBxdf::compute_trap(layers(TextureEvalContext{})));
}

CoatedConductorMaterial::~CoatedConductorMaterial() = default;

Bsdf CoatedConductorMaterial::get_bsdf(const SurfaceInteraction& si, ScratchBuffer& scratch) const {
    CoatedConductorLayers l = layers(context(si));
    l.trap = m_trap.get();
    return Bsdf(frame(si), si.ng, scratch_new<CoatedConductorBxdf>(scratch, l));
}

CoatedConductorLayers CoatedConductorMaterial::layers(const TextureEvalContext& ctx) const {
    const CoatedConductorParams& p = m_params;
    CoatedConductorLayers l;
    l.coat = p.interface_roughness.distribution(ctx);
    l.base = p.conductor_roughness.distribution(ctx);
    l.eta = p.eta == 0 ? 1.f : p.eta;
    RGB eta = RGB(1), k;
    if (p.use_reflectance) {
        k = k_for_reflectance(p.reflectance.eval(ctx));
    } else {
        eta = p.conductor_eta.eval(ctx);
        k = p.conductor_k.eval(ctx);
    }
    // The conductor's IOR relative to the coat's.
    l.base_eta = eta / l.eta;
    l.base_k = k / l.eta;
    l.thickness = std::max(0.f, p.thickness.eval(ctx));
    l.base_visits = CoatLayer::visits_for_max_depth(p.maxdepth);
    return l;
}

}  // namespace ml
