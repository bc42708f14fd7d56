// pbrt-v4's "hair" material: the hair scattering model of Chiang et al. 2016 ("A Practical and
// Controllable Hair and Fur Model for Production Path Tracing") as pbrt-v4's HairBxDF has it:
// longitudinal lobes Mp (with the cuticle scales' tilt alpha), attenuations Ap through a
// cylinder of absorption sigma_a, and trimmed-logistic azimuthal lobes Np, for p = R, TT, TRT
// and the remainder. Local frame: x along the hair (dp/du), z the curve's normal; the offset
// across the fibre is h = -1 + 2 v.
#pragma once

#include <array>

#include "materials/bxdfs.h"
#include "materials/materials.h"

namespace ml {

class HairBxdf final : public Bxdf {
public:
    static constexpr int kPMax = 3;
    // h in [-1, 1]; beta_m, beta_n in [0, 1] (the material clamps them to [0.01, 1]); alpha in
    // degrees.
    HairBxdf(float h, float eta, const RGB& sigma_a, float beta_m, float beta_n, float alpha);
    uint8_t flags() const override { return kBxdfGlossyReflection; }
    RGB eval(const Vec3& wo, const Vec3& wi, TransportMode mode) const override;
    std::optional<BsdfSample> sample(const Vec3& wo, float uc, const Vec2& u,
                                     TransportMode mode) const override;
    float pdf_solid_angle(const Vec3& wo, const Vec3& wi, TransportMode mode) const override;
    RGB max_value_bound(const Vec3& wo, const DirectionCone& cone) const override;

    // pbrt-v4's absorption from melanin concentrations, and from a desired diffuse colour.
    static RGB sigma_a_from_concentration(float eumelanin, float pheomelanin);
    static RGB sigma_a_from_reflectance(const RGB& c, float beta_n);

private:
    // sin and cos of theta_o tilted by the scales for lobe p.
    void tilted(int p, float sin_o, float cos_o, float* sin_p, float* cos_p) const;
    // The attenuations A_p at theta_o (cos_o) given the transmittance T of one pass.
    std::array<RGB, kPMax + 1> attenuation(float cos_o, const RGB& t) const;
    // The transmittance of one pass and gamma_t for wo with sin theta_o = sin_o.
    void refraction(float sin_o, RGB* t, float* gamma_t) const;
    // Lobe selection probabilities at cos theta_o.
    std::array<float, kPMax + 1> lobe_pdf(float cos_o) const;
    // Sum over the lobes of Mp * w_p * Np for wo, wi (w: the Ap, or their pdf), no 1/|cos|.
    float pdf_sum(const Vec3& wo, const Vec3& wi, const std::array<float, kPMax + 1>& w) const;

    float m_h, m_gamma_o, m_eta;
    RGB m_sigma_a;
    float m_v[kPMax + 1];
    float m_s;
    float m_sin2k_alpha[kPMax], m_cos2k_alpha[kPMax];
};

class HairMaterial final : public Material {
public:
    // sigma_a, reflectance, eumelanin, pheomelanin: whichever pbrt-v4's precedence picks (the
    // others empty); with none, the default brown (eumelanin 1.3).
    enum class Source { sigma_a, reflectance, melanin };
    HairMaterial(Source source, RGBParam colour, FloatParam eumelanin, FloatParam pheomelanin,
                 FloatParam eta, FloatParam beta_m, FloatParam beta_n, FloatParam alpha)
        : m_source(source),
          m_colour(std::move(colour)),
          m_eumelanin(std::move(eumelanin)),
          m_pheomelanin(std::move(pheomelanin)),
          m_eta(std::move(eta)),
          m_beta_m(std::move(beta_m)),
          m_beta_n(std::move(beta_n)),
          m_alpha(std::move(alpha)) {}
    Bsdf get_bsdf(const SurfaceInteraction& si, ScratchBuffer& scratch) const override;
    std::string type() const override { return "hair"; }

private:
    Source m_source;
    RGBParam m_colour;  // sigma_a or the reflectance, per m_source
    FloatParam m_eumelanin, m_pheomelanin, m_eta, m_beta_m, m_beta_n, m_alpha;
};

}  // namespace ml
