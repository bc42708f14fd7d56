// Diffuse area lights over a whole triangle mesh. For next-event estimation a triangle is picked
// (small meshes: by its estimated solid angle and the receiver's cosine; large ones: by area, O(log
// n) in the CDF), then a direction uniformly over the solid angle it subtends, warped towards the
// receiver's cosine (pbrt-v4's Triangle::Sample); where the triangle looks tiny or huge, a uniform
// point on it. Paths leaving the light start at a uniform point, area density 1 / total area.
// With an image (pbrt-v4's "filename"), the radiance at texture coordinates (u, v) is the image's
// bilinear value at (u, 1 - v), clamped at its edges; sampling stays by area, as pbrt-v4's.
// On a cut-out shape ("alpha") the emission is masked where the cut-out removes the surface
// (pbrt-v4's AlphaMasked in L, SampleLi and SampleLe); densities, power and bounds stay the
// whole mesh's, as pbrt-v4's.
#include "geometry/alpha_test.h"
#include "lights/lights.h"
#include "lights/point_lights.h"
#include "sampling/distributions.h"
#include "sampling/sampler.h"
#include "sampling/spherical_triangle.h"
#include "sampling/warps.h"

namespace ml {
namespace {

class DiffuseAreaLight final : public Light {
public:
    DiffuseAreaLight(const TriangleMesh* mesh, const RGB& L, bool two_sided, Image image)
        : m_mesh(mesh), m_L(L), m_two_sided(two_sided), m_image(std::move(image)) {
        if (m_image.width > 0) {
            // The image's mean stands for L in power() and the bounds (pbrt-v4's Phi).
            RGB sum;
            for (RGB& c : m_image.pixels) sum += c = clamp_zero(c);
            m_L = sum / float(m_image.pixels.size());
        }
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
        // Small meshes: each triangle's corners, normal and centroid, which every light sample
        // reads for every triangle (receiver_importances).
        if (mesh->triangle_count() <= kPerReceiverChoice) {
            m_small.resize(mesh->triangle_count());
            for (size_t i = 0; i < m_small.size(); ++i) {
                SmallTriangle& t = m_small[i];
                const uint32_t* idx = &mesh->indices[3 * i];
                for (int k = 0; k < 3; ++k) t.v[k] = mesh->p[idx[k]];
                t.n = mesh->triangle_normal(i);
                t.centroid = (t.v[0] + t.v[1] + t.v[2]) / 3.f;
            }
        }
    }
    LightType type() const override { return LightType::Area; }
    bool met_by_rays() const override { return !invisible(); }

    std::optional<LightLiSample> sample_li(const LightSampleContext& ctx,
                                           const Vec2& u) const override {
        if (m_area <= 0) return std::nullopt;
        float pmf_tri = 0, ux = 0;
        size_t tri = choose_triangle(ctx, u.x, &pmf_tri, &ux);
        if (!(pmf_tri > 0)) return std::nullopt;
        Vec3 v[3];
        corners(tri, v);
        Vec3 n = normal(tri);
        // Seen from behind, a one-sided triangle sends nothing: no sample.
        if (!m_two_sided && dot(n, ctx.p - v[0]) <= 0) return std::nullopt;
        LightLiSample s;
        Barycentrics bary;
        auto st = solid_angle_sampler(tri, v, ctx.p);
        if (st) {
            Vec2 uu(ux, u.y);
            float pdf_warp = 1;
            if (ctx.ns != Vec3()) {
                float w[4];
                cosine_weights(ctx, v, w);
                uu = sample_bilinear(uu, w);
                pdf_warp = pdf_bilinear_area(uu, w);
            }
            auto dir = st->sample(uu);
            if (!dir) return std::nullopt;
            auto b = hit_barycentrics(v, ctx.p, *dir);
            if (!b) return std::nullopt;
            bary = *b;
            point_at(v, bary, &s.p_light, &s.p_error);
            s.pdf_solid_angle = pmf_tri * pdf_warp / st->solid_angle();
        } else {
            bary = sample_uniform_triangle({ux, u.y});
            point_at(v, bary, &s.p_light, &s.p_error);
        }
        Vec3 d = s.p_light - ctx.p;
        float d2 = length_squared(d);
        if (!(d2 > 0)) return std::nullopt;
        s.wi = d / std::sqrt(d2);
        float cos_l = -dot(n, s.wi);
        if (cos_l == 0 || (!m_two_sided && cos_l < 0)) return std::nullopt;
        if (!st) s.pdf_solid_angle = pmf_tri * d2 / (std::abs(cos_l) * m_mesh->triangle_area(tri));
        s.uv = texture_coords(tri, bary);
        // A cut-out sends nothing where it is not (pbrt-v4's AlphaMasked); the density stays
        // over the whole mesh.
        if (masked(s.p_light, n, s.uv)) return std::nullopt;
        s.L = emission(s.uv);
        s.n_light = n;
        s.prim = uint32_t(tri);
        return s;
    }
    float pdf_li(const LightSampleContext& ctx, const Vec3& wi, const Vec3& p_light,
                 const Vec3& n_light, uint32_t prim) const override {
        if (m_area <= 0 || prim >= m_mesh->triangle_count()) return 0;
        float cos_l = -dot(n_light, wi);
        if (cos_l == 0 || (!m_two_sided && cos_l < 0)) return 0;
        Vec3 v[3];
        corners(prim, v);
        float pmf_tri = triangle_pmf(ctx, prim);
        if (!(pmf_tri > 0)) return 0;
        auto st = solid_angle_sampler(prim, v, ctx.p);
        if (!st)
            return pmf_tri * distance_squared(ctx.p, p_light) /
                   (std::abs(cos_l) * m_mesh->triangle_area(prim));
        float pdf_warp = 1;
        if (ctx.ns != Vec3()) {
            float w[4];
            cosine_weights(ctx, v, w);
            pdf_warp = pdf_bilinear_area(st->invert(wi), w);
        }
        return pmf_tri * pdf_warp / st->solid_angle();
    }
    RGB radiance(const Vec3& p, const Vec3& n, const Vec2& uv, const Vec3& w) const override {
        if (!m_two_sided && dot(n, w) <= 0) return RGB();
        if (masked(p, n, uv)) return RGB();
        return emission(uv);
    }

    std::optional<LightLeSample> sample_le(const Vec2& u_pos, const Vec2& u_dir) const override {
        if (m_area <= 0) return std::nullopt;
        LightLeSample s;
        sample_point(u_pos, &s.ray.o, &s.n_light, &s.p_error, &s.uv, &s.prim);
        if (masked(s.ray.o, s.n_light, s.uv)) return std::nullopt;
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
        s.L = emission(s.uv);
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
    // the surface, a cosine lobe of peak intensity L * area / n per emitting side (L at the
    // point, for an image).
    void to_point_lights(int n, Sampler& sampler, std::vector<PointLight>& out) const override {
        if (m_area <= 0 || n <= 0) return;
        Vec2 shift = sampler.get_2d();
        for (int i = 0; i < n; ++i) {
            PointLight pl;
            Vec3 p_error;
            Vec2 uv;
            uint32_t prim;
            sample_point(shifted_hammersley(uint32_t(i), uint32_t(n), shift), &pl.p, &pl.n,
                         &p_error, &uv, &prim);
            pl.offset = surface_offset(pl.n, p_error);
            if (masked(pl.p, pl.n, uv)) continue;  // stands for area / n of a cut-out: none here
            pl.intensity = emission(uv) * (m_area / float(n));
            if (pl.intensity.is_black()) continue;
            pl.kind = PointLightKind::Oriented;
            out.push_back(pl);
            if (m_two_sided) {
                pl.n = -pl.n;
                out.push_back(pl);
            }
        }
    }

private:
    // A uniform point p on the mesh, its normal n, the error bound of p, its texture
    // coordinates and its triangle.
    void sample_point(Vec2 u, Vec3* p, Vec3* n, Vec3* p_error, Vec2* uv, uint32_t* prim) const {
        float ux;
        size_t tri = m_tri.sample_discrete(u.x, nullptr, &ux);
        Vec3 v[3];
        corners(tri, v);
        Barycentrics b = sample_uniform_triangle({ux, u.y});
        point_at(v, b, p, p_error);
        *n = normal(tri);
        *uv = texture_coords(tri, b);
        *prim = uint32_t(tri);
    }
    // Whether the shape's cut-out removes the emission at p (normal n, texture coordinates
    // uv): pbrt-v4's test, which hashes the point (so a fractional alpha a lets a of the
    // surface emit, and a ray that hit it, kept with probability a by the ray's own test, sees
    // its emission with probability a again, as in pbrt-v4).
    // An invisible light (constant alpha 0) emits in full: its alpha keeps rays away, not light.
    bool masked(const Vec3& p, const Vec3& n, const Vec2& uv) const {
        return m_mesh->alpha && !invisible() &&
               !alpha_keeps(m_mesh->alpha->eval(p, uv, n), alpha_hash(p));
    }
    bool invisible() const { return m_mesh->alpha && m_mesh->alpha->removes_all(); }
    // Texture coordinates at barycentrics b of triangle tri: the mesh's, else pbrt's (0,0),
    // (1,0), (1,1) per triangle (as ray hits have them).
    Vec2 texture_coords(size_t tri, const Barycentrics& b) const {
        if (m_image.width == 0 && !m_mesh->alpha) return {};
        Vec2 t0(0, 0), t1(1, 0), t2(1, 1);
        if (!m_mesh->uv.empty()) {
            const uint32_t* idx = &m_mesh->indices[3 * tri];
            t0 = m_mesh->uv[idx[0]], t1 = m_mesh->uv[idx[1]], t2 = m_mesh->uv[idx[2]];
        }
        return t0 * b.b0 + t1 * b.b1 + t2 * b.b2;
    }
    // Radiance at texture coordinates uv: L, or the image's bilinear value at (u, 1 - v) with
    // pixel centres at half-integers and clamped edges (pbrt-v4's Image::Bilerp).
    RGB emission(Vec2 uv) const {
        if (m_image.width == 0) return m_L;
        float x = uv.x * float(m_image.width) - 0.5f, y = (1 - uv.y) * float(m_image.height) - 0.5f;
        if (!std::isfinite(x) || !std::isfinite(y)) return RGB();
        float fx = std::floor(x), fy = std::floor(y);
        float dx = x - fx, dy = y - fy;
        auto at = [&](float px, float py) {
            int ix = int(std::clamp(px, 0.f, float(m_image.width - 1)));
            int iy = int(std::clamp(py, 0.f, float(m_image.height - 1)));
            return m_image.at(ix, iy);
        };
        return at(fx, fy) * ((1 - dx) * (1 - dy)) + at(fx + 1, fy) * (dx * (1 - dy)) +
               at(fx, fy + 1) * ((1 - dx) * dy) + at(fx + 1, fy + 1) * (dx * dy);
    }
    void corners(size_t tri, Vec3 v[3]) const {
        if (!m_small.empty()) {
            for (int k = 0; k < 3; ++k) v[k] = m_small[tri].v[k];
            return;
        }
        const uint32_t* idx = &m_mesh->indices[3 * tri];
        for (int k = 0; k < 3; ++k) v[k] = m_mesh->p[idx[k]];
    }
    Vec3 normal(size_t tri) const {
        return m_small.empty() ? m_mesh->triangle_normal(tri) : m_small[tri].n;
    }
    // The point at barycentrics b and its error bound: as for ray hits, with one rounding fewer
    // (pbrt-v4's Triangle::Sample).
    static void point_at(const Vec3 v[3], const Barycentrics& b, Vec3* p, Vec3* p_error) {
        Vec3 p0 = v[0] * b.b0, p1 = v[1] * b.b1, p2 = v[2] * b.b2;
        *p = p0 + p1 + p2;
        *p_error = (vabs(p0) + vabs(p1) + vabs(p2)) * gamma_bound(6);
    }
    // Where the ray from o along unit w meets the triangle's plane, as barycentrics clamped into
    // the triangle (the sampled direction passes through it up to rounding); none if parallel.
    static std::optional<Barycentrics> hit_barycentrics(const Vec3 v[3], const Vec3& o,
                                                        const Vec3& w) {
        Vec3 e1 = v[1] - v[0], e2 = v[2] - v[0];
        Vec3 s1 = cross(w, e2);
        float div = dot(s1, e1);
        if (div == 0 || !std::isfinite(div)) return std::nullopt;
        Vec3 s = o - v[0];
        float b1 = std::max(0.f, dot(s, s1) / div), b2 = std::max(0.f, dot(w, cross(s, e1)) / div);
        if (b1 + b2 > 1) {
            float sum = b1 + b2;
            b1 /= sum;
            b2 /= sum;
        }
        return Barycentrics{1 - b1 - b2, b1, b2};
    }
    // The triangle for a sample at ctx, with its probability; u_remapped receives u rescaled
    // inside its share. Small meshes (a quad, a box) choose in proportion to an estimate of each
    // triangle's solid angle at ctx times the receiver's cosine, which evens the density over
    // the whole light; larger meshes by area (per-receiver weights cost O(n)).
    static constexpr size_t kPerReceiverChoice = 16;
    size_t choose_triangle(const LightSampleContext& ctx, float u, float* pmf,
                           float* u_remapped) const {
        if (m_mesh->triangle_count() > kPerReceiverChoice)
            return m_tri.sample_discrete(u, pmf, u_remapped);
        float imp[kPerReceiverChoice];
        float sum = receiver_importances(ctx, imp);
        *pmf = 0;
        if (!(sum > 0)) return 0;
        size_t n = m_mesh->triangle_count(), last = 0;
        for (size_t t = 0; t < n; ++t)
            if (imp[t] > 0) last = t;
        float target = u * sum, acc = 0;
        for (size_t t = 0; t < n; ++t) {
            if (!(imp[t] > 0)) continue;
            if (target < acc + imp[t] || t == last) {
                *pmf = imp[t] / sum;
                *u_remapped = std::clamp((target - acc) / imp[t], 0.f, kOneMinusEpsilon);
                return t;
            }
            acc += imp[t];
        }
        return 0;
    }
    float triangle_pmf(const LightSampleContext& ctx, size_t tri) const {
        if (m_mesh->triangle_count() > kPerReceiverChoice) return m_tri.pmf(tri);
        float imp[kPerReceiverChoice];
        float sum = receiver_importances(ctx, imp);
        return sum > 0 ? imp[tri] / sum : 0.f;
    }
    // Each triangle's weight at ctx (small meshes), returning the sum: zero where it shows ctx
    // its back (one-sided), else its estimated solid angle times the receiver's cosine towards
    // its centroid, floored so that no part of a triangle that rises above the horizon goes
    // unsampled.
    float receiver_importances(const LightSampleContext& ctx, float* imp) const {
        float sum = 0;
        for (size_t t = 0; t < m_mesh->triangle_count(); ++t) {
            imp[t] = 0;
            Vec3 v[3];
            corners(t, v);
            if (!m_two_sided && dot(normal(t), ctx.p - v[0]) <= 0) continue;
            Vec3 dir;
            float w = estimated_solid_angle(t, v, ctx.p, &dir);
            if (ctx.ns != Vec3() && dir != Vec3()) w *= std::max(0.1f, dot(ctx.ns, dir));
            imp[t] = w;
            sum += w;
        }
        return sum;
    }
    // Triangle tri's solid angle at p estimated from its centroid (area |cos| / d^2, at most a
    // hemisphere; zero for no area): no trigonometry. `dir` receives the unit direction to the
    // centroid (zero if p is on it).
    float estimated_solid_angle(size_t tri, const Vec3 v[3], const Vec3& p, Vec3* dir) const {
        float area = m_tri.func()[tri];
        *dir = Vec3();
        if (!(area > 0)) return 0;
        Vec3 d = (m_small.empty() ? (v[0] + v[1] + v[2]) / 3.f : m_small[tri].centroid) - p;
        float d2 = length_squared(d);
        if (!(d2 > 0)) return 2 * kPi;
        *dir = d / std::sqrt(d2);
        return std::min(2 * kPi, area * std::abs(dot(normal(tri), *dir)) / d2);
    }
    // Solid-angle sampling pays where a triangle looks large: where it looks small (under
    // 0.05 sr, a 13-degree cone) 1 / d^2 and the cosines hardly vary over it and the cheaper
    // area sampling does as well; near a whole hemisphere it is unstable. Sampling and pdf_li
    // decide alike, from the estimate; the spherical triangle when by solid angle.
    std::optional<SphericalTriangle> solid_angle_sampler(size_t tri, const Vec3 v[3],
                                                         const Vec3& p) const {
        Vec3 dir;
        float omega = estimated_solid_angle(tri, v, p, &dir);
        if (!(omega >= 0.05f && omega <= 6.2f)) return std::nullopt;
        return SphericalTriangle::make(v[0], v[1], v[2], p);
    }
    // The receiver's cosine towards the corners, as bilinear weights over the spherical
    // triangle's square (u.y = 0 is corner 1; at u.y = 1, u.x runs from corner 0 to corner 2),
    // floored so that no part of the triangle goes unsampled.
    static void cosine_weights(const LightSampleContext& ctx, const Vec3 v[3], float w[4]) {
        auto c = [&](const Vec3& corner) {
            Vec3 d = corner - ctx.p;
            float l = length(d);
            return l > 0 ? std::max(0.01f, std::abs(dot(ctx.ns, d / l))) : 0.01f;
        };
        w[0] = w[1] = c(v[1]);
        w[2] = c(v[0]);
        w[3] = c(v[2]);
    }

    struct SmallTriangle {
        Vec3 v[3], n, centroid;
    };

    const TriangleMesh* m_mesh;
    std::vector<SmallTriangle> m_small;  // meshes of at most kPerReceiverChoice triangles
    RGB m_L;                             // the radiance; with an image, its mean
    bool m_two_sided;
    Image m_image;  // width 0: none; else linear, scaled, non-negative
    float m_area = 0;
    Distribution1D m_tri;
    LightBounds m_bounds;
};

}  // namespace

std::unique_ptr<Light> make_diffuse_area_light(const TriangleMesh* mesh, const RGB& L,
                                               bool two_sided) {
    return std::make_unique<DiffuseAreaLight>(mesh, L, two_sided, Image());
}

std::unique_ptr<Light> make_image_area_light(const TriangleMesh* mesh, Image image,
                                             bool two_sided) {
    return std::make_unique<DiffuseAreaLight>(mesh, RGB(), two_sided, std::move(image));
}

}  // namespace ml
