// Goniometric lights (pbrt-v4): a point light whose intensity is I times a grey equal-area
// octahedral image of directions, read at the nearest pixel. pbrt-v4 reads the image in a frame
// whose y and z axes are the light space's swapped, so that the image's centre is the light's +y
// (create_light folds that swap into `image_to_world`). Paths leave by the image's density: a
// pixel by its value, then a uniform point of it, so that I / pdf is constant.
#include "lights/image_point_light.h"
#include "lights/lights.h"
#include "lights/point_lights.h"
#include "sampling/distributions.h"
#include "sampling/warps.h"

namespace ml {
namespace {

class GoniometricLight final : public ImagePointLight {
public:
    GoniometricLight(const Transform& image_to_world, const RGB& I, std::vector<float> values,
                     int res)
        : ImagePointLight(image_to_world.point(Vec3(0, 0, 0))),
          m_to_world(image_to_world),
          m_to_image(image_to_world.inverse()),
          m_I(I),
          m_values(std::move(values)),
          m_res(res) {
        double sum = 0;
        for (float v : m_values) {
            sum += double(v);
            m_max = std::max(m_max, v);
        }
        m_mean = float(sum / double(m_values.size()));
        m_dist = Distribution2D(m_values, m_res, m_res);
    }
    RGB emitted_intensity(const Vec3& w) const override {
        return m_I * value(equal_area_sphere_to_square(normalize(m_to_image.vector(w))));
    }
    std::optional<LightLeSample> sample_le(const Vec2& u_pos, const Vec2& u_dir) const override {
        if (!(m_mean > 0)) return std::nullopt;
        float pdf_uv;
        Vec2 uv = m_dist.sample(u_dir, &pdf_uv);
        if (!(pdf_uv > 0)) return std::nullopt;
        LightLeSample s;
        s.ray.o = m_p;
        s.ray.d = normalize(m_to_world.vector(equal_area_square_to_sphere(uv)));
        s.L = m_I * value(uv);
        s.pdf_pos = 1;
        s.pdf_dir = pdf_uv * kInv4Pi;  // the map covers 4 pi sr uniformly
        return s;
    }
    void pdf_le(const Ray& ray, const Vec3&, float* pdf_pos, float* pdf_dir) const override {
        *pdf_pos = 0;
        *pdf_dir =
            m_mean > 0
                ? m_dist.pdf(equal_area_sphere_to_square(normalize(m_to_image.vector(ray.d)))) *
                      kInv4Pi
                : 0.f;
    }
    RGB power() const override { return m_I * (4 * kPi * m_mean); }
    // Bounded as an isotropic light of the largest intensity (as pbrt-v4 bounds it, isotropic).
    std::optional<LightBounds> bounds() const override {
        LightBounds b;
        b.box.expand(m_p);
        b.phi = std::max(0.f, m_I.luminance() * m_max);
        b.cos_theta_o = -1;
        b.cos_theta_e = 0;
        return b;
    }
    // An omni light bounded by the largest intensity, evaluated through emitted_intensity.
    void to_point_lights(int, Sampler&, std::vector<PointLight>& out) const override {
        PointLight pl;
        pl.p = m_p;
        pl.intensity = m_I * m_max;
        pl.kind = PointLightKind::Omni;
        pl.emitter = this;
        out.push_back(pl);
    }

private:
    // The nearest pixel's value (pbrt-v4's LookupNearestChannel, clamped at the edges).
    float value(Vec2 uv) const {
        int x = std::clamp(int(uv.x * float(m_res)), 0, m_res - 1);
        int y = std::clamp(int(uv.y * float(m_res)), 0, m_res - 1);
        return m_values[size_t(y) * size_t(m_res) + size_t(x)];
    }

    Transform m_to_world, m_to_image;
    RGB m_I;
    std::vector<float> m_values;  // res x res, row-major, top row first, non-negative
    int m_res;
    float m_mean = 0, m_max = 0;
    Distribution2D m_dist;
};

}  // namespace

std::unique_ptr<Light> make_goniometric_light(const Transform& image_to_world, const RGB& I,
                                              std::vector<float> values, int res) {
    return std::make_unique<GoniometricLight>(image_to_world, I, std::move(values), res);
}

}  // namespace ml
