#include "media/medium.h"

#include <algorithm>
#include <cmath>

#include "core/noise.h"
#include "core/scattering_presets.h"
#include "media/nanovdb_medium.h"

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

std::optional<MajorantSegment> box_majorant(const Transform& world_to_medium, const Vec3& p0,
                                            const Vec3& p1, float sigma_maj, const Ray& ray,
                                            float tmax) {
    // The ray in medium space keeps its parameter (an affine map).
    const Vec3 o = world_to_medium.point(ray.o), d = world_to_medium.vector(ray.d);
    float t0 = 0, t1 = tmax;
    for (int i = 0; i < 3; ++i) {
        const float inv = 1 / d[i];
        float tn = (p0[i] - o[i]) * inv, tf = (p1[i] - o[i]) * inv;
        if (tn > tf) std::swap(tn, tf);
        if (std::isnan(tn) || std::isnan(tf)) {  // parallel to the slab
            if (o[i] < p0[i] || o[i] > p1[i]) return std::nullopt;
            continue;
        }
        t0 = std::max(t0, tn);
        t1 = std::min(t1, tf);
    }
    if (!(t0 < t1)) return std::nullopt;
    return MajorantSegment{t0, t1, sigma_maj};
}

MajorantIterator::MajorantIterator(const MajorantGrid& grid, const Vec3& o, const Vec3& d, float t0,
                                   float t1)
    : m_t(t0), m_t1(t1), m_grid(&grid) {
    const int res = grid.res();
    const Vec3 p = o + d * t0;
    for (int a = 0; a < 3; ++a) {
        m_voxel[a] = std::clamp(int(p[a] * float(res)), 0, res - 1);
        if (d[a] == 0) {  // never crosses this axis's planes
            m_next_t[a] = kInfinity;
            m_delta_t[a] = kInfinity;
            m_step[a] = 0;
            m_limit[a] = -2;
            continue;
        }
        m_delta_t[a] = 1.f / (std::abs(d[a]) * float(res));
        const bool up = d[a] > 0;
        const float plane = float(m_voxel[a] + (up ? 1 : 0)) / float(res);
        m_next_t[a] = t0 + (plane - p[a]) / d[a];
        m_step[a] = up ? 1 : -1;
        m_limit[a] = up ? res : -1;
    }
}

std::optional<MajorantSegment> MajorantIterator::next() {
    if (!(m_t < m_t1)) return std::nullopt;
    if (!m_grid) {
        m_t = m_t1;
        return m_single;
    }
    // The axis whose next cell boundary comes first.
    int a = 0;
    if (m_next_t[1] < m_next_t[a]) a = 1;
    if (m_next_t[2] < m_next_t[a]) a = 2;
    const float exit = std::min(m_t1, std::max(m_t, m_next_t[a]));
    const MajorantSegment seg{m_t, exit, m_grid->at(m_voxel[0], m_voxel[1], m_voxel[2])};
    m_t = exit;
    m_voxel[a] += m_step[a];
    if (m_voxel[a] == m_limit[a]) m_t = m_t1;
    m_next_t[a] += m_delta_t[a];
    return seg;
}

MajorantIterator box_majorants(const Transform& world_to_medium, const Vec3& p0, const Vec3& p1,
                               const MajorantGrid& grid, float sigma_maj, const Ray& ray,
                               float tmax) {
    const std::optional<MajorantSegment> s =
        box_majorant(world_to_medium, p0, p1, sigma_maj, ray, tmax);
    if (!s) return MajorantIterator();
    if (grid.empty()) return MajorantIterator(*s);
    const Vec3 ext = p1 - p0, o = world_to_medium.point(ray.o), d = world_to_medium.vector(ray.d);
    return MajorantIterator(grid,
                            Vec3((o.x - p0.x) / ext.x, (o.y - p0.y) / ext.y, (o.z - p0.z) / ext.z),
                            Vec3(d.x / ext.x, d.y / ext.y, d.z / ext.z), s->t0, s->t1);
}

BlackbodyTable::BlackbodyTable(float offset, float scale, float raw_min, float raw_max)
    : m_offset(offset), m_scale(scale) {
    const float hottest = std::max((raw_min - offset) * scale, (raw_max - offset) * scale);
    if (!(hottest > 100)) return;
    // Hotter than the table (rare: a hundred thousand kelvin) is evaluated directly.
    const size_t n = size_t(std::ceil((std::min(hottest, kTableTop) - 100) / 10)) + 2;
    m_rgb.resize(n);
    for (size_t i = 0; i < n; ++i) m_rgb[i] = blackbody_radiance_rgb(100 + 10 * float(i));
}

RGB BlackbodyTable::at(float raw) const {
    const float k = (raw - m_offset) * m_scale;
    if (!(k > 100) || m_rgb.empty()) return RGB();
    if (k > kTableTop) return blackbody_radiance_rgb(k);
    const float x = std::min((k - 100) / 10, float(m_rgb.size() - 1));
    const size_t i = std::min(size_t(x), m_rgb.size() - 2);
    const float t = x - float(i);
    return m_rgb[i] * (1 - t) + m_rgb[i + 1] * t;
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

// pbrt-v4's SampledGrid: nx x ny x nz values (float or RGB) at the cells' centres of the unit
// cube, interpolated trilinearly; zero outside.
template <class T>
class Grid {
public:
    Grid() = default;
    Grid(std::vector<T> values, int nx, int ny, int nz)
        : m_v(std::move(values)), m_nx(nx), m_ny(ny), m_nz(nz) {}
    T lookup(const Vec3& p) const {
        const float x = p.x * float(m_nx) - 0.5f, y = p.y * float(m_ny) - 0.5f,
                    z = p.z * float(m_nz) - 0.5f;
        const int ix = int(std::floor(x)), iy = int(std::floor(y)), iz = int(std::floor(z));
        const float dx = x - float(ix), dy = y - float(iy), dz = z - float(iz);
        auto v = [&](int i, int j, int k) {
            if (i < 0 || j < 0 || k < 0 || i >= m_nx || j >= m_ny || k >= m_nz) return T{};
            return m_v[(size_t(k) * size_t(m_ny) + size_t(j)) * size_t(m_nx) + size_t(i)];
        };
        auto mix = [](float t, const T& a, const T& b) { return a * (1 - t) + b * t; };
        const T d00 = mix(dx, v(ix, iy, iz), v(ix + 1, iy, iz));
        const T d10 = mix(dx, v(ix, iy + 1, iz), v(ix + 1, iy + 1, iz));
        const T d01 = mix(dx, v(ix, iy, iz + 1), v(ix + 1, iy, iz + 1));
        const T d11 = mix(dx, v(ix, iy + 1, iz + 1), v(ix + 1, iy + 1, iz + 1));
        return mix(dz, mix(dy, d00, d10), mix(dy, d01, d11));
    }
    bool empty() const { return m_v.empty(); }
    const std::vector<T>& values() const { return m_v; }
    // A majorant grid's cells per axis for this grid (majorant_res).
    int res(int most) const { return majorant_res(std::max({m_nx, m_ny, m_nz}), most); }
    // f(flat index) for every value that lookup() mixes in somewhere in the box [lo, hi] of the
    // unit cube (the others are zero there, or out of reach).
    template <class F>
    void for_each_within(const Vec3& lo, const Vec3& hi, const F& f) const {
        const int n[3] = {m_nx, m_ny, m_nz};
        int i0[3], i1[3];
        for (int a = 0; a < 3; ++a) {
            i0[a] = std::max(0, int(std::floor(lo[a] * float(n[a]) - 0.5f)));
            i1[a] = std::min(n[a] - 1, int(std::floor(hi[a] * float(n[a]) - 0.5f)) + 1);
        }
        for (int k = i0[2]; k <= i1[2]; ++k)
            for (int j = i0[1]; j <= i1[1]; ++j)
                for (int i = i0[0]; i <= i1[0]; ++i)
                    f((size_t(k) * size_t(m_ny) + size_t(j)) * size_t(m_nx) + size_t(i));
    }

private:
    std::vector<T> m_v;
    int m_nx = 0, m_ny = 0, m_nz = 0;
};

// A medium inside the box [p0, p1] of medium space, its coefficients looked up at the point's
// coordinates in the unit cube; the majorant is one bound for the whole box, over the part of the
// ray inside it.
class BoxMedium : public Medium {
public:
    BoxMedium(const Transform& medium_to_world, const Vec3& p0, const Vec3& p1, float g)
        : m_world_to_medium(medium_to_world.inverse()), m_p0(p0), m_p1(p1) {
        m_g = g;
    }
    MediumProperties at(const Vec3& p_world) const override {
        const Vec3 p = m_world_to_medium.point(p_world);
        return at_unit(Vec3((p.x - m_p0.x) / (m_p1.x - m_p0.x), (p.y - m_p0.y) / (m_p1.y - m_p0.y),
                            (p.z - m_p0.z) / (m_p1.z - m_p0.z)));
    }
    std::optional<MajorantSegment> majorant(const Ray& ray, float tmax) const override {
        return box_majorant(m_world_to_medium, m_p0, m_p1, m_sigma_maj, ray, tmax);
    }
    MajorantIterator majorants(const Ray& ray, float tmax) const override {
        return box_majorants(m_world_to_medium, m_p0, m_p1, m_majorants, m_sigma_maj, ray, tmax);
    }
    bool homogeneous() const override { return false; }

protected:
    // The coefficients at u in the unit cube of the box.
    virtual MediumProperties at_unit(const Vec3& u) const = 0;
    float m_sigma_maj = 0;  // >= sigma_a + sigma_s in every channel, everywhere in the box
    // Finer bounds, cell by cell (as pbrt-v4's grid media: up to 16^3); empty: m_sigma_maj
    // alone.
    MajorantGrid m_majorants;
    static constexpr int kMajorantRes = 16;

private:
    Transform m_world_to_medium;
    Vec3 m_p0, m_p1;
};

float max_of(const std::vector<float>& v) {
    float m = 0;
    for (float x : v) m = std::max(m, x);
    return m;
}

// pbrt-v4's "uniformgrid": sigma_a and sigma_s scaled by a density grid over the box [p0, p1]
// of medium space; emission Le, or a blackbody at a grid of temperatures, scaled by "Lescale"
// (one value, or a grid of the density's size).
class GridMedium final : public BoxMedium {
public:
    GridMedium(const Transform& medium_to_world, const Vec3& p0, const Vec3& p1,
               Grid<float> density, const RGB& sigma_a, const RGB& sigma_s, const RGB& Le,
               Grid<float> le_scale, float g, Grid<float> temperature = {},
               BlackbodyTable blackbody = {})
        : BoxMedium(medium_to_world, p0, p1, g),
          m_density(std::move(density)),
          m_sigma_a(sigma_a),
          m_sigma_s(sigma_s),
          m_Le(Le),
          m_le_scale(std::move(le_scale)),
          m_temperature(std::move(temperature)),
          m_blackbody(std::move(blackbody)) {
        m_emits = (!Le.is_black() || !m_blackbody.empty()) && !sigma_a.is_black();
        const float sigma_t = (sigma_a + sigma_s).max_component();
        m_sigma_maj = max_of(m_density.values()) * sigma_t;
        // Trilinear interpolation stays within the values it mixes.
        m_majorants =
            MajorantGrid(m_density.res(kMajorantRes), [&](const Vec3& lo, const Vec3& hi) {
                float most = 0;
                m_density.for_each_within(
                    lo, hi, [&](size_t i) { most = std::max(most, m_density.values()[i]); });
                return most * sigma_t;
            });
    }
    std::string type() const override { return "uniformgrid"; }

private:
    MediumProperties at_unit(const Vec3& u) const override {
        const float d = m_density.lookup(u);
        MediumProperties props{m_sigma_a * d, m_sigma_s * d, RGB()};
        if (!m_emits) return props;
        const float scale = m_le_scale.lookup(u);
        if (!(scale > 0)) return props;
        props.Le = (m_temperature.empty() ? m_Le : m_blackbody.at(m_temperature.lookup(u))) * scale;
        return props;
    }
    Grid<float> m_density;
    RGB m_sigma_a, m_sigma_s, m_Le;
    Grid<float> m_le_scale;
    Grid<float> m_temperature;
    BlackbodyTable m_blackbody;
};

// pbrt-v4's "rgbgrid": sigma_a and sigma_s each an RGB grid (a missing one is 1 everywhere),
// both times "scale"; emission an RGB grid times "Lescale".
class RgbGridMedium final : public BoxMedium {
public:
    RgbGridMedium(const Transform& medium_to_world, const Vec3& p0, const Vec3& p1,
                  Grid<RGB> sigma_a, Grid<RGB> sigma_s, float scale, Grid<RGB> Le, float le_scale,
                  float g)
        : BoxMedium(medium_to_world, p0, p1, g),
          m_sigma_a(std::move(sigma_a)),
          m_sigma_s(std::move(sigma_s)),
          m_Le(std::move(Le)),
          m_scale(scale),
          m_le_scale(le_scale) {
        m_emits = !m_Le.empty() && le_scale > 0;
        // The interpolation never exceeds the largest cell, channel by channel.
        const size_t n = std::max(m_sigma_a.values().size(), m_sigma_s.values().size());
        auto sigma_t = [&](size_t i) {
            const RGB a = m_sigma_a.empty() ? RGB(1.f) : m_sigma_a.values()[i];
            const RGB s = m_sigma_s.empty() ? RGB(1.f) : m_sigma_s.values()[i];
            return (a + s).max_component();
        };
        float most = 0;
        for (size_t i = 0; i < n; ++i) most = std::max(most, sigma_t(i));
        m_sigma_maj = scale * most;
        const Grid<RGB>& cells = m_sigma_a.empty() ? m_sigma_s : m_sigma_a;  // both alike
        m_majorants = MajorantGrid(cells.res(kMajorantRes), [&](const Vec3& lo, const Vec3& hi) {
            float cell = 0;
            cells.for_each_within(lo, hi, [&](size_t i) { cell = std::max(cell, sigma_t(i)); });
            return scale * cell;
        });
    }
    std::string type() const override { return "rgbgrid"; }

private:
    MediumProperties at_unit(const Vec3& u) const override {
        MediumProperties props{m_sigma_a.empty() ? RGB(1.f) : m_sigma_a.lookup(u),
                               m_sigma_s.empty() ? RGB(1.f) : m_sigma_s.lookup(u), RGB()};
        props.sigma_a *= m_scale;
        props.sigma_s *= m_scale;
        if (m_emits) props.Le = m_Le.lookup(u) * m_le_scale;
        return props;
    }
    Grid<RGB> m_sigma_a, m_sigma_s, m_Le;
    float m_scale, m_le_scale;
};

// pbrt-v4's "cloud": a procedural cloud in the box [p0, p1] of medium space, its density a sum of
// five octaves of Perlin noise at "frequency" times the point (moved about by the noise's gradient
// where "wispiness" > 0), thinning with height above y = 0 and filling in below y = 0.5, clamped
// to [0, 1]; sigma_a and sigma_s times that density.
class CloudMedium final : public BoxMedium {
public:
    CloudMedium(const Transform& medium_to_world, const Vec3& p0, const Vec3& p1,
                const RGB& sigma_a, const RGB& sigma_s, float g, float density, float wispiness,
                float frequency)
        : BoxMedium(medium_to_world, p0, p1, g),
          m_p0(p0),
          m_p1(p1),
          m_sigma_a(sigma_a),
          m_sigma_s(sigma_s),
          m_density(density),
          m_wispiness(wispiness),
          m_frequency(frequency) {
        m_sigma_maj = (sigma_a + sigma_s).max_component();  // the density is at most 1
    }
    std::string type() const override { return "cloud"; }

private:
    MediumProperties at_unit(const Vec3& u) const override {
        const Vec3 p(m_p0.x + u.x * (m_p1.x - m_p0.x), m_p0.y + u.y * (m_p1.y - m_p0.y),
                     m_p0.z + u.z * (m_p1.z - m_p0.z));
        const float d = density(p);
        return {m_sigma_a * d, m_sigma_s * d, RGB()};
    }
    float density(const Vec3& p) const {
        Vec3 pp = p * m_frequency;
        if (m_wispiness > 0) {
            float omega = 0.05f * m_wispiness, lambda = 10;
            for (int i = 0; i < 2; ++i) {
                pp = pp + perlin_noise_gradient(pp * lambda) * omega;
                omega *= 0.5f;
                lambda *= 1.99f;
            }
        }
        float d = 0, omega = 0.5f, lambda = 1;
        for (int i = 0; i < 5; ++i) {
            d += omega * perlin_noise(pp * lambda);
            omega *= 0.5f;
            lambda *= 1.99f;
        }
        d = std::clamp((1 - p.y) * 4.5f * m_density * d, 0.f, 1.f);
        d += 2 * std::max(0.f, 0.5f - p.y);
        return std::clamp(d, 0.f, 1.f);
    }
    Vec3 m_p0, m_p1;
    RGB m_sigma_a, m_sigma_s;
    float m_density, m_wispiness, m_frequency;
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

// The box of a grid medium: "p0" below "p1" on every axis.
std::pair<Vec3, Vec3> grid_box(const ParameterList& params, const char* type, const FileLoc& loc) {
    const Vec3 p0 = params.get_point3("p0").value_or(Vec3(0, 0, 0));
    const Vec3 p1 = params.get_point3("p1").value_or(Vec3(1, 1, 1));
    if (!(p0.x < p1.x && p0.y < p1.y && p0.z < p1.z))
        throw_input_error(loc, "medium \"{}\": \"p0\" must be below \"p1\" on every axis", type);
    return {p0, p1};
}

std::unique_ptr<Medium> create_rgb_grid(const ParameterList& params,
                                        const Transform& medium_to_world, const FileLoc& loc) {
    const std::vector<RGB> sigma_a = params.get_rgbs("sigma_a"),
                           sigma_s = params.get_rgbs("sigma_s"), Le = params.get_rgbs("Le");
    if (sigma_a.empty() && sigma_s.empty())
        throw_input_error(loc,
                          "medium \"rgbgrid\": needs \"rgb sigma_a\" or \"rgb sigma_s\" values");
    const size_t n = sigma_a.empty() ? sigma_s.size() : sigma_a.size();
    if (!sigma_a.empty() && !sigma_s.empty() && sigma_s.size() != n)
        throw_input_error(loc,
                          "medium \"rgbgrid\": {} \"sigma_a\" values but {} \"sigma_s\" values",
                          sigma_a.size(), sigma_s.size());
    if (!Le.empty() && sigma_a.empty())
        throw_input_error(loc, "medium \"rgbgrid\": \"Le\" needs \"sigma_a\" values too");
    if (!Le.empty() && Le.size() != n)
        throw_input_error(loc, "medium \"rgbgrid\": {} \"Le\" values where there are {} cells",
                          Le.size(), n);
    const int nx = params.get_int("nx", 1), ny = params.get_int("ny", 1),
              nz = params.get_int("nz", 1);
    if (nx < 1 || ny < 1 || nz < 1 || size_t(nx) * size_t(ny) * size_t(nz) != n)
        throw_input_error(loc, "medium \"rgbgrid\": {} values where nx * ny * nz = {} x {} x {}", n,
                          nx, ny, nz);
    for (const auto* v : {&sigma_a, &sigma_s, &Le})
        for (const RGB& c : *v) check_non_negative(c, "rgbgrid values", loc);
    const float scale = params.get_float("scale", 1), le_scale = params.get_float("Lescale", 1);
    if (!(scale >= 0) || !(le_scale >= 0))
        throw_input_error(loc, "medium \"rgbgrid\": \"scale\" and \"Lescale\" must be >= 0");
    const float g = checked_g(params, loc);
    const auto [p0, p1] = grid_box(params, "rgbgrid", loc);
    auto grid = [&](const std::vector<RGB>& v) {
        return v.empty() ? Grid<RGB>() : Grid<RGB>(v, nx, ny, nz);
    };
    return std::make_unique<RgbGridMedium>(medium_to_world, p0, p1, grid(sigma_a), grid(sigma_s),
                                           scale, grid(Le), le_scale, g);
}

std::unique_ptr<Medium> create_cloud(const ParameterList& params, const Transform& medium_to_world,
                                     const FileLoc& loc) {
    const RGB sigma_a = medium_rgb(params, "sigma_a", RGB(1.f)),
              sigma_s = medium_rgb(params, "sigma_s", RGB(1.f));
    check_non_negative(sigma_a, "sigma_a", loc);
    check_non_negative(sigma_s, "sigma_s", loc);
    const float density = params.get_float("density", 1),
                wispiness = params.get_float("wispiness", 1),
                frequency = params.get_float("frequency", 5);
    if (!(density >= 0) || !std::isfinite(density) || !(wispiness >= 0) ||
        !std::isfinite(wispiness) || !std::isfinite(frequency))
        throw_input_error(loc,
                          "medium \"cloud\": \"density\" and \"wispiness\" must be finite and "
                          ">= 0, \"frequency\" finite");
    const float g = checked_g(params, loc);
    const auto [p0, p1] = grid_box(params, "cloud", loc);
    return std::make_unique<CloudMedium>(medium_to_world, p0, p1, sigma_a, sigma_s, g, density,
                                         wispiness, frequency);
}

}  // namespace

std::unique_ptr<Medium> create_medium(const std::string& type, const ParameterList& params,
                                      const Transform& medium_to_world, const std::string& base_dir,
                                      const FileLoc& loc) {
    if (type == "nanovdb") return create_nanovdb_medium(params, medium_to_world, base_dir, loc);
    if (type != "homogeneous" && type != "uniformgrid" && type != "rgbgrid" && type != "cloud")
        throw_input_error(loc, "unknown medium type \"{}\"", type);
    if (type == "rgbgrid") return create_rgb_grid(params, medium_to_world, loc);
    if (type == "cloud") return create_cloud(params, medium_to_world, loc);
    const float scale = params.get_float("scale", 1);
    RGB sigma_a = medium_rgb(params, "sigma_a", RGB(1.f)) * scale;
    RGB sigma_s = medium_rgb(params, "sigma_s", RGB(1.f)) * scale;
    // pbrt-v4 reads "preset" for homogeneous media only (elsewhere it is an unused parameter).
    if (type == "homogeneous" && params.has("preset")) {
        const Param* p = params.find("preset");
        const std::string name = params.get_string("preset", "");
        const auto preset = scattering_preset(name);
        if (!preset)
            throw_input_error(p->loc, "medium: unknown \"preset\" \"{}\" (pbrt-v4's are {})", name,
                              scattering_preset_names());
        if (params.has("sigma_a") || params.has("sigma_s"))
            throw_input_error(p->loc,
                              "medium: \"preset\" gives sigma_a and sigma_s; leave out "
                              "\"sigma_a\" and \"sigma_s\"");
        sigma_a = preset->sigma_a * scale;
        sigma_s = preset->sigma_s * scale;
    }
    check_non_negative(sigma_a, "sigma_a", loc);
    check_non_negative(sigma_s, "sigma_s", loc);
    const float g = checked_g(params, loc);
    const RGB Le = medium_rgb(params, "Le", RGB());
    check_non_negative(Le, "Le", loc);
    if (type == "homogeneous") {
        const float le_scale = params.get_float("Lescale", 1);
        return std::make_unique<HomogeneousMedium>(sigma_a, sigma_s, Le * le_scale, g);
    }
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
    Grid<float> le_grid({1.f}, 1, 1, 1);
    if (!le_scale.empty()) {
        if (le_scale.size() != density.size())
            throw_input_error(loc,
                              "medium \"uniformgrid\": {} \"Lescale\" values where the density "
                              "has {}",
                              le_scale.size(), density.size());
        le_grid = Grid<float>(le_scale, nx, ny, nz);
    }
    // Emission from a blackbody at each cell's temperature (not with "Le").
    const std::vector<float> temperature = params.get_floats("temperature");
    const float offset =
                    params.get_float("temperatureoffset", params.get_float("temperaturecutoff", 0)),
                t_scale = params.get_float("temperaturescale", 1);
    Grid<float> t_grid;
    BlackbodyTable blackbody;
    if (!temperature.empty()) {
        if (params.has("Le"))
            throw_input_error(params.find("Le")->loc,
                              "medium \"uniformgrid\": both \"Le\" and \"temperature\" given");
        if (temperature.size() != density.size())
            throw_input_error(params.find("temperature")->loc,
                              "medium \"uniformgrid\": {} \"temperature\" values where the "
                              "density has {}",
                              temperature.size(), density.size());
        const auto [lo, hi] = std::minmax_element(temperature.begin(), temperature.end());
        blackbody = BlackbodyTable(offset, t_scale, *lo, *hi);
        t_grid = Grid<float>(temperature, nx, ny, nz);
    }
    const auto [p0, p1] = grid_box(params, "uniformgrid", loc);
    return std::make_unique<GridMedium>(medium_to_world, p0, p1, Grid<float>(density, nx, ny, nz),
                                        sigma_a, sigma_s, Le, std::move(le_grid), g,
                                        std::move(t_grid), std::move(blackbody));
}

std::unique_ptr<Medium> make_homogeneous_medium(const RGB& sigma_a, const RGB& sigma_s, float g) {
    return std::make_unique<HomogeneousMedium>(sigma_a, sigma_s, RGB(), g);
}

}  // namespace ml
