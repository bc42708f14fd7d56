// pbrt-v4's PortalImageInfiniteLight: an equal-area environment map seen only through a
// rectangular portal (a window of the scene). The map is resampled once into a rectified image
// over the portal's frame, (u, v) = ((alpha + pi/2) / pi, (beta + pi/2) / pi) with alpha and beta
// the direction's angles about the portal's two edges, so that the directions a point sees
// through the portal are an axis-aligned window of that image. Light samples are drawn in that
// window (WindowedDistribution2D), so every one passes through the portal. Directions behind
// the portal's plane are black, and so is every direction that misses the portal.
#include <algorithm>
#include <array>
#include <cmath>

#include "lights/lights.h"
#include "lights/point_lights.h"
#include "sampling/sampler.h"
#include "sampling/warps.h"
#include "sampling/windowed_distribution.h"

namespace ml {
namespace {

// The equal-area map's bilinear value at uv with pbrt-v4's octahedral wrap: a pixel past an
// edge of the square is its mirror across that edge's midpoint (the sphere continues there).
RGB bilerp_octahedral(const Image& img, Vec2 uv) {
    const int n = img.width;
    auto at = [&](int x, int y) {
        if (x < 0) x = -x - 1, y = n - 1 - y;
        if (x >= n) x = 2 * n - 1 - x, y = n - 1 - y;
        if (y < 0) x = n - 1 - x, y = -y - 1;
        if (y >= n) x = n - 1 - x, y = 2 * n - 1 - y;
        return img.at(std::clamp(x, 0, n - 1), std::clamp(y, 0, n - 1));
    };
    const float x = uv.x * float(n) - 0.5f, y = uv.y * float(n) - 0.5f;
    const int x0 = int(std::floor(x)), y0 = int(std::floor(y));
    const float dx = x - float(x0), dy = y - float(y0);
    return at(x0, y0) * ((1 - dx) * (1 - dy)) + at(x0 + 1, y0) * (dx * (1 - dy)) +
           at(x0, y0 + 1) * ((1 - dx) * dy) + at(x0 + 1, y0 + 1) * (dx * dy);
}

class PortalInfiniteLight final : public Light {
public:
    PortalInfiniteLight(const Image& equal_area, const Transform& light_to_world,
                        const std::array<Vec3, 4>& portal)
        : m_portal(portal) {
        // The portal's frame (pbrt-v4's Frame::FromXY(p03, p01)): x along the edge 0-3, y along
        // 0-1, z = x cross y, the side the light comes from.
        const Vec3 x = normalize(portal[3] - portal[0]), y = normalize(portal[1] - portal[0]);
        m_frame = Frame(x, y, cross(x, y));
        m_area = length(portal[1] - portal[0]) * length(portal[3] - portal[0]);
        // 1. The rectified image, the map's resolution: each pixel the map's bilinear value in
        //    its centre's direction.
        const Transform to_light = light_to_world.inverse();
        const int w = equal_area.width, h = equal_area.height;
        m_image = Image(w, h);
        std::vector<float> f(size_t(w) * h);
        double sum = 0;
        for (int py = 0; py < h; ++py)
            for (int px = 0; px < w; ++px) {
                Vec2 uv((float(px) + 0.5f) / float(w), (float(py) + 0.5f) / float(h));
                float duv_dw;
                Vec3 wl = normalize(to_light.vector(world_from_image(uv, &duv_dw)));
                RGB c = clamp_zero(bilerp_octahedral(equal_area, equal_area_sphere_to_square(wl)));
                m_image.at(px, py) = c;
                // 2. Sampling weights: radiance per unit of (u, v), so that directions go as the
                //    radiance over solid angle; floored where there is radiance.
                float v = duv_dw > 0 ? c.luminance() / duv_dw : 0.f;
                f[size_t(py) * w + px] = v;
                sum += v;
                m_flux_density += c / (duv_dw > 0 ? duv_dw : kInfinity);
            }
        m_flux_density = m_flux_density / float(w * h);
        const float floor = float(sum / double(f.size())) * 1e-3f;
        for (size_t i = 0; i < f.size(); ++i)
            if (!m_image.pixels[i].is_black()) f[i] += floor;
        m_dist = WindowedDistribution2D(f, w, h);
    }
    LightType type() const override { return LightType::Infinite; }
    void preprocess(const Bounds3& b) override { b.bounding_sphere(&m_center, &m_radius); }

    std::optional<LightLiSample> sample_li(const LightSampleContext& ctx,
                                           const Vec2& u) const override {
        auto window = seen_through_portal(ctx.p);
        if (!window) return std::nullopt;
        float map_pdf;
        auto uv = m_dist.sample(u, *window, &map_pdf);
        if (!uv) return std::nullopt;
        float duv_dw;
        LightLiSample s;
        s.wi = world_from_image(*uv, &duv_dw);
        if (!(duv_dw > 0)) return std::nullopt;
        s.pdf_solid_angle = map_pdf / duv_dw;
        s.L = lookup(*uv);
        s.p_light = ctx.p + s.wi * (2 * std::max(m_radius, 1.f) + length(ctx.p - m_center));
        return s;
    }
    float pdf_li(const LightSampleContext& ctx, const Vec3& wi, const Vec3&, const Vec3&,
                 uint32_t) const override {
        float duv_dw;
        auto uv = image_from_world(wi, &duv_dw);
        auto window = seen_through_portal(ctx.p);
        if (!uv || !window || !(duv_dw > 0)) return 0;
        return m_dist.pdf(*uv, *window) / duv_dw;
    }
    RGB radiance_escaped(const Ray& ray) const override {
        auto uv = image_from_world(normalize(ray.d));
        auto window = seen_through_portal(ray.o);
        if (!uv || !window || !window->inside(*uv)) return RGB();
        return lookup(*uv);
    }
    // As pbrt-v4: directions over the whole image (the portal's side), from a disk of the
    // scene's bounding sphere; a closed room around the portal lets in only what passes it.
    std::optional<LightLeSample> sample_le(const Vec2& u_pos, const Vec2& u_dir) const override {
        float map_pdf;
        auto uv = m_dist.sample(u_dir, Window2{{0, 0}, {1, 1}}, &map_pdf);
        if (!uv || m_radius <= 0) return std::nullopt;
        float duv_dw;
        Vec3 wi = world_from_image(*uv, &duv_dw);
        if (!(duv_dw > 0)) return std::nullopt;
        Frame f = Frame::from_z(wi);
        Vec2 d = sample_uniform_disk_concentric(u_pos);
        LightLeSample s;
        s.ray.o = m_center + (wi + f.s * d.x + f.t * d.y) * m_radius;
        s.ray.d = -wi;
        s.pdf_pos = 1 / (kPi * m_radius * m_radius);
        s.pdf_dir = map_pdf / duv_dw;
        s.L = lookup(*uv);
        return s;
    }
    void pdf_le(const Ray& ray, const Vec3&, float* pdf_pos, float* pdf_dir) const override {
        *pdf_pos = m_radius > 0 ? 1 / (kPi * m_radius * m_radius) : 0.f;
        float duv_dw;
        auto uv = image_from_world(-ray.d, &duv_dw);
        *pdf_dir = uv && duv_dw > 0 ? m_dist.pdf(*uv, Window2{{0, 0}, {1, 1}}) / duv_dw : 0.f;
    }
    // pbrt-v4's Phi: the portal's area times the radiance integrated over the directions it
    // lets in.
    RGB power() const override { return m_flux_density * m_area; }
    // n directions drawn from the whole image, each the irradiance L(w) / (pdf(w) n) along -w
    // (directional lights: walls around the portal keep them out where it does not see).
    void to_point_lights(int n, Sampler& sampler, std::vector<PointLight>& out) const override {
        if (n <= 0) return;
        Vec2 shift = sampler.get_2d();
        for (int i = 0; i < n; ++i) {
            float map_pdf, duv_dw;
            auto uv = m_dist.sample(shifted_hammersley(uint32_t(i), uint32_t(n), shift),
                                    Window2{{0, 0}, {1, 1}}, &map_pdf);
            if (!uv) continue;
            Vec3 wi = world_from_image(*uv, &duv_dw);
            if (!(duv_dw > 0)) continue;
            PointLight pl;
            pl.n = -wi;
            pl.intensity = lookup(*uv) / (map_pdf / duv_dw * float(n));
            pl.kind = PointLightKind::Directional;
            out.push_back(pl);
        }
    }

private:
    // The rectified image's (u, v) of world direction w, with d(u, v) / d(omega); none behind
    // the portal's plane.
    std::optional<Vec2> image_from_world(const Vec3& w, float* duv_dw = nullptr) const {
        const Vec3 l = m_frame.to_local(w);
        if (!(l.z > 0)) return std::nullopt;
        if (duv_dw) *duv_dw = kPi * kPi * (1 - l.x * l.x) * (1 - l.y * l.y) / l.z;
        const float alpha = std::atan2(l.x, l.z), beta = std::atan2(l.y, l.z);
        return Vec2(std::clamp((alpha + kPi / 2) / kPi, 0.f, 1.f),
                    std::clamp((beta + kPi / 2) / kPi, 0.f, 1.f));
    }
    Vec3 world_from_image(const Vec2& uv, float* duv_dw) const {
        const float alpha = -kPi / 2 + uv.x * kPi, beta = -kPi / 2 + uv.y * kPi;
        const Vec3 l = normalize(Vec3(std::tan(alpha), std::tan(beta), 1));
        *duv_dw = kPi * kPi * (1 - l.x * l.x) * (1 - l.y * l.y) / l.z;
        return m_frame.to_world(l);
    }
    // The window of the image that p sees through the portal: the image points of two opposite
    // corners (edges parallel to the frame's axes are lines of constant alpha or beta); none
    // from behind the portal.
    std::optional<Window2> seen_through_portal(const Vec3& p) const {
        auto a = image_from_world(normalize(m_portal[0] - p));
        auto b = image_from_world(normalize(m_portal[2] - p));
        if (!a || !b) return std::nullopt;
        return Window2{{std::min(a->x, b->x), std::min(a->y, b->y)},
                       {std::max(a->x, b->x), std::max(a->y, b->y)}};
    }
    RGB lookup(const Vec2& uv) const {
        int x = std::clamp(int(uv.x * float(m_image.width)), 0, m_image.width - 1);
        int y = std::clamp(int(uv.y * float(m_image.height)), 0, m_image.height - 1);
        return m_image.at(x, y);
    }

    std::array<Vec3, 4> m_portal;
    Frame m_frame;
    float m_area = 0;
    Image m_image;       // rectified, scaled, non-negative
    RGB m_flux_density;  // the radiance integrated over the image's directions
    WindowedDistribution2D m_dist;
    Vec3 m_center;
    float m_radius = 0;
};

}  // namespace

std::unique_ptr<Light> make_portal_infinite_light(const Image& image,
                                                  const Transform& light_to_world,
                                                  const std::array<Vec3, 4>& portal) {
    return std::make_unique<PortalInfiniteLight>(image, light_to_world, portal);
}

}  // namespace ml
