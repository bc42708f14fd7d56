// What the lights at a point whose intensity varies with direction by an image share
// (goniometric and projection lights): light samples towards the point, I(w) / r^2, which
// emitted_intensity gives.
#pragma once

#include <cmath>

#include "lights/light.h"

namespace ml {

class ImagePointLight : public Light {
public:
    explicit ImagePointLight(const Vec3& p) : m_p(p) {}
    LightType type() const override { return LightType::DeltaPosition; }
    std::optional<LightLiSample> sample_li(const LightSampleContext& ctx,
                                           const Vec2&) const override {
        const Vec3 d = m_p - ctx.p;
        const float d2 = length_squared(d);
        if (!(d2 > 0)) return std::nullopt;
        LightLiSample s;
        s.wi = d / std::sqrt(d2);
        const RGB I = emitted_intensity(-s.wi);
        if (I.is_black()) return std::nullopt;
        s.L = I / d2;
        s.pdf_solid_angle = 1;
        s.p_light = m_p;
        return s;
    }
    float pdf_li(const LightSampleContext&, const Vec3&, const Vec3&, const Vec3&,
                 uint32_t) const override {
        return 0;
    }

protected:
    Vec3 m_p;  // the light's position
};

}  // namespace ml
