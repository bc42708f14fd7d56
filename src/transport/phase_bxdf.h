// The Henyey-Greenstein phase function dressed as a Bxdf, so that a scattering point inside a
// medium can stand where a surface's BSDF stands (the many-light integrators' gather points and
// VPLs, manylight/gather.h). Those weigh a direction by the BSDF times the cosine of the other
// direction than the one light arrived along: f(wo, wi) |cos(n, wi)| at a gather point reached
// along wo, f(w, wi) |cos(n, w)| for a VPL's light that arrived along wi and leaves along w.
// This Bxdf's value is the phase function divided by |cos wo| |cos wi|, and its frame's normal
// is the direction light arrived along (phase_bsdf), whose cosine is 1: in both uses the
// product is the phase function. It samples and gives densities exactly as the phase function
// does (from wo along the normal, the sample's f |cos| / pdf is 1), and bounds f |cos| over a
// cone for Lightcuts.
#pragma once

#include "core/scratch.h"
#include "materials/bsdf.h"

namespace ml {

class PhaseBxdf final : public Bxdf {
public:
    explicit PhaseBxdf(float g) : m_g(g) {}
    // Scatters in every direction; counted as diffuse so that it is gathered at, never as a
    // delta lobe, and as both reflection and transmission (both sides of any frame).
    uint8_t flags() const override { return kBxdfDiffuse | kBxdfReflection | kBxdfTransmission; }
    RGB eval(const Vec3& wo, const Vec3& wi, TransportMode mode) const override;
    std::optional<BsdfSample> sample(const Vec3& wo, float uc, const Vec2& u,
                                     TransportMode mode) const override;
    float pdf_solid_angle(const Vec3& wo, const Vec3& wi, TransportMode mode) const override;
    RGB max_value_bound(const Vec3& wo, const DirectionCone& cone) const override;
    // A VPL in a medium keeps the whole phase function (it has no glossy part to drop).
    RGB eval_diffuse(const Vec3& wo, const Vec3& wi, TransportMode mode) const override {
        return eval(wo, wi, mode);
    }
    float g() const { return m_g; }

private:
    float m_g;
};

// The largest value of the Henyey-Greenstein phase function of asymmetry g.
float hg_phase_max(float g);

// The phase function of asymmetry g at a point reached along `arrival` (unit, pointing back
// where the camera path or the light path came from), as a Bsdf whose frame has that direction
// as its normal, its Bxdf in `scratch`. Only valid with one of the two directions the arrival.
Bsdf phase_bsdf(const Vec3& arrival, float g, ScratchBuffer& scratch);

}  // namespace ml
