#include "transport/phase_bxdf.h"

#include <algorithm>
#include <cmath>

#include "core/cone.h"
#include "materials/bxdfs.h"
#include "media/medium.h"

namespace ml {

namespace {

// |cos| below which the value's division stops: the product f |cos| is then below the phase
// function only on directions of solid angle about 4 pi 1e-30, which no sample draws.
constexpr float kMinCos = 1e-30f;

// The phase function at cos(angle from the forward direction -wo) = mu.
float hg_at(float mu, float g) {
    const float denom = std::max(1 + g * g - 2 * g * mu, 1e-12f);
    return kInv4Pi * (1 - g * g) / (denom * std::sqrt(denom));
}

}  // namespace

float hg_phase_max(float g) { return hg_at(g >= 0 ? 1.f : -1.f, g); }

RGB PhaseBxdf::eval(const Vec3& wo, const Vec3& wi, TransportMode) const {
    return RGB(hg_phase(wo, wi, m_g) /
               (std::max(std::abs(wo.z), kMinCos) * std::max(std::abs(wi.z), kMinCos)));
}

std::optional<BsdfSample> PhaseBxdf::sample(const Vec3& wo, float, const Vec2& u,
                                            TransportMode mode) const {
    BsdfSample s;
    s.wi = sample_hg_phase(wo, m_g, u);
    s.pdf_solid_angle = hg_phase(wo, s.wi, m_g);
    s.f = eval(wo, s.wi, mode);
    s.flags = s.wi.z * wo.z > 0 ? kBxdfDiffuseReflection : kBxdfDiffuseTransmission;
    return s;
}

float PhaseBxdf::pdf_solid_angle(const Vec3& wo, const Vec3& wi, TransportMode) const {
    return hg_phase(wo, wi, m_g);
}

RGB PhaseBxdf::max_value_bound(const Vec3& wo, const DirectionCone& cone) const {
    // f |cos wi| is the phase function over |cos wo| (1 where wo is the frame's normal).
    const float over = 1 / std::max(std::abs(wo.z), kMinCos);
    if (cone.is_empty()) return RGB();
    if (cone.is_entire_sphere()) return RGB(hg_phase_max(m_g) * over);
    // The phase function rises towards the forward direction -wo when g > 0 and away from it
    // when g < 0: the cone's direction nearest to (farthest from) it bounds it.
    const float to_axis = angle_between(cone.axis, -wo), half = cone_angle(cone);
    const float angle = m_g >= 0 ? std::max(0.f, to_axis - half) : std::min(kPi, to_axis + half);
    return RGB(hg_at(std::cos(angle), m_g) * over);
}

Bsdf phase_bsdf(const Vec3& arrival, float g, ScratchBuffer& scratch) {
    return Bsdf(Frame::from_z(arrival), arrival, scratch_new<PhaseBxdf>(scratch, g));
}

}  // namespace ml
