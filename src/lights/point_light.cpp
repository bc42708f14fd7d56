// Isotropic point lights.
#include "lights/lights.h"
#include "lights/point_lights.h"
#include "sampling/sampler.h"
#include "sampling/warps.h"

namespace ml {
namespace {

class PointLight final : public Light {
public:
    PointLight(const Vec3& p, const RGB& I) : m_p(p), m_I(I) {}
    LightType type() const override { return LightType::DeltaPosition; }

    std::optional<LightLiSample> sample_li(const LightSampleContext& ctx,
                                           const Vec2& u) const override {
        Vec3 d = m_p - ctx.p;
        float d2 = length_squared(d);
        if (d2 == 0) return std::nullopt;
        LightLiSample s;
        s.wi = d / std::sqrt(d2);
        s.L = m_I / d2;
        s.pdf_solid_angle = 1;
        s.p_light = m_p;
        return s;
    }
    float pdf_li(const LightSampleContext&, const Vec3&, const Vec3&, const Vec3&,
                 uint32_t) const override {
        return 0;
    }
    std::optional<LightLeSample> sample_le(const Vec2& u_pos, const Vec2& u_dir) const override {
        LightLeSample s;
        s.ray.o = m_p;
        s.ray.d = sample_uniform_sphere(u_dir);
        s.L = m_I;
        s.pdf_pos = 1;
        s.pdf_dir = pdf_uniform_sphere();
        return s;
    }
    void pdf_le(const Ray&, const Vec3&, float* pdf_pos, float* pdf_dir) const override {
        *pdf_pos = 0;  // a delta position: no other path strategy can find this origin
        *pdf_dir = pdf_uniform_sphere();
    }
    RGB power() const override { return m_I * (4 * kPi); }
    std::optional<LightBounds> bounds() const override {
        LightBounds b;
        b.box.expand(m_p);
        b.phi = std::max(0.f, m_I.luminance());
        b.cos_theta_o = -1;  // every direction
        b.cos_theta_e = 0;
        return b;
    }
    void to_point_lights(int, Sampler&, std::vector<ml::PointLight>& out) const override {
        ml::PointLight pl;
        pl.p = m_p;
        pl.intensity = m_I;
        pl.kind = PointLightKind::Omni;
        out.push_back(pl);
    }

private:
    Vec3 m_p;
    RGB m_I;
};

// ml::PointLight (the Lightcuts point light) is also visible outside this namespace.
using IsotropicPointLight = PointLight;

}  // namespace

std::unique_ptr<Light> make_point_light(const Vec3& p, const RGB& I) {
    return std::make_unique<IsotropicPointLight>(p, I);
}

}  // namespace ml
