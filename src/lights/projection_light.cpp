// Projection lights (pbrt-v4): a point light that projects an RGB image like a slide projector.
// Light space looks down +z with y flipped (pbrt-v4's flip: the image's top row is light +y);
// a direction w with w.z > 1e-3 meets the screen plane z = 1 at (w.x, w.y) / w.z, scaled by
// 1 / tan(fov / 2) into screen coordinates, whose window is [-a, a] x [-1, 1] for an image of
// aspect a >= 1 ([-1, 1] x [-1/a, 1/a] otherwise: fov spans the shorter side). The intensity is
// scale times the nearest pixel. Paths leave by the pixels' average value times the solid angle
// they cover, cos^3 at their centre per unit screen area, uniformly within a pixel.
#include "lights/image_point_light.h"
#include "lights/lights.h"
#include "lights/point_lights.h"
#include "sampling/distributions.h"

namespace ml {
namespace {

constexpr float kHither = 1e-3f;

class ProjectionLight final : public ImagePointLight {
public:
    ProjectionLight(const Transform& light_to_world, Image image, float fov_degrees)
        : ImagePointLight(light_to_world.point(Vec3(0, 0, 0))),
          m_to_world(light_to_world * Transform::scale(Vec3(1, -1, 1))),
          m_to_light(m_to_world.inverse()),
          m_image(std::move(image)) {
        int w = m_image.width, h = m_image.height;
        float aspect = float(w) / float(h);
        m_lo = aspect > 1 ? Vec2(-aspect, -1) : Vec2(-1, -1 / aspect);
        m_hi = Vec2(-m_lo.x, -m_lo.y);
        m_tan = std::tan(radians(fov_degrees) / 2);
        m_screen_area = (m_hi.x - m_lo.x) * (m_hi.y - m_lo.y);
        std::vector<float> f(size_t(w) * size_t(h));
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                RGB c = m_image.at(x, y);
                Vec3 d = direction({(float(x) + 0.5f) / float(w), (float(y) + 0.5f) / float(h)});
                float cos3 = d.z * d.z * d.z;
                f[size_t(y) * size_t(w) + size_t(x)] = (c.r + c.g + c.b) / 3 * cos3;
                m_power += c * cos3;
                for (int k = 0; k < 3; ++k) m_max[k] = std::max(m_max[k], c[k]);
            }
        // Solid angle per pixel at its centre: (screen area tan^2 / pixels) cos^3.
        m_power = m_power * (m_screen_area * m_tan * m_tan / float(w * h));
        m_dist = Distribution2D(f, w, h);
        m_any = m_dist.integral() > 0;
        Vec3 corner = normalize(Vec3(m_hi.x * m_tan, m_hi.y * m_tan, 1));
        m_cos_corner = corner.z;
        m_axis = normalize(m_to_world.vector(Vec3(0, 0, 1)));
    }
    RGB emitted_intensity(const Vec3& w) const override {
        Vec2 uv;
        if (!to_uv(normalize(m_to_light.vector(w)), &uv)) return RGB();
        return lookup(uv);
    }
    std::optional<LightLeSample> sample_le(const Vec2& u_pos, const Vec2& u_dir) const override {
        if (!m_any) return std::nullopt;
        float pdf_uv;
        Vec2 uv = m_dist.sample(u_dir, &pdf_uv);
        if (!(pdf_uv > 0)) return std::nullopt;
        Vec3 w = direction(uv);
        LightLeSample s;
        s.ray.o = m_p;
        s.ray.d = normalize(m_to_world.vector(w));
        s.L = lookup(uv);
        s.pdf_pos = 1;
        s.pdf_dir = pdf_solid_angle(pdf_uv, w.z);
        return s;
    }
    void pdf_le(const Ray& ray, const Vec3&, float* pdf_pos, float* pdf_dir) const override {
        *pdf_pos = 0;
        *pdf_dir = 0;
        Vec3 w = normalize(m_to_light.vector(ray.d));
        Vec2 uv;
        if (m_any && to_uv(w, &uv)) *pdf_dir = pdf_solid_angle(m_dist.pdf(uv), w.z);
    }
    RGB power() const override { return m_power; }
    // Within the cone through the screen's corners, of the largest pixel's intensity.
    std::optional<LightBounds> bounds() const override {
        LightBounds b;
        b.box.expand(m_p);
        b.w = m_axis;
        b.phi = std::max(0.f, m_max.luminance());
        b.cos_theta_o = 1;
        b.cos_theta_e = m_cos_corner;
        return b;
    }
    // An omni light within the corners' cone, bounded by the largest pixel, evaluated through
    // emitted_intensity.
    void to_point_lights(int, Sampler&, std::vector<PointLight>& out) const override {
        PointLight pl;
        pl.p = m_p;
        pl.n = m_axis;
        pl.intensity = m_max;
        pl.kind = PointLightKind::Omni;
        pl.cos_start = pl.cos_end = m_cos_corner;
        pl.emitter = this;
        out.push_back(pl);
    }

private:
    // Light-space unit direction w to image coordinates (top row at v = 0); false outside.
    bool to_uv(const Vec3& w, Vec2* uv) const {
        if (!(w.z >= kHither)) return false;
        float sx = w.x / (w.z * m_tan), sy = w.y / (w.z * m_tan);
        if (!(sx >= m_lo.x && sx <= m_hi.x && sy >= m_lo.y && sy <= m_hi.y)) return false;
        *uv = Vec2((sx - m_lo.x) / (m_hi.x - m_lo.x), (sy - m_lo.y) / (m_hi.y - m_lo.y));
        return true;
    }
    // The unit light-space direction through image point uv.
    Vec3 direction(Vec2 uv) const {
        float sx = m_lo.x + uv.x * (m_hi.x - m_lo.x), sy = m_lo.y + uv.y * (m_hi.y - m_lo.y);
        return normalize(Vec3(sx * m_tan, sy * m_tan, 1));
    }
    // Density over [0,1]^2 to solid angle: the plane z = 1 covers tan^2 times the screen's
    // area, and d(omega) = cos^3 dA there.
    float pdf_solid_angle(float pdf_uv, float cos_theta) const {
        return pdf_uv / (m_screen_area * m_tan * m_tan * cos_theta * cos_theta * cos_theta);
    }
    RGB lookup(Vec2 uv) const {
        int x = std::clamp(int(uv.x * float(m_image.width)), 0, m_image.width - 1);
        int y = std::clamp(int(uv.y * float(m_image.height)), 0, m_image.height - 1);
        return m_image.at(x, y);
    }

    Transform m_to_world, m_to_light;  // light space with y flipped
    Image m_image;                     // linear, scaled, non-negative
    Vec2 m_lo, m_hi;                   // the screen window
    float m_tan = 1, m_screen_area = 4, m_cos_corner = 0;
    Vec3 m_axis;
    RGB m_power, m_max;
    Distribution2D m_dist;
    bool m_any = false;
};

}  // namespace

std::unique_ptr<Light> make_projection_light(const Transform& light_to_world, Image image,
                                             float fov_degrees) {
    return std::make_unique<ProjectionLight>(light_to_world, std::move(image), fov_degrees);
}

}  // namespace ml
