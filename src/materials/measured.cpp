#include "materials/measured.h"

#include <algorithm>
#include <cmath>

#include "core/spectrum.h"
#include "materials/bxdfs.h"
#include "materials/tensor_file.h"

namespace ml {

namespace {

// The unit-square coordinates of the file's parameterisation: u = sqrt(theta / (pi / 2)), and phi
// from -pi to pi.
float theta_to_u(float theta) { return std::sqrt(std::max(0.f, theta) * (2 / kPi)); }
float phi_to_u(float phi) { return phi * (0.5f / kPi) + 0.5f; }
float u_to_theta(float u) { return u * u * (kPi / 2); }
float u_to_phi(float u) { return (2 * u - 1) * kPi; }

// atan2 rather than acos: precise near the pole, where u = sqrt(theta) magnifies any error.
float spherical_theta(const Vec3& w) { return std::atan2(std::sqrt(w.x * w.x + w.y * w.y), w.z); }
float spherical_phi(const Vec3& w) { return std::atan2(w.y, w.x); }

// The fields of a .bsdf file that the material reads, checked as pbrt-v4 checks them and more
// (values finite, parameters increasing, grids of 2 x 2 or more).
class Fields {
public:
    Fields(const std::string& path, const FileLoc& loc)
        : m_path(path), m_loc(loc), m_fields(read_tensor_file(path, loc)) {}

    const TensorField& get(const std::string& name, TensorField::Type type, size_t ndim) const {
        auto it = m_fields.find(name);
        if (it == m_fields.end())
            throw_input_error(m_loc, "measured: \"{}\" has no field \"{}\"", m_path, name);
        if (it->second.type != type || it->second.shape.size() != ndim)
            throw_input_error(m_loc, "measured: \"{}\": field \"{}\" is not a {}-dimensional {}",
                              m_path, name, ndim,
                              type == TensorField::Float32 ? "float32 array" : "byte array");
        return it->second;
    }
    // A Float32 field's values, each finite and at least `lowest`.
    std::vector<float> floats(const std::string& name, size_t ndim, float lowest) const {
        std::vector<float> v = get(name, TensorField::Float32, ndim).floats();
        for (float x : v)
            if (!std::isfinite(x) || x < lowest)
                fail("field \"{}\" holds {}, where finite values of at least {} are read", name, x,
                     lowest);
        return v;
    }
    // A parameter's values: increasing, at least one.
    std::vector<float> parameter(const std::string& name) const {
        std::vector<float> v = floats(name, 1, -1e30f);
        if (v.empty()) fail("field \"{}\" is empty", name);
        for (size_t i = 1; i < v.size(); ++i)
            if (!(v[i] > v[i - 1])) fail("field \"{}\" does not increase", name);
        return v;
    }
    template <typename... Args>
    [[noreturn]] void fail(fmt::format_string<Args...> f, Args&&... args) const {
        throw_input_error(m_loc, "measured: \"{}\": {}", m_path,
                          fmt::format(f, std::forward<Args>(args)...));
    }

private:
    std::string m_path;
    FileLoc m_loc;
    std::map<std::string, TensorField> m_fields;
};

// What a spectrum's value at each of the file's wavelengths adds to its sRGB colour under D65,
// with the spectrum linear between wavelengths and constant beyond the ends (as pbrt-v4 reads it).
std::vector<RGB> wavelength_weights(const std::vector<float>& nm) {
    std::vector<RGB> w(nm.size());
    for (size_t k = 0; k < nm.size(); ++k) {
        w[k] = reflectance_srgb([&](double l) {
            if (nm.size() == 1) return 1.0;
            if (l <= nm.front()) return k == 0 ? 1.0 : 0.0;
            if (l >= nm.back()) return k + 1 == nm.size() ? 1.0 : 0.0;
            if (k > 0 && l >= nm[k - 1] && l <= nm[k]) return (l - nm[k - 1]) / (nm[k] - nm[k - 1]);
            if (k + 1 < nm.size() && l >= nm[k] && l <= nm[k + 1])
                return (nm[k + 1] - l) / (nm[k + 1] - nm[k]);
            return 0.0;
        });
    }
    return w;
}

}  // namespace

std::shared_ptr<const MeasuredBrdf> load_measured_brdf(const std::string& path,
                                                       const FileLoc& loc) {
    Fields f(path, loc);
    f.get("description", TensorField::UInt8, 1);
    if (f.get("jacobian", TensorField::UInt8, 1).shape[0] != 1)
        f.fail("field \"jacobian\" is not one byte");
    const std::vector<float> theta_i = f.parameter("theta_i"), phi_i = f.parameter("phi_i");
    const std::vector<float> nm = f.parameter("wavelengths");
    const auto& ndf_shape = f.get("ndf", TensorField::Float32, 2).shape;
    const auto& sigma_shape = f.get("sigma", TensorField::Float32, 2).shape;
    const auto& vndf_shape = f.get("vndf", TensorField::Float32, 4).shape;
    const auto& lum_shape = f.get("luminance", TensorField::Float32, 4).shape;
    const auto& spec_shape = f.get("spectra", TensorField::Float32, 5).shape;
    const size_t n_phi = phi_i.size(), n_theta = theta_i.size();
    for (const auto* s : {&ndf_shape, &sigma_shape})
        if ((*s)[0] < 2 || (*s)[1] < 2) f.fail("\"ndf\" and \"sigma\" need 2 x 2 values or more");
    if (vndf_shape[0] != n_phi || vndf_shape[1] != n_theta || vndf_shape[2] < 2 ||
        vndf_shape[3] < 2)
        f.fail("\"vndf\" is not one grid of 2 x 2 or more per (phi_i, theta_i)");
    if (lum_shape[0] != n_phi || lum_shape[1] != n_theta || lum_shape[2] < 2 || lum_shape[3] < 2)
        f.fail("\"luminance\" is not one grid of 2 x 2 or more per (phi_i, theta_i)");
    if (spec_shape[0] != n_phi || spec_shape[1] != n_theta || spec_shape[2] != nm.size() ||
        spec_shape[3] != lum_shape[2] || spec_shape[4] != lum_shape[3])
        f.fail("\"spectra\" does not match \"luminance\" per wavelength");

    auto brdf = std::make_shared<MeasuredBrdf>();
    brdf->isotropic = n_phi <= 2;
    if (!brdf->isotropic && std::lrint(2 * kPi / (phi_i.back() - phi_i.front())) != 1)
        f.fail(
            "phi_i spans less than a full turn (a reduced, symmetric table), which pbrt-v4 "
            "does not read either");
    brdf->ndf =
        PiecewiseLinear2D(f.floats("ndf", 2, 0), int(ndf_shape[1]), int(ndf_shape[0]), {}, false);
    std::vector<float> sigma = f.floats("sigma", 2, 0);
    if (std::any_of(sigma.begin(), sigma.end(), [](float s) { return !(s > 0); }))
        f.fail("field \"sigma\" holds zero, where projected areas are positive");
    brdf->sigma = PiecewiseLinear2D(sigma, int(sigma_shape[1]), int(sigma_shape[0]), {}, false);

    // The two warps: densities, so each (phi_i, theta_i) grid must hold something.
    auto warp = [&](const char* name, const std::vector<size_t>& shape) {
        std::vector<float> v = f.floats(name, 4, 0);
        const size_t per = shape[2] * shape[3];
        for (size_t s = 0; s < n_phi * n_theta; ++s)
            if (std::all_of(v.begin() + ptrdiff_t(s * per), v.begin() + ptrdiff_t((s + 1) * per),
                            [](float x) { return x == 0; }))
                f.fail("field \"{}\" has a grid of zeros", name);
        return PiecewiseLinear2D(v, int(shape[3]), int(shape[2]), {phi_i, theta_i}, true);
    };
    brdf->vndf = warp("vndf", vndf_shape);
    brdf->luminance = warp("luminance", lum_shape);

    // The spectra, as linear sRGB per point of the luminance warp's grids.
    const std::vector<float> spectra = f.floats("spectra", 5, -1e30f);
    const std::vector<RGB> weights = wavelength_weights(nm);
    const size_t per = spec_shape[3] * spec_shape[4], slices = n_phi * n_theta;
    std::vector<float> rgb[3];
    for (auto& c : rgb) c.assign(slices * per, 0.f);
    for (size_t s = 0; s < slices; ++s)
        for (size_t k = 0; k < nm.size(); ++k)
            for (size_t i = 0; i < per; ++i) {
                const float v = std::max(0.f, spectra[(s * nm.size() + k) * per + i]);
                for (int c = 0; c < 3; ++c) rgb[c][s * per + i] += v * weights[k][c];
            }
    for (int c = 0; c < 3; ++c) {
        for (float& v : rgb[c]) v = std::max(0.f, v);
        brdf->rgb[c] = PiecewiseLinear2D(rgb[c], int(spec_shape[4]), int(spec_shape[3]),
                                         {phi_i, theta_i}, false);
    }
    return brdf;
}

namespace {

// The tables' coordinates of wo and of the half vector wm (wo, wm on the +z side).
struct MeasuredCoords {
    float params[2];  // phi_o, theta_o: the warps' parameters
    Vec2 u_wo, u_wm;
};

MeasuredCoords coords(const MeasuredBrdf& b, const Vec3& wo, const Vec3& wm) {
    MeasuredCoords c;
    const float theta_o = spherical_theta(wo), phi_o = spherical_phi(wo);
    c.params[0] = phi_o, c.params[1] = theta_o;
    c.u_wo = Vec2(theta_to_u(theta_o), phi_to_u(phi_o));
    float phi_m = spherical_phi(wm);
    if (b.isotropic) phi_m -= phi_o;
    float y = phi_to_u(phi_m);
    c.u_wm = Vec2(theta_to_u(spherical_theta(wm)), y - std::floor(y));
    return c;
}

RGB spectrum_at(const MeasuredBrdf& b, Vec2 u, std::span<const float> params) {
    return RGB(std::max(0.f, b.rgb[0].eval(u, params)), std::max(0.f, b.rgb[1].eval(u, params)),
               std::max(0.f, b.rgb[2].eval(u, params)));
}

// d(omega_m) / d(u_wm) = 2 pi^2 u sin(theta_m), times 4 (wo . wm) from wm to wi, as pbrt-v4
// bounds it away from zero.
float half_vector_jacobian(float u_x, float sin_m, float cos_om) {
    return 4 * cos_om * std::max(2 * kPi * kPi * u_x * sin_m, 1e-6f);
}

}  // namespace

RGB MeasuredBxdf::eval(const Vec3& wo_in, const Vec3& wi_in, TransportMode) const {
    if (!same_hemisphere(wo_in, wi_in)) return RGB();
    const Vec3 wo = wo_in.z < 0 ? -wo_in : wo_in, wi = wo_in.z < 0 ? -wi_in : wi_in;
    const Vec3 h = wo + wi;
    if (length_squared(h) == 0) return RGB();
    const MeasuredCoords c = coords(*m_brdf, wo, normalize(h));
    const PiecewiseLinear2D::Point ui = m_brdf->vndf.invert(c.u_wm, c.params);
    return spectrum_at(*m_brdf, ui.p, c.params) *
           (m_brdf->ndf.eval(c.u_wm, {}) / (4 * m_brdf->sigma.eval(c.u_wo, {}) * wi.z));
}

std::optional<BsdfSample> MeasuredBxdf::sample(const Vec3& wo_in, float, const Vec2& u,
                                               TransportMode) const {
    const bool flip = wo_in.z < 0;
    const Vec3 wo = flip ? -wo_in : wo_in;
    if (wo.z == 0) return std::nullopt;
    const float theta_o = spherical_theta(wo), phi_o = spherical_phi(wo);
    const float params[2] = {phi_o, theta_o};
    const PiecewiseLinear2D::Point lum = m_brdf->luminance.sample(u, params);
    const PiecewiseLinear2D::Point vn = m_brdf->vndf.sample(lum.p, params);
    const float theta_m = u_to_theta(vn.p.x);
    const float phi_m = u_to_phi(vn.p.y) + (m_brdf->isotropic ? phi_o : 0.f);
    const float sin_m = std::sin(theta_m);
    const Vec3 wm(sin_m * std::cos(phi_m), sin_m * std::sin(phi_m), std::cos(theta_m));
    const float cos_om = dot(wo, wm);
    const Vec3 wi = reflect(wo, wm);
    if (!(cos_om > 0) || !(wi.z > 0)) return std::nullopt;
    const Vec2 u_wo(theta_to_u(theta_o), phi_to_u(phi_o));
    BsdfSample s;
    s.f = spectrum_at(*m_brdf, lum.p, params) *
          (m_brdf->ndf.eval(vn.p, {}) / (4 * m_brdf->sigma.eval(u_wo, {}) * wi.z));
    s.pdf_solid_angle = vn.pdf * lum.pdf / half_vector_jacobian(vn.p.x, sin_m, cos_om);
    s.wi = flip ? -wi : wi;
    s.flags = kBxdfGlossyReflection;
    return s;
}

float MeasuredBxdf::pdf_solid_angle(const Vec3& wo_in, const Vec3& wi_in, TransportMode) const {
    if (!same_hemisphere(wo_in, wi_in)) return 0;
    const Vec3 wo = wo_in.z < 0 ? -wo_in : wo_in, wi = wo_in.z < 0 ? -wi_in : wi_in;
    const Vec3 h = wo + wi;
    if (length_squared(h) == 0) return 0;
    const Vec3 wm = normalize(h);
    const MeasuredCoords c = coords(*m_brdf, wo, wm);
    const PiecewiseLinear2D::Point ui = m_brdf->vndf.invert(c.u_wm, c.params);
    const float lum = m_brdf->luminance.eval(ui.p, c.params);
    const float sin_m = std::sqrt(wm.x * wm.x + wm.y * wm.y);
    return ui.pdf * lum / half_vector_jacobian(c.u_wm.x, sin_m, dot(wo, wm));
}

RGB MeasuredBxdf::max_value_bound(const Vec3& wo_in, const DirectionCone& cone) const {
    // Reflection only: nothing when the cone stays on the other side.
    const Vec3 side(0, 0, wo_in.z < 0 ? -1.f : 1.f);
    if (max_cos(cone, side) <= 0) return RGB();
    const Vec3 wo = wo_in.z < 0 ? -wo_in : wo_in;
    const Vec2 u_wo(theta_to_u(spherical_theta(wo)), phi_to_u(spherical_phi(wo)));
    const float scale = m_brdf->ndf.max_value() / (4 * m_brdf->sigma.eval(u_wo, {}));
    return RGB(m_brdf->rgb[0].max_value(), m_brdf->rgb[1].max_value(), m_brdf->rgb[2].max_value()) *
           scale;
}

Bsdf MeasuredMaterial::get_bsdf(const SurfaceInteraction& si, ScratchBuffer& scratch) const {
    return Bsdf(frame(si), si.ng, scratch_new<MeasuredBxdf>(scratch, m_brdf.get()));
}

}  // namespace ml
