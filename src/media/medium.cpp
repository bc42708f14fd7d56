#include "media/medium.h"

#include <algorithm>
#include <cmath>

namespace ml {

float hg_phase(const Vec3& wo, const Vec3& wi, float g) {
    const float denom = 1 + g * g + 2 * g * dot(wo, wi);
    return kInv4Pi * (1 - g * g) / (denom * std::sqrt(std::max(denom, 1e-12f)));
}

Vec3 sample_hg_phase(const Vec3& wo, float g, const Vec2& u) {
    // cos of the angle between wo and wi, by inverting the density's distribution over it,
    // (1 - g^2) / (2 (1 + g^2 + 2 g mu)^(3/2)) on [-1, 1].
    float mu;
    if (std::abs(g) < 1e-3f) {
        mu = 1 - 2 * u.x;
    } else {
        const float s = (1 - g * g) / (1 - g + 2 * g * u.x);
        mu = -(1 + g * g - s * s) / (2 * g);
    }
    mu = std::clamp(mu, -1.f, 1.f);
    const float sin_theta = std::sqrt(std::max(0.f, 1 - mu * mu));
    const float phi = 2 * kPi * u.y;
    const Frame f = Frame::from_z(wo);
    return f.to_world(Vec3(sin_theta * std::cos(phi), sin_theta * std::sin(phi), mu));
}

namespace {

// The spectra of pbrt-v4's media as RGB: an "rgb" or "spectrum" value (unbounded: no clamp).
RGB medium_rgb(const ParameterList& params, const char* name, const RGB& def) {
    return params.get_rgb(name).value_or(def);
}

class HomogeneousMedium final : public Medium {
public:
    HomogeneousMedium(const RGB& sigma_a, const RGB& sigma_s, const RGB& Le, float g) {
        m_props = {sigma_a, sigma_s, Le};
        m_g = g;
        m_emits = !Le.is_black() && !sigma_a.is_black();
        m_sigma_maj = (sigma_a + sigma_s).max_component();
    }
    MediumProperties at(const Vec3&) const override { return m_props; }
    std::optional<MajorantSegment> majorant(const Ray&, float tmax) const override {
        return MajorantSegment{0, tmax, m_sigma_maj};
    }
    bool homogeneous() const override { return true; }
    std::string type() const override { return "homogeneous"; }

private:
    MediumProperties m_props;
    float m_sigma_maj = 0;
};

// pbrt-v4's SampledGrid: nx x ny x nz values at the cells' centres of the unit cube,
// interpolated trilinearly; zero outside.
class Grid {
public:
    Grid() = default;
    Grid(std::vector<float> values, int nx, int ny, int nz)
        : m_v(std::move(values)), m_nx(nx), m_ny(ny), m_nz(nz) {}
    float lookup(const Vec3& p) const {
        const float x = p.x * float(m_nx) - 0.5f, y = p.y * float(m_ny) - 0.5f,
                    z = p.z * float(m_nz) - 0.5f;
        const int ix = int(std::floor(x)), iy = int(std::floor(y)), iz = int(std::floor(z));
        const float dx = x - float(ix), dy = y - float(iy), dz = z - float(iz);
        auto v = [&](int i, int j, int k) {
            if (i < 0 || j < 0 || k < 0 || i >= m_nx || j >= m_ny || k >= m_nz) return 0.f;
            return m_v[(size_t(k) * size_t(m_ny) + size_t(j)) * size_t(m_nx) + size_t(i)];
        };
        const float d00 = lerp(dx, v(ix, iy, iz), v(ix + 1, iy, iz));
        const float d10 = lerp(dx, v(ix, iy + 1, iz), v(ix + 1, iy + 1, iz));
        const float d01 = lerp(dx, v(ix, iy, iz + 1), v(ix + 1, iy, iz + 1));
        const float d11 = lerp(dx, v(ix, iy + 1, iz + 1), v(ix + 1, iy + 1, iz + 1));
        return lerp(dz, lerp(dy, d00, d10), lerp(dy, d01, d11));
    }
    float max_value() const {
        float m = 0;
        for (float x : m_v) m = std::max(m, x);
        return m;
    }

private:
    std::vector<float> m_v;
    int m_nx = 0, m_ny = 0, m_nz = 0;
};

// pbrt-v4's "uniformgrid": sigma_a and sigma_s scaled by a density grid over the box [p0, p1]
// of medium space; emission Le scaled by "Lescale" (one value, or a grid of the density's size).
// The majorant is the largest density's extinction over the part of the ray inside the box.
class GridMedium final : public Medium {
public:
    GridMedium(const Transform& medium_to_world, const Vec3& p0, const Vec3& p1, Grid density,
               const RGB& sigma_a, const RGB& sigma_s, const RGB& Le, Grid le_scale, float g)
        : m_world_to_medium(medium_to_world.inverse()),
          m_p0(p0),
          m_p1(p1),
          m_density(std::move(density)),
          m_sigma_a(sigma_a),
          m_sigma_s(sigma_s),
          m_Le(Le),
          m_le_scale(std::move(le_scale)) {
        m_g = g;
        m_emits = !Le.is_black() && !sigma_a.is_black();
        m_sigma_maj = m_density.max_value() * (sigma_a + sigma_s).max_component();
    }
    MediumProperties at(const Vec3& p_world) const override {
        const Vec3 p = m_world_to_medium.point(p_world);
        const Vec3 u((p.x - m_p0.x) / (m_p1.x - m_p0.x), (p.y - m_p0.y) / (m_p1.y - m_p0.y),
                     (p.z - m_p0.z) / (m_p1.z - m_p0.z));
        const float d = m_density.lookup(u);
        MediumProperties props{m_sigma_a * d, m_sigma_s * d, RGB()};
        if (m_emits) props.Le = m_Le * m_le_scale.lookup(u);
        return props;
    }
    std::optional<MajorantSegment> majorant(const Ray& ray, float tmax) const override {
        // The ray in medium space keeps its parameter (an affine map).
        const Vec3 o = m_world_to_medium.point(ray.o), d = m_world_to_medium.vector(ray.d);
        float t0 = 0, t1 = tmax;
        for (int i = 0; i < 3; ++i) {
            const float inv = 1 / d[i];
            float tn = (m_p0[i] - o[i]) * inv, tf = (m_p1[i] - o[i]) * inv;
            if (tn > tf) std::swap(tn, tf);
            if (std::isnan(tn) || std::isnan(tf)) {  // parallel to the slab
                if (o[i] < m_p0[i] || o[i] > m_p1[i]) return std::nullopt;
                continue;
            }
            t0 = std::max(t0, tn);
            t1 = std::min(t1, tf);
        }
        if (!(t0 < t1)) return std::nullopt;
        return MajorantSegment{t0, t1, m_sigma_maj};
    }
    bool homogeneous() const override { return false; }
    std::string type() const override { return "uniformgrid"; }

private:
    Transform m_world_to_medium;
    Vec3 m_p0, m_p1;
    Grid m_density;
    RGB m_sigma_a, m_sigma_s, m_Le;
    Grid m_le_scale;
    float m_sigma_maj = 0;
};

float checked_g(const ParameterList& params, const FileLoc& loc) {
    const float g = params.get_float("g", 0);
    if (!(g > -1 && g < 1))
        throw_input_error(loc, "medium: \"g\" must be in (-1, 1) (it is {})", g);
    return g;
}

void check_non_negative(const RGB& c, const char* name, const FileLoc& loc) {
    if (!(c.r >= 0 && c.g >= 0 && c.b >= 0) || !c.is_finite())
        throw_input_error(loc, "medium: \"{}\" must be finite and non-negative", name);
}

}  // namespace

std::unique_ptr<Medium> create_medium(const std::string& type, const ParameterList& params,
                                      const Transform& medium_to_world, const FileLoc& loc) {
    if (type == "rgbgrid" || type == "cloud" || type == "nanovdb")
        throw_input_error(loc,
                          "medium \"{}\" is not supported yet (manylight reads \"homogeneous\" "
                          "and \"uniformgrid\")",
                          type);
    if (type != "homogeneous" && type != "uniformgrid")
        throw_input_error(loc, "unknown medium type \"{}\"", type);
    if (params.has("preset"))
        throw_input_error(params.find("preset")->loc,
                          "medium: \"preset\" (pbrt-v4's measured scattering coefficients) is "
                          "not supported yet: give sigma_a and sigma_s");
    const float scale = params.get_float("scale", 1);
    const RGB sigma_a = medium_rgb(params, "sigma_a", RGB(1.f)) * scale;
    const RGB sigma_s = medium_rgb(params, "sigma_s", RGB(1.f)) * scale;
    check_non_negative(sigma_a, "sigma_a", loc);
    check_non_negative(sigma_s, "sigma_s", loc);
    const float g = checked_g(params, loc);
    const RGB Le = medium_rgb(params, "Le", RGB());
    check_non_negative(Le, "Le", loc);
    if (type == "homogeneous") {
        const float le_scale = params.get_float("Lescale", 1);
        return std::make_unique<HomogeneousMedium>(sigma_a, sigma_s, Le * le_scale, g);
    }
    if (params.has("temperature") || params.has("temperatureoffset") ||
        params.has("temperaturecutoff") || params.has("temperaturescale"))
        throw_input_error(loc,
                          "medium \"uniformgrid\": blackbody emission by \"temperature\" is not "
                          "supported yet: give \"Le\"");
    const std::vector<float> density = params.get_floats("density");
    const int nx = params.get_int("nx", 1), ny = params.get_int("ny", 1),
              nz = params.get_int("nz", 1);
    if (density.empty()) throw_input_error(loc, "medium \"uniformgrid\": no \"density\" given");
    if (nx < 1 || ny < 1 || nz < 1 || size_t(nx) * size_t(ny) * size_t(nz) != density.size())
        throw_input_error(loc,
                          "medium \"uniformgrid\": {} \"density\" values where nx * ny * nz = "
                          "{} x {} x {}",
                          density.size(), nx, ny, nz);
    for (float d : density)
        if (!(d >= 0) || !std::isfinite(d))
            throw_input_error(loc,
                              "medium \"uniformgrid\": a \"density\" value is negative "
                              "or not finite");
    const std::vector<float> le_scale = params.get_floats("Lescale");
    Grid le_grid({1.f}, 1, 1, 1);
    if (!le_scale.empty()) {
        if (le_scale.size() != density.size())
            throw_input_error(loc,
                              "medium \"uniformgrid\": {} \"Lescale\" values where the density "
                              "has {}",
                              le_scale.size(), density.size());
        le_grid = Grid(le_scale, nx, ny, nz);
    }
    const Vec3 p0 = params.get_point3("p0").value_or(Vec3(0, 0, 0));
    const Vec3 p1 = params.get_point3("p1").value_or(Vec3(1, 1, 1));
    if (!(p0.x < p1.x && p0.y < p1.y && p0.z < p1.z))
        throw_input_error(loc, "medium \"uniformgrid\": \"p0\" must be below \"p1\" on every axis");
    return std::make_unique<GridMedium>(medium_to_world, p0, p1, Grid(density, nx, ny, nz), sigma_a,
                                        sigma_s, Le, std::move(le_grid), g);
}

}  // namespace ml
