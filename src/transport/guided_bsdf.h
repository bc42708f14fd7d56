// A BSDF mixed with a path guide's directional distribution (one-sample MIS): a direction is
// drawn from the BSDF with probability bsdf_share, else from the guide, and its density is the
// mixture's, bsdf_share * p_bsdf + (1 - bsdf_share) * p_guide, wherever the path tracer uses a
// direction's density (the throughput, MIS against light samples). Without a guide it is the
// BSDF itself. Only for BSDFs without delta lobes (a guide cannot sample a delta lobe).
#pragma once

#include <optional>

#include "materials/bsdf.h"
#include "transport/sd_tree.h"

namespace ml {

class GuidedBsdf {
public:
    GuidedBsdf(const Bsdf& bsdf, const DirectionTree* guide, float bsdf_share)
        : m_bsdf(bsdf), m_guide(guide), m_bsdf_share(guide ? bsdf_share : 1.f) {}
    bool guided() const { return m_guide != nullptr; }
    // uc picks the BSDF or the guide (and, rescaled, the BSDF's lobe); u places the direction.
    std::optional<BsdfSample> sample(const Vec3& wo, float uc, const Vec2& u) const;
    float pdf_solid_angle(const Vec3& wo, const Vec3& wi) const;

private:
    float mixture(float bsdf_pdf, const Vec3& wi) const;
    const Bsdf& m_bsdf;
    const DirectionTree* m_guide;
    float m_bsdf_share;
};

}  // namespace ml
