// Environment lights: constant radiance, or an image in the equal-area octahedral (square) or
// latitude-longitude (2:1) parameterisation, importance-sampled by a Distribution2D over the
// pixels. Lookups are nearest-pixel (as pbrt-v4), so the sampling density is exactly
// proportional to the sampled function within each pixel.
#include "lights/lights.h"
#include "lights/point_lights.h"
#include "sampling/distributions.h"
#include "sampling/sampler.h"
#include "sampling/warps.h"

namespace ml {
namespace {

// Ray origins for light paths: a disk of the scene's bounding sphere facing -wi.
LightLeSample disk_ray(const Vec3& center, float radius, const Vec3& wi, const Vec2& u_pos) {
    Frame f = Frame::from_z(wi);
    Vec2 d = sample_uniform_disk_concentric(u_pos);
    LightLeSample s;
    s.ray.o = center + (wi + f.s * d.x + f.t * d.y) * radius;
    s.ray.d = -wi;
    s.pdf_pos = 1 / (kPi * radius * radius);
    return s;
}

float far_distance(const Vec3& p, const Vec3& center, float radius) {
    return 2 * std::max(radius, 1.f) + length(p - center);
}

class UniformInfiniteLight final : public Light {
public:
    explicit UniformInfiniteLight(const RGB& L) : m_L(L) {}
    LightType type() const override { return LightType::Infinite; }
    void preprocess(const Bounds3& b) override { b.bounding_sphere(&m_center, &m_radius); }
    bool emission_sphere(Vec3* center, float* radius) const override {
        *center = m_center, *radius = m_radius;
        return m_radius > 0;
    }

    // With MIS against the BSDF allowed to leave directions out (allow_incomplete_pdf), a
    // constant radiance is left to BSDF sampling entirely, as pbrt-v4 does: it fits the BSDF
    // at least as well as uniform directions do.
    std::optional<LightLiSample> sample_li(const LightSampleContext& ctx,
                                           const Vec2& u) const override {
        if (ctx.allow_incomplete_pdf) return std::nullopt;
        LightLiSample s;
        s.wi = sample_uniform_sphere(u);
        s.L = m_L;
        s.pdf_solid_angle = pdf_uniform_sphere();
        s.p_light = ctx.p + s.wi * far_distance(ctx.p, m_center, m_radius);
        return s;
    }
    float pdf_li(const LightSampleContext& ctx, const Vec3&, const Vec3&, const Vec3&,
                 uint32_t) const override {
        return ctx.allow_incomplete_pdf ? 0.f : pdf_uniform_sphere();
    }
    RGB radiance_escaped(const Ray&) const override { return m_L; }
    std::optional<LightLeSample> sample_le(const Vec2& u_pos, const Vec2& u_dir) const override {
        if (m_radius <= 0) return std::nullopt;
        LightLeSample s = disk_ray(m_center, m_radius, sample_uniform_sphere(u_dir), u_pos);
        s.L = m_L;
        s.pdf_dir = pdf_uniform_sphere();
        return s;
    }
    void pdf_le(const Ray&, const Vec3&, float* pdf_pos, float* pdf_dir) const override {
        *pdf_pos = m_radius > 0 ? 1 / (kPi * m_radius * m_radius) : 0.f;
        *pdf_dir = pdf_uniform_sphere();
    }
    RGB power() const override { return m_L * (4 * kPi * kPi * m_radius * m_radius); }
    // n stratified directions over the sphere, each the irradiance L * 4 pi / n.
    void to_point_lights(int n, Sampler& sampler, std::vector<PointLight>& out) const override {
        if (n <= 0) return;
        Vec2 shift = sampler.get_2d();
        for (int i = 0; i < n; ++i) {
            PointLight pl;
            pl.n = -sample_uniform_sphere(shifted_hammersley(uint32_t(i), uint32_t(n), shift));
            pl.intensity = m_L * (4 * kPi / float(n));
            pl.kind = PointLightKind::Directional;
            out.push_back(pl);
        }
    }

private:
    RGB m_L;
    Vec3 m_center;
    float m_radius = 0;
};

// Solid angle of pixel row y of a lat-long map, per pixel.
float latlong_pixel_solid_angle(int y, int w, int h) {
    float t0 = kPi * float(y) / float(h), t1 = kPi * float(y + 1) / float(h);
    return (2 * kPi / float(w)) * (std::cos(t0) - std::cos(t1));
}

class ImageInfiniteLight final : public Light {
public:
    ImageInfiniteLight(Image image, EnvMapping mapping, const Transform& light_to_world,
                       float scale)
        : m_image(std::move(image)),
          m_mapping(mapping),
          m_to_world(light_to_world),
          m_to_light(light_to_world.inverse()) {
        int w = m_image.width, h = m_image.height;
        for (RGB& c : m_image.pixels) c = clamp_zero(c * scale);
        // Sampling weights: luminance, times sin(theta) for lat-long (its pixels shrink towards
        // the poles), plus a floor so that no pixel with radiance has zero density.
        std::vector<float> f(size_t(w) * h);
        double sum = 0;
        for (int y = 0; y < h; ++y) {
            float row = m_mapping == EnvMapping::LatLong
                            ? std::sin(kPi * (float(y) + 0.5f) / float(h))
                            : 1.f;
            for (int x = 0; x < w; ++x) {
                float v = m_image.at(x, y).luminance() * row;
                f[size_t(y) * w + x] = v;
                sum += v;
            }
        }
        // The compensated density (pbrt-v4's, for MIS with BSDF sampling): radiance above the
        // map's mean over the sphere, so that light samples go where the map stands out and
        // BSDF samples take the even rest. A map with nothing above its mean (a constant one)
        // keeps the complete density.
        double mean_sum = 0, solid_angle = 0;
        for (int y = 0; y < h; ++y) {
            double dw = m_mapping == EnvMapping::EqualArea
                            ? 1.0
                            : double(latlong_pixel_solid_angle(y, w, h));
            for (int x = 0; x < w; ++x) mean_sum += double(m_image.at(x, y).luminance()) * dw;
            solid_angle += dw * double(w);
        }
        float mean = float(mean_sum / solid_angle);
        std::vector<float> fc(f.size());
        bool any = false;
        for (int y = 0; y < h; ++y) {
            float row = m_mapping == EnvMapping::LatLong
                            ? std::sin(kPi * (float(y) + 0.5f) / float(h))
                            : 1.f;
            for (int x = 0; x < w; ++x) {
                float v = std::max(0.f, m_image.at(x, y).luminance() - mean) * row;
                fc[size_t(y) * w + x] = v;
                any = any || v > 0;
            }
        }
        float floor = float(sum / double(f.size())) * 1e-3f;
        for (float& v : f) v += floor;
        m_dist = Distribution2D(f, w, h);
        m_compensated = any ? Distribution2D(fc, w, h) : m_dist;
    }
    LightType type() const override { return LightType::Infinite; }
    void preprocess(const Bounds3& b) override { b.bounding_sphere(&m_center, &m_radius); }
    bool emission_sphere(Vec3* center, float* radius) const override {
        *center = m_center, *radius = m_radius;
        return m_radius > 0;
    }

    std::optional<LightLiSample> sample_li(const LightSampleContext& ctx,
                                           const Vec2& u) const override {
        Vec3 wi;
        float pdf;
        Vec2 uv;
        if (!sample_direction(distribution(ctx), u, &wi, &pdf, &uv)) return std::nullopt;
        LightLiSample s;
        s.wi = wi;
        s.L = lookup(uv);
        s.pdf_solid_angle = pdf;
        s.p_light = ctx.p + wi * far_distance(ctx.p, m_center, m_radius);
        return s;
    }
    float pdf_li(const LightSampleContext& ctx, const Vec3& wi, const Vec3&, const Vec3&,
                 uint32_t) const override {
        return pdf_direction(distribution(ctx), wi);
    }
    RGB radiance_escaped(const Ray& ray) const override {
        return lookup(to_uv(normalize(m_to_light.vector(ray.d))));
    }
    std::optional<LightLeSample> sample_le(const Vec2& u_pos, const Vec2& u_dir) const override {
        Vec3 wi;
        float pdf;
        Vec2 uv;
        if (m_radius <= 0 || !sample_direction(m_dist, u_dir, &wi, &pdf, &uv)) return std::nullopt;
        LightLeSample s = disk_ray(m_center, m_radius, wi, u_pos);
        s.L = lookup(uv);
        s.pdf_dir = pdf;
        return s;
    }
    void pdf_le(const Ray& ray, const Vec3&, float* pdf_pos, float* pdf_dir) const override {
        *pdf_pos = m_radius > 0 ? 1 / (kPi * m_radius * m_radius) : 0.f;
        *pdf_dir = pdf_direction(m_dist, -ray.d);
    }
    RGB power() const override {
        // pi r^2 times the radiance integrated over all directions.
        RGB sum;
        int w = m_image.width, h = m_image.height;
        for (int y = 0; y < h; ++y) {
            float dw = m_mapping == EnvMapping::EqualArea ? 4 * kPi / float(w * h)
                                                          : latlong_pixel_solid_angle(y, w, h);
            RGB row;
            for (int x = 0; x < w; ++x) row += m_image.at(x, y);
            sum += row * dw;
        }
        return sum * (kPi * m_radius * m_radius);
    }
    // n directions importance-sampled from the map (stratified in its unit square), each the
    // irradiance L(w) / (pdf(w) n) travelling along -w.
    void to_point_lights(int n, Sampler& sampler, std::vector<PointLight>& out) const override {
        if (n <= 0) return;
        Vec2 shift = sampler.get_2d();
        for (int i = 0; i < n; ++i) {
            Vec3 wi;
            float pdf;
            Vec2 uv;
            if (!sample_direction(m_dist, shifted_hammersley(uint32_t(i), uint32_t(n), shift), &wi,
                                  &pdf, &uv))
                continue;
            PointLight pl;
            pl.n = -wi;
            pl.intensity = lookup(uv) / (pdf * float(n));
            pl.kind = PointLightKind::Directional;
            out.push_back(pl);
        }
    }

private:
    Vec2 to_uv(const Vec3& w_light) const {
        if (m_mapping == EnvMapping::EqualArea) return equal_area_sphere_to_square(w_light);
        return {spherical_phi(w_light) * kInv2Pi, spherical_theta(w_light) * kInvPi};
    }
    Vec3 from_uv(Vec2 uv, float* sin_theta) const {
        if (m_mapping == EnvMapping::EqualArea) {
            *sin_theta = 1;
            return equal_area_square_to_sphere(uv);
        }
        float theta = uv.y * kPi, phi = uv.x * 2 * kPi;
        *sin_theta = std::sin(theta);
        return spherical_direction(*sin_theta, std::cos(theta), phi);
    }
    // Density over [0,1]^2 turned into solid angle by the mapping's Jacobian.
    float jacobian_inv(float sin_theta) const {
        return m_mapping == EnvMapping::EqualArea ? kInv4Pi : 1 / (2 * kPi * kPi * sin_theta);
    }
    const Distribution2D& distribution(const LightSampleContext& ctx) const {
        return ctx.allow_incomplete_pdf ? m_compensated : m_dist;
    }
    bool sample_direction(const Distribution2D& dist, Vec2 u, Vec3* wi, float* pdf,
                          Vec2* uv) const {
        float map_pdf;
        *uv = dist.sample(u, &map_pdf);
        if (map_pdf == 0) return false;
        float sin_theta;
        Vec3 w_light = from_uv(*uv, &sin_theta);
        if (sin_theta <= 0) return false;
        *wi = normalize(m_to_world.vector(w_light));
        *pdf = map_pdf * jacobian_inv(sin_theta);
        return true;
    }
    float pdf_direction(const Distribution2D& dist, const Vec3& wi) const {
        Vec3 w_light = normalize(m_to_light.vector(wi));
        float sin_theta =
            m_mapping == EnvMapping::EqualArea ? 1.f : safe_sqrt(1 - w_light.z * w_light.z);
        if (sin_theta <= 0) return 0;
        return dist.pdf(to_uv(w_light)) * jacobian_inv(sin_theta);
    }
    RGB lookup(Vec2 uv) const {
        int x = std::clamp(int(uv.x * float(m_image.width)), 0, m_image.width - 1);
        int y = std::clamp(int(uv.y * float(m_image.height)), 0, m_image.height - 1);
        return m_image.at(x, y);
    }

    Image m_image;
    EnvMapping m_mapping;
    Transform m_to_world, m_to_light;
    Distribution2D m_dist;         // luminance (times sin theta for lat-long), floored
    Distribution2D m_compensated;  // the part above the mean: allow_incomplete_pdf
    Vec3 m_center;
    float m_radius = 0;
};

}  // namespace

std::unique_ptr<Light> make_uniform_infinite_light(const RGB& L) {
    return std::make_unique<UniformInfiniteLight>(L);
}

std::unique_ptr<Light> make_image_infinite_light(Image image, EnvMapping mapping,
                                                 const Transform& light_to_world, float scale) {
    return std::make_unique<ImageInfiniteLight>(std::move(image), mapping, light_to_world, scale);
}

float image_upper_hemisphere_illuminance(const Image& image, EnvMapping mapping) {
    int w = image.width, h = image.height;
    double e = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            Vec2 uv((float(x) + 0.5f) / float(w), (float(y) + 0.5f) / float(h));
            Vec3 d;
            float dw;
            if (mapping == EnvMapping::EqualArea) {
                d = equal_area_square_to_sphere(uv);
                dw = 4 * kPi / float(w * h);
            } else {
                float theta = uv.y * kPi;
                d = spherical_direction(std::sin(theta), std::cos(theta), uv.x * 2 * kPi);
                dw = latlong_pixel_solid_angle(y, w, h);
            }
            if (d.z > 0) e += double(image.at(x, y).luminance() * d.z * dw);
        }
    return float(e);
}

}  // namespace ml
