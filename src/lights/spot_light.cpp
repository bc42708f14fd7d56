// Spot lights with pbrt-v4's smoothstep falloff between the inner and outer cone.
#include "lights/lights.h"
#include "lights/point_lights.h"
#include "sampling/sampler.h"
#include "sampling/warps.h"

namespace ml {
namespace {

float smooth_step(float a, float b, float x) {
    if (a == b) return x < a ? 0.f : 1.f;
    float t = std::clamp((x - a) / (b - a), 0.f, 1.f);
    return t * t * (3 - 2 * t);
}

class SpotLight final : public Light {
public:
    SpotLight(const Vec3& p, const Vec3& axis, const RGB& I, float cos_start, float cos_end)
        : m_p(p),
          m_frame(Frame::from_z(axis)),
          m_I(I),
          m_cos_start(cos_start),
          m_cos_end(cos_end) {}
    LightType type() const override { return LightType::DeltaPosition; }

    std::optional<LightLiSample> sample_li(const LightSampleContext& ctx,
                                           const Vec2& u) const override {
        Vec3 d = m_p - ctx.p;
        float d2 = length_squared(d);
        if (d2 == 0) return std::nullopt;
        Vec3 wi = d / std::sqrt(d2);
        RGB I = intensity(-wi);
        if (I.is_black()) return std::nullopt;
        LightLiSample s;
        s.wi = wi;
        s.L = I / d2;
        s.pdf_solid_angle = 1;
        s.p_light = m_p;
        return s;
    }
    float pdf_li(const LightSampleContext&, const Vec3&, const Vec3&, const Vec3&,
                 uint32_t) const override {
        return 0;
    }
    std::optional<LightLeSample> sample_le(const Vec2& u_pos, const Vec2& u_dir) const override {
        Vec3 w = m_frame.to_world(sample_uniform_cone(u_dir, m_cos_end));
        LightLeSample s;
        s.ray.o = m_p;
        s.ray.d = w;
        s.L = intensity(w);
        s.pdf_pos = 1;
        s.pdf_dir = pdf_uniform_cone(m_cos_end);
        return s;
    }
    void pdf_le(const Ray& ray, const Vec3&, float* pdf_pos, float* pdf_dir) const override {
        *pdf_pos = 0;
        *pdf_dir = dot(m_frame.n, ray.d) >= m_cos_end ? pdf_uniform_cone(m_cos_end) : 0.f;
    }
    // The smoothstep integrates to exactly half the falloff band in cos theta.
    RGB power() const override { return m_I * (2 * kPi * (1 - 0.5f * (m_cos_start + m_cos_end))); }
    // Full intensity within theta_start of the axis, fading out by theta_end (pbrt-v4's bounds).
    std::optional<LightBounds> bounds() const override {
        LightBounds b;
        b.box.expand(m_p);
        b.w = m_frame.n;
        b.phi = std::max(0.f, m_I.luminance());
        b.cos_theta_o = m_cos_start;
        b.cos_theta_e = std::cos(std::max(0.f, safe_acos(m_cos_end) - safe_acos(m_cos_start)));
        return b;
    }
    // An omni light with the same cone and smoothstep falloff (point_light_intensity).
    void to_point_lights(int, Sampler&, std::vector<PointLight>& out) const override {
        PointLight pl;
        pl.p = m_p;
        pl.n = m_frame.n;
        pl.intensity = m_I;
        pl.kind = PointLightKind::Omni;
        pl.cos_start = m_cos_start;
        pl.cos_end = m_cos_end;
        out.push_back(pl);
    }

private:
    // Intensity leaving towards unit w.
    RGB intensity(const Vec3& w) const {
        return m_I * smooth_step(m_cos_end, m_cos_start, dot(m_frame.n, w));
    }

    Vec3 m_p;
    Frame m_frame;
    RGB m_I;
    float m_cos_start, m_cos_end;
};

}  // namespace

std::unique_ptr<Light> make_spot_light(const Vec3& p, const Vec3& axis, const RGB& I,
                                       float cos_start, float cos_end) {
    return std::make_unique<SpotLight>(p, normalize(axis), I, cos_start, cos_end);
}

}  // namespace ml
