// Diffuse area lights over a whole triangle mesh: a triangle is picked in proportion to its area
// (O(log n) in the CDF), then a uniform point on it, so the area density is 1 / total area
// everywhere and pdf_li needs only the hit point and its normal.
#include "lights/lights.h"
#include "lights/point_lights.h"
#include "sampling/distributions.h"
#include "sampling/sampler.h"
#include "sampling/warps.h"

namespace ml {
namespace {

class DiffuseAreaLight final : public Light {
public:
    DiffuseAreaLight(const TriangleMesh* mesh, const RGB& L, bool two_sided)
        : m_mesh(mesh), m_L(L), m_two_sided(two_sided) {
        std::vector<float> areas(mesh->triangle_count());
        double total = 0;
        for (size_t i = 0; i < areas.size(); ++i) {
            areas[i] = mesh->triangle_area(i);
            if (!std::isfinite(areas[i])) areas[i] = 0;
            total += areas[i];
        }
        m_area = float(total);
        m_tri = Distribution1D(areas);
        // The tree's bounds: the emitting triangles' corners and the cone of their normals.
        DirectionCone cone = DirectionCone::empty_cone();
        for (size_t i = 0; i < areas.size(); ++i) {
            if (!(areas[i] > 0)) continue;
            const uint32_t* idx = &mesh->indices[3 * i];
            for (int k = 0; k < 3; ++k) m_bounds.box.expand(mesh->p[idx[k]]);
            DirectionCone n(mesh->triangle_normal(i));
            cone = cone.is_empty() ? n : union_cones(cone, n);
        }
        m_bounds.w = cone.axis;
        m_bounds.cos_theta_o = cone.is_empty() ? 1.f : std::max(-1.f, cone.cos_theta);
        m_bounds.cos_theta_e = 0;  // diffuse: each point emits over its hemisphere
        m_bounds.two_sided = two_sided;
        m_bounds.phi = m_area > 0 ? std::max(0.f, L.luminance()) * m_area : 0.f;
    }
    LightType type() const override { return LightType::Area; }

    std::optional<LightLiSample> sample_li(const LightSampleContext& ctx,
                                           const Vec2& u) const override {
        if (m_area <= 0) return std::nullopt;
        Vec3 p, n, p_error;
        sample_point(u, &p, &n, &p_error);
        Vec3 d = p - ctx.p;
        float d2 = length_squared(d);
        if (d2 == 0) return std::nullopt;
        Vec3 wi = d / std::sqrt(d2);
        float cos_l = -dot(n, wi);
        if (cos_l == 0 || (!m_two_sided && cos_l < 0)) return std::nullopt;
        LightLiSample s;
        s.wi = wi;
        s.L = m_L;
        s.pdf_solid_angle = d2 / (std::abs(cos_l) * m_area);
        s.p_light = p;
        s.n_light = n;
        s.p_error = p_error;
        return s;
    }
    float pdf_li(const LightSampleContext& ctx, const Vec3& wi, const Vec3& p_light,
                 const Vec3& n_light) const override {
        if (m_area <= 0) return 0;
        float cos_l = -dot(n_light, wi);
        if (cos_l == 0 || (!m_two_sided && cos_l < 0)) return 0;
        return distance_squared(ctx.p, p_light) / (std::abs(cos_l) * m_area);
    }
    RGB radiance(const Vec3& p, const Vec3& n, const Vec2& uv, const Vec3& w) const override {
        if (!m_two_sided && dot(n, w) <= 0) return RGB();
        return m_L;
    }

    std::optional<LightLeSample> sample_le(const Vec2& u_pos, const Vec2& u_dir) const override {
        if (m_area <= 0) return std::nullopt;
        LightLeSample s;
        sample_point(u_pos, &s.ray.o, &s.n_light, &s.p_error);
        // Cosine-weighted about the normal; two-sided lights pick a side with half of u_dir.x.
        Vec2 u = u_dir;
        bool back = false;
        if (m_two_sided) {
            back = u.x >= 0.5f;
            u.x = std::min(back ? 2 * u.x - 1 : 2 * u.x, kOneMinusEpsilon);
        }
        Vec3 w = sample_cosine_hemisphere(u);
        float pdf_dir = pdf_cosine_hemisphere(w.z) * (m_two_sided ? 0.5f : 1.f);
        if (pdf_dir == 0) return std::nullopt;
        if (back) w.z = -w.z;
        s.ray.d = Frame::from_z(s.n_light).to_world(w);
        s.L = m_L;
        s.pdf_pos = 1 / m_area;
        s.pdf_dir = pdf_dir;
        return s;
    }
    void pdf_le(const Ray& ray, const Vec3& n_light, float* pdf_pos,
                float* pdf_dir) const override {
        *pdf_pos = m_area > 0 ? 1 / m_area : 0.f;
        float c = dot(n_light, ray.d);
        *pdf_dir = m_two_sided ? 0.5f * std::abs(c) * kInvPi : pdf_cosine_hemisphere(c);
    }
    RGB power() const override { return m_L * (kPi * m_area * (m_two_sided ? 2.f : 1.f)); }
    std::optional<LightBounds> bounds() const override { return m_bounds; }
    // n points stratified over the area (uniform density 1 / area): each stands for area / n of
    // the surface, a cosine lobe of peak intensity L * area / n per emitting side.
    void to_point_lights(int n, Sampler& sampler, std::vector<PointLight>& out) const override {
        if (m_area <= 0 || n <= 0) return;
        Vec2 shift = sampler.get_2d();
        RGB I = m_L * (m_area / float(n));
        for (int i = 0; i < n; ++i) {
            PointLight pl;
            Vec3 p_error;
            sample_point(shifted_hammersley(uint32_t(i), uint32_t(n), shift), &pl.p, &pl.n,
                         &p_error);
            pl.offset = surface_offset(pl.n, p_error);
            pl.intensity = I;
            pl.kind = PointLightKind::Oriented;
            out.push_back(pl);
            if (m_two_sided) {
                pl.n = -pl.n;
                out.push_back(pl);
            }
        }
    }

private:
    // A uniform point p on the mesh, its normal n and the error bound of p.
    void sample_point(Vec2 u, Vec3* p, Vec3* n, Vec3* p_error) const {
        float ux;
        size_t tri = m_tri.sample_discrete(u.x, nullptr, &ux);
        Barycentrics b = sample_uniform_triangle({ux, u.y});
        const uint32_t* idx = &m_mesh->indices[3 * tri];
        Vec3 p0 = m_mesh->p[idx[0]] * b.b0, p1 = m_mesh->p[idx[1]] * b.b1,
             p2 = m_mesh->p[idx[2]] * b.b2;
        *p = p0 + p1 + p2;
        // As for ray hits, with one rounding fewer (pbrt-v4's Triangle::Sample).
        *p_error = (vabs(p0) + vabs(p1) + vabs(p2)) * gamma_bound(6);
        *n = m_mesh->triangle_normal(tri);
    }

    const TriangleMesh* m_mesh;
    RGB m_L;
    bool m_two_sided;
    float m_area = 0;
    Distribution1D m_tri;
    LightBounds m_bounds;
};

}  // namespace

std::unique_ptr<Light> make_diffuse_area_light(const TriangleMesh* mesh, const RGB& L,
                                               bool two_sided) {
    return std::make_unique<DiffuseAreaLight>(mesh, L, two_sided);
}

}  // namespace ml
