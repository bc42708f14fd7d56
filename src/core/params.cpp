#include "core/params.h"

#include <cstring>
#include <map>

#include "core/spectrum.h"

namespace ml {

void ParameterList::add(Param p) {
    for (const Param& q : m_params)
        if (q.name == p.name) throw_input_error(p.loc, "parameter \"{}\" given twice", p.name);
    m_params.push_back(std::move(p));
}

const Param* ParameterList::find(const std::string& name) const {
    for (const Param& p : m_params)
        if (p.name == name) {
            p.looked_up = true;
            return &p;
        }
    return nullptr;
}

bool ParameterList::has(const std::string& name) const {
    for (const Param& p : m_params)
        if (p.name == name) return true;
    return false;
}

const Param* ParameterList::find_typed(const std::string& name,
                                       std::initializer_list<const char*> types,
                                       const char* wanted) const {
    const Param* p = find(name);
    if (!p) return nullptr;
    for (const char* t : types)
        if (p->type == t) return p;
    throw_input_error(p->loc, "parameter \"{}\" has type \"{}\", expected {}", name, p->type,
                      wanted);
}

namespace {

void expect_count(const Param& p, size_t n, size_t got) {
    if (got != n)
        throw_input_error(p.loc, "parameter \"{} {}\" needs {} value{}, got {}", p.type, p.name, n,
                          n == 1 ? "" : "s", got);
}

void expect_multiple(const Param& p, size_t n, size_t got) {
    if (got % n != 0)
        throw_input_error(p.loc, "parameter \"{} {}\" needs a multiple of {} values, got {}",
                          p.type, p.name, n, got);
}

void expect_finite(const Param& p) {
    for (double v : p.numbers)
        if (!std::isfinite(v))
            throw_input_error(p.loc, "parameter \"{}\" holds a non-finite value", p.name);
}

}  // namespace

float ParameterList::get_float(const std::string& name, float def) const {
    const Param* p = find_typed(name, {"float"}, "float");
    if (!p) return def;
    expect_count(*p, 1, p->numbers.size());
    expect_finite(*p);
    return float(p->numbers[0]);
}

int ParameterList::get_int(const std::string& name, int def) const {
    const Param* p = find_typed(name, {"integer"}, "integer");
    if (!p) return def;
    expect_count(*p, 1, p->numbers.size());
    return int(p->numbers[0]);
}

bool ParameterList::get_bool(const std::string& name, bool def) const {
    const Param* p = find_typed(name, {"bool"}, "bool");
    if (!p) return def;
    expect_count(*p, 1, p->bools.size());
    return p->bools[0];
}

std::string ParameterList::get_string(const std::string& name, const std::string& def) const {
    const Param* p = find_typed(name, {"string"}, "string");
    if (!p) return def;
    expect_count(*p, 1, p->strings.size());
    return p->strings[0];
}

std::optional<Vec3> ParameterList::get_point3(const std::string& name) const {
    const Param* p =
        find_typed(name, {"point3", "point", "vector3", "vector", "normal", "normal3"}, "point3");
    if (!p) return std::nullopt;
    expect_count(*p, 3, p->numbers.size());
    expect_finite(*p);
    return Vec3(float(p->numbers[0]), float(p->numbers[1]), float(p->numbers[2]));
}

std::vector<RGB> ParameterList::get_rgbs(const std::string& name) const {
    const Param* p = find_typed(name, {"rgb", "color"}, "rgb");
    if (!p) return {};
    if (p->numbers.empty() || p->numbers.size() % 3 != 0)
        throw_input_error(p->loc, "parameter \"rgb {}\": {} values, not a positive multiple of 3",
                          name, p->numbers.size());
    expect_finite(*p);
    std::vector<RGB> out;
    for (size_t i = 0; i < p->numbers.size(); i += 3)
        out.emplace_back(float(p->numbers[i]), float(p->numbers[i + 1]), float(p->numbers[i + 2]));
    return out;
}

std::optional<RGB> ParameterList::get_rgb(const std::string& name) const {
    const Param* p = find_typed(name, {"rgb", "color", "spectrum", "blackbody"}, "rgb");
    if (!p) return std::nullopt;
    if (p->type == "rgb" || p->type == "color") {
        expect_count(*p, 3, p->numbers.size());
        expect_finite(*p);
        return RGB(float(p->numbers[0]), float(p->numbers[1]), float(p->numbers[2]));
    }
    if (p->type == "blackbody") {
        expect_count(*p, 1, p->numbers.size());
        expect_finite(*p);
        return blackbody_rgb(float(p->numbers[0]));
    }
    // spectrum: one named spectrum, or a constant value.
    if (p->strings.size() == 1 && p->numbers.empty()) {
        auto rgb = named_spectrum_rgb(p->strings[0]);
        if (!rgb) throw_input_error(p->loc, "unknown named spectrum \"{}\"", p->strings[0]);
        return rgb;
    }
    if (p->numbers.size() == 1 && p->strings.empty()) {
        expect_finite(*p);
        return RGB(float(p->numbers[0]));
    }
    throw_input_error(p->loc,
                      "parameter \"spectrum {}\": only named spectra and constants are supported "
                      "(manylight renders in RGB)",
                      name);
}

std::string ParameterList::get_texture(const std::string& name) const {
    const Param* p = find_typed(name, {"texture"}, "texture");
    if (!p) return "";
    expect_count(*p, 1, p->strings.size());
    return p->strings[0];
}

std::vector<float> ParameterList::get_floats(const std::string& name) const {
    const Param* p = find_typed(name, {"float"}, "float");
    if (!p) return {};
    expect_finite(*p);
    return std::vector<float>(p->numbers.begin(), p->numbers.end());
}

std::vector<int> ParameterList::get_ints(const std::string& name) const {
    const Param* p = find_typed(name, {"integer"}, "integer");
    if (!p) return {};
    std::vector<int> out;
    out.reserve(p->numbers.size());
    for (double v : p->numbers) out.push_back(int(v));
    return out;
}

std::vector<Vec2> ParameterList::get_point2s(const std::string& name) const {
    const Param* p = find_typed(name, {"point2", "vector2", "float"}, "point2");
    if (!p) return {};
    expect_multiple(*p, 2, p->numbers.size());
    expect_finite(*p);
    std::vector<Vec2> out(p->numbers.size() / 2);
    for (size_t i = 0; i < out.size(); ++i)
        out[i] = Vec2(float(p->numbers[2 * i]), float(p->numbers[2 * i + 1]));
    return out;
}

namespace {

std::vector<Vec3> vec3_array(const Param* p) {
    if (!p) return {};
    expect_multiple(*p, 3, p->numbers.size());
    expect_finite(*p);
    std::vector<Vec3> out(p->numbers.size() / 3);
    for (size_t i = 0; i < out.size(); ++i)
        out[i] = Vec3(float(p->numbers[3 * i]), float(p->numbers[3 * i + 1]),
                      float(p->numbers[3 * i + 2]));
    return out;
}

}  // namespace

std::vector<Vec3> ParameterList::get_point3s(const std::string& name) const {
    return vec3_array(find_typed(name, {"point3", "point", "vector3", "vector"}, "point3"));
}

std::vector<Vec3> ParameterList::get_normals(const std::string& name) const {
    return vec3_array(find_typed(name, {"normal", "normal3"}, "normal"));
}

std::vector<std::string> ParameterList::get_strings(const std::string& name) const {
    const Param* p = find_typed(name, {"string"}, "string");
    if (!p) return {};
    return p->strings;
}

void ParameterList::check_unused() const {
    for (const Param& p : m_params)
        if (!p.looked_up)
            throw_input_error(p.loc, "parameter \"{} {}\" is unknown or unused here", p.type,
                              p.name);
}

std::optional<RGB> named_spectrum_rgb(const std::string& name) {
    // RGB (approximately 650/550/450 nm) equivalents of pbrt-v4's tabulated spectra; the metal
    // values agree with those the shared scenes spell out as "rgb eta"/"rgb k".
    static const std::map<std::string, RGB> table = {
        {"metal-Ag-eta", RGB(0.155265f, 0.116723f, 0.138381f)},
        {"metal-Ag-k", RGB(4.828343f, 3.122246f, 2.146950f)},
        {"metal-Al-eta", RGB(1.657460f, 0.880369f, 0.521229f)},
        {"metal-Al-k", RGB(9.223869f, 6.269523f, 4.837001f)},
        {"metal-Au-eta", RGB(0.143119f, 0.374957f, 1.442479f)},
        {"metal-Au-k", RGB(3.983160f, 2.385721f, 1.603215f)},
        {"metal-Cu-eta", RGB(0.200438f, 0.924033f, 1.102212f)},
        {"metal-Cu-k", RGB(3.912949f, 2.452848f, 2.142188f)},
        {"metal-CuZn-eta", RGB(0.444f, 0.527f, 1.094f)},
        {"metal-CuZn-k", RGB(3.695f, 2.765f, 1.829f)},
        {"metal-MgO-eta", RGB(1.732f, 1.738f, 1.751f)},
        {"metal-MgO-k", RGB(0.f, 0.f, 0.f)},
        {"metal-TiO2-eta", RGB(2.540f, 2.650f, 2.890f)},
        {"metal-TiO2-k", RGB(0.f, 0.f, 0.f)},
        {"glass-BK7", RGB(1.5168f)},
        {"glass-BAF10", RGB(1.6700f)},
        {"glass-FK51A", RGB(1.4866f)},
        {"glass-LASF9", RGB(1.8503f)},
        {"glass-F5", RGB(1.6034f)},
        {"glass-F10", RGB(1.6200f)},
        {"glass-F11", RGB(1.6209f)},
    };
    auto it = table.find(name);
    if (it == table.end()) return std::nullopt;
    return it->second;
}

namespace {

// Planck's law: spectral radiance of a blackbody at `kelvin`, wavelength in nm.
double planck(double lambda_nm, double kelvin) {
    const double l = lambda_nm * 1e-9, c = 299792458.0, h = 6.62606957e-34, kb = 1.3806488e-23;
    return (2 * h * c * c) / (std::pow(l, 5) * (std::exp((h * c) / (l * kb * kelvin)) - 1));
}

}  // namespace

RGB blackbody_rgb(float kelvin) {
    RGB rgb = clamp_zero(emission_srgb([&](double l) { return planck(l, kelvin); }));
    float m = rgb.max_component();
    return m > 0 ? rgb / m : RGB();
}

RGB blackbody_radiance_rgb(float kelvin) {
    if (!(kelvin > 0)) return RGB();
    // pbrt-v4's BlackbodySpectrum: Planck's law over its value at the peak (Wien's law).
    const double peak = planck(2.8977721e-3 / kelvin * 1e9, kelvin);
    return clamp_zero(emission_srgb([&](double l) { return planck(l, kelvin) / peak; }));
}

}  // namespace ml
