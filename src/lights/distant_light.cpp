// Directional (distant) lights; light paths start on a disk the size of the scene's bounding
// sphere, facing the light.
#include "lights/lights.h"
#include "lights/point_lights.h"
#include "sampling/sampler.h"
#include "sampling/warps.h"

namespace ml {
namespace {

class DistantLight final : public Light {
public:
    DistantLight(const Vec3& w, const RGB& L) : m_w(normalize(w)), m_L(L) {}
    LightType type() const override { return LightType::DeltaDirection; }
    void preprocess(const Bounds3& b) override { b.bounding_sphere(&m_center, &m_radius); }
    bool emission_sphere(Vec3* center, float* radius) const override {
        *center = m_center, *radius = m_radius;
        return m_radius > 0;
    }

    std::optional<LightLiSample> sample_li(const LightSampleContext& ctx,
                                           const Vec2& u) const override {
        LightLiSample s;
        s.wi = m_w;
        s.L = m_L;
        s.pdf_solid_angle = 1;
        // Past the scene from anywhere inside it.
        s.p_light = ctx.p + m_w * (2 * std::max(m_radius, 1.f) + length(ctx.p - m_center));
        return s;
    }
    float pdf_li(const LightSampleContext&, const Vec3&, const Vec3&, const Vec3&,
                 uint32_t) const override {
        return 0;
    }
    std::optional<LightLeSample> sample_le(const Vec2& u_pos, const Vec2& u_dir) const override {
        if (m_radius <= 0) return std::nullopt;
        Frame f = Frame::from_z(m_w);
        Vec2 d = sample_uniform_disk_concentric(u_pos);
        LightLeSample s;
        s.ray.o = m_center + (m_w + f.s * d.x + f.t * d.y) * m_radius;
        s.ray.d = -m_w;
        s.L = m_L;
        s.pdf_pos = 1 / (kPi * m_radius * m_radius);
        s.pdf_dir = 1;
        return s;
    }
    void pdf_le(const Ray&, const Vec3&, float* pdf_pos, float* pdf_dir) const override {
        *pdf_pos = m_radius > 0 ? 1 / (kPi * m_radius * m_radius) : 0.f;
        *pdf_dir = 0;
    }
    RGB power() const override { return m_L * (kPi * m_radius * m_radius); }
    // m_L is already the irradiance at normal incidence (a delta direction).
    void to_point_lights(int, Sampler&, std::vector<PointLight>& out) const override {
        PointLight pl;
        pl.n = -m_w;
        pl.intensity = m_L;
        pl.kind = PointLightKind::Directional;
        out.push_back(pl);
    }

private:
    Vec3 m_w;
    RGB m_L;
    Vec3 m_center;
    float m_radius = 0;
};

}  // namespace

std::unique_ptr<Light> make_distant_light(const Vec3& w, const RGB& L) {
    return std::make_unique<DistantLight>(w, L);
}

}  // namespace ml
