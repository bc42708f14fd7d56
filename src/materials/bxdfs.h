// The BSDF lobes manylight implements. Each is a small value type placed in the per-sample
// ScratchBuffer by its material; all hold only plain data, so skipping their destructor is safe.
#pragma once

#include <cstddef>

#include "core/scratch.h"
#include "materials/bsdf.h"
#include "materials/microfacet.h"

namespace ml {

// Bxdfs have a virtual destructor and so are not "trivially destructible" for ScratchBuffer's
// check, although destroying them does nothing. They are built in raw scratch bytes instead.
template <typename T, typename... Args>
T* scratch_new(ScratchBuffer& scratch, Args&&... args) {
    struct alignas(T) Bytes {
        std::byte b[sizeof(T)];
    };
    void* p = scratch.alloc<Bytes>();
    return new (p) T(std::forward<Args>(args)...);
}

// Lambertian reflection on both sides.
class DiffuseBxdf final : public Bxdf {
public:
    explicit DiffuseBxdf(const RGB& r) : m_r(r) {}
    uint8_t flags() const override { return m_r.is_black() ? kBxdfNone : kBxdfDiffuseReflection; }
    RGB eval(const Vec3& wo, const Vec3& wi, TransportMode mode) const override;
    std::optional<BsdfSample> sample(const Vec3& wo, float uc, const Vec2& u,
                                     TransportMode mode) const override;
    float pdf_solid_angle(const Vec3& wo, const Vec3& wi, TransportMode mode) const override;
    RGB max_value_bound(const Vec3& wo, const DirectionCone& cone) const override;

private:
    RGB m_r;
};

// Lambertian reflection plus Lambertian transmission to the other side.
class DiffuseTransmissionBxdf final : public Bxdf {
public:
    DiffuseTransmissionBxdf(const RGB& r, const RGB& t) : m_r(r), m_t(t) {}
    uint8_t flags() const override;
    RGB eval(const Vec3& wo, const Vec3& wi, TransportMode mode) const override;
    std::optional<BsdfSample> sample(const Vec3& wo, float uc, const Vec2& u,
                                     TransportMode mode) const override;
    float pdf_solid_angle(const Vec3& wo, const Vec3& wi, TransportMode mode) const override;
    RGB max_value_bound(const Vec3& wo, const DirectionCone& cone) const override;

private:
    RGB m_r, m_t;
};

// A metal: complex Fresnel per channel over a GGX distribution, or a mirror when smooth.
class ConductorBxdf final : public Bxdf {
public:
    ConductorBxdf(const TrowbridgeReitz& distrib, const RGB& eta, const RGB& k)
        : m_distrib(distrib), m_eta(eta), m_k(k) {}
    uint8_t flags() const override {
        return m_distrib.effectively_smooth() ? kBxdfSpecularReflection : kBxdfGlossyReflection;
    }
    RGB eval(const Vec3& wo, const Vec3& wi, TransportMode mode) const override;
    std::optional<BsdfSample> sample(const Vec3& wo, float uc, const Vec2& u,
                                     TransportMode mode) const override;
    float pdf_solid_angle(const Vec3& wo, const Vec3& wi, TransportMode mode) const override;
    RGB max_value_bound(const Vec3& wo, const DirectionCone& cone) const override;

private:
    TrowbridgeReitz m_distrib;
    RGB m_eta, m_k;
};

// Glass: Fresnel-weighted reflection and refraction, smooth or GGX-rough. eta is the IOR of the
// -z side relative to the +z side.
class DielectricBxdf final : public Bxdf {
public:
    DielectricBxdf(const TrowbridgeReitz& distrib, float eta) : m_distrib(distrib), m_eta(eta) {}
    uint8_t flags() const override;
    RGB eval(const Vec3& wo, const Vec3& wi, TransportMode mode) const override;
    std::optional<BsdfSample> sample(const Vec3& wo, float uc, const Vec2& u,
                                     TransportMode mode) const override;
    float pdf_solid_angle(const Vec3& wo, const Vec3& wi, TransportMode mode) const override;
    RGB max_value_bound(const Vec3& wo, const DirectionCone& cone) const override;

private:
    bool smooth() const { return m_eta == 1 || m_distrib.effectively_smooth(); }
    TrowbridgeReitz m_distrib;
    float m_eta;
};

// A thin sheet of glass (pbrt-v4's ThinDielectricBxDF): light reflects specularly or passes
// straight through (wi = -wo, no bending: the two faces are parallel), with the reflectance R of
// one interface summed over the inter-reflections inside, R + T^2 R / (1 - R^2).
class ThinDielectricBxdf final : public Bxdf {
public:
    explicit ThinDielectricBxdf(float eta) : m_eta(eta) {}
    uint8_t flags() const override { return kBxdfReflection | kBxdfTransmission | kBxdfSpecular; }
    RGB eval(const Vec3&, const Vec3&, TransportMode) const override { return RGB(); }
    std::optional<BsdfSample> sample(const Vec3& wo, float uc, const Vec2& u,
                                     TransportMode mode) const override;
    float pdf_solid_angle(const Vec3&, const Vec3&, TransportMode) const override { return 0; }
    // Delta lobes only: nothing towards a point light.
    RGB max_value_bound(const Vec3&, const DirectionCone&) const override { return RGB(); }
    // The sheet's reflectance at |cos| = cos_o, inter-reflections included.
    float reflectance(float cos_o) const;

private:
    float m_eta;
};

// The parts of pbrt-v4's clear (albedo 0) coat layer that survive in its BSDF's expected value:
// the layer's absorption and the random walk's depth limit (see coated_diffuse.cpp).
struct CoatLayer {
    float thickness = 0.01f;  // optical depth at normal incidence (pbrt-v4 "thickness")
    float round_trip = 0;     // coat_internal_round_trip(eta, thickness): precomputed, it costs
                              // an integral
    int base_visits = 5;      // pbrt-v4 "maxdepth" 10: the walk reaches the base at most 5 times

    static int visits_for_max_depth(int maxdepth) { return std::max(0, (maxdepth + 1) / 2); }
};

// A dielectric coat over a Lambertian base, evaluated in closed form (see coated_diffuse.cpp).
class CoatedDiffuseBxdf final : public Bxdf {
public:
    CoatedDiffuseBxdf(const TrowbridgeReitz& distrib, float eta, const RGB& reflectance,
                      const CoatLayer& layer);
    // A clear, non-absorbing layer with an unbounded walk (energy-conserving for a white base);
    // fdr: fresnel_diffuse_internal(eta).
    CoatedDiffuseBxdf(const TrowbridgeReitz& distrib, float eta, const RGB& reflectance, float fdr)
        : CoatedDiffuseBxdf(distrib, eta, reflectance, CoatLayer{0, fdr, 1 << 20}) {}
    uint8_t flags() const override;
    RGB eval(const Vec3& wo, const Vec3& wi, TransportMode mode) const override;
    std::optional<BsdfSample> sample(const Vec3& wo, float uc, const Vec2& u,
                                     TransportMode mode) const override;
    float pdf_solid_angle(const Vec3& wo, const Vec3& wi, TransportMode mode) const override;
    RGB max_value_bound(const Vec3& wo, const DirectionCone& cone) const override;
    RGB eval_diffuse(const Vec3& wo, const Vec3& wi, TransportMode mode) const override;
    std::optional<RGB> max_diffuse_value(const Vec3& wi) const override;

private:
    float coat_probability(float cos_o) const;
    RGB eval_base(float cos_o, float cos_i) const;
    float eval_coat(const Vec3& wo, const Vec3& wi) const;
    float pdf_coat(const Vec3& wo, const Vec3& wi) const;

    TrowbridgeReitz m_distrib;
    float m_eta;
    float m_thickness;
    RGB m_base_scale;     // reflectance sum_k (reflectance A)^k / (pi eta^2), the diffuse part's
                          // value without the transmittances in and out of the coat
    float m_base_weight;  // average escaping albedo, for lobe selection
};

// A dielectric coat over a conductor (pbrt-v4's CoatedConductorBxDF), in closed form: see
// coated_conductor.cpp. eta: the coat's IOR; base_eta, base_k: the conductor's, relative to
// the coat.
// The light a coated conductor sends beyond the coat's critical angle and lets out after more
// bounces (coated_conductor.cpp): a few hundred microfacet samples, so a material with constant
// parameters computes it once.
struct CoatedConductorTrap {
    static constexpr int kNodes = 6;
    float crit_cos = 1;    // the critical angle's cosine inside the coat
    RGB fraction[kNodes];  // trapped fraction at inside cos from crit_cos to 1
    RGB scale;             // K of eval_trapped
    float weight = 0;      // for lobe selection
};

struct CoatedConductorLayers {
    TrowbridgeReitz coat, base;
    float eta = 1.5f;
    RGB base_eta, base_k;
    float thickness = 0.01f;
    int base_visits = 5;                        // CoatLayer::visits_for_max_depth(maxdepth)
    const CoatedConductorTrap* trap = nullptr;  // precomputed for these layers, or computed
};

class CoatedConductorBxdf final : public Bxdf {
public:
    explicit CoatedConductorBxdf(const CoatedConductorLayers& layers);
    uint8_t flags() const override;
    RGB eval(const Vec3& wo, const Vec3& wi, TransportMode mode) const override;
    std::optional<BsdfSample> sample(const Vec3& wo, float uc, const Vec2& u,
                                     TransportMode mode) const override;
    float pdf_solid_angle(const Vec3& wo, const Vec3& wi, TransportMode mode) const override;
    RGB max_value_bound(const Vec3& wo, const DirectionCone& cone) const override;

private:
    // A smooth coat over a mirror: one delta lobe.
    bool mirror_only() const { return m_coat.effectively_smooth() && m_base.effectively_smooth(); }
    RGB mirror_weight(float cos_o) const;
    // The probabilities of sampling the coat's lobe, the conductor's and the trapped light's.
    void lobe_probabilities(float cos_o, float* p_coat, float* p_base, float* p_trap) const;
    // For wo, wi on the +z side.
    float eval_coat(const Vec3& wo, const Vec3& wi) const;
    float pdf_coat(const Vec3& wo, const Vec3& wi) const;
    RGB eval_base(const Vec3& wo, const Vec3& wi) const;
    float pdf_base(const Vec3& wo, const Vec3& wi) const;
    Vec3 coat_inside(const Vec3& w) const;  // w refracted into the coat (pointing up)
    RGB coat_series(const RGB& q) const;    // sum_{k<base_visits} q^k

    TrowbridgeReitz m_coat;
    TrowbridgeReitz m_base;  // the conductor's, widened by the coat's roughness
    float m_eta, m_thickness;
    RGB m_base_eta, m_base_k;
    int m_base_visits;
    float m_base_weight;  // the conductor's reflectance at normal incidence, for lobe selection
    // The light the conductor scatters beyond the coat's critical angle (trapped by total
    // internal reflection) and that leaves after more bounces: see coated_conductor.cpp.
    RGB trapped(float cos_t) const;  // the fraction trapped from inside direction cos_t
    RGB eval_trapped(const Vec3& wo, const Vec3& wi) const;
    CoatedConductorTrap m_trap;

public:
    static CoatedConductorTrap compute_trap(const CoatedConductorLayers& layers);
};

}  // namespace ml
