// Typed parameter lists of pbrt-v4 directives ("float fov" [ 45 ]), with used-tracking: every
// lookup marks its parameter, and check_unused() turns a parameter nobody asked for into an
// error at its own location (pbrt's ReportUnused, Mitsuba's unused-property errors).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/color.h"
#include "core/error.h"
#include "core/math.h"

namespace ml {

struct Param {
    std::string type;  // integer float point2 vector2 point3 vector3 normal rgb spectrum bool
                       // string texture blackbody
    std::string name;
    FileLoc loc;
    std::vector<double> numbers;
    std::vector<std::string> strings;
    std::vector<bool> bools;
    mutable bool looked_up = false;
    size_t value_count() const { return numbers.size() + strings.size() + bools.size(); }
};

class ParameterList {
public:
    ParameterList() = default;
    explicit ParameterList(FileLoc loc) : m_loc(std::move(loc)) {}

    // Adds a parameter; a second one of the same name is an error.
    void add(Param p);
    const FileLoc& loc() const { return m_loc; }
    void set_loc(FileLoc loc) { m_loc = std::move(loc); }
    bool empty() const { return m_params.empty(); }
    const std::vector<Param>& params() const { return m_params; }

    // Single values: the default when absent; an error when of another type or arity.
    float get_float(const std::string& name, float def) const;
    int get_int(const std::string& name, int def) const;
    bool get_bool(const std::string& name, bool def) const;
    std::string get_string(const std::string& name, const std::string& def) const;
    std::optional<Vec3> get_point3(const std::string& name) const;  // point3 / vector3 / normal
    // An RGB from "rgb", a single-valued or named "spectrum", or "blackbody" (normalised).
    std::optional<RGB> get_rgb(const std::string& name) const;
    // An "rgb" array of one or more triples (pbrt-v4's rgbgrid medium); empty when absent.
    std::vector<RGB> get_rgbs(const std::string& name) const;
    // The texture name of a "texture" parameter, or "" when absent.
    std::string get_texture(const std::string& name) const;

    // Arrays (empty when absent).
    std::vector<float> get_floats(const std::string& name) const;
    std::vector<int> get_ints(const std::string& name) const;
    std::vector<Vec2> get_point2s(const std::string& name) const;
    std::vector<Vec3> get_point3s(const std::string& name) const;
    std::vector<Vec3> get_normals(const std::string& name) const;
    std::vector<std::string> get_strings(const std::string& name) const;

    // The parameter of that name, marked used, or null.
    const Param* find(const std::string& name) const;
    bool has(const std::string& name) const;
    // Throws InputError at the first parameter never looked up.
    void check_unused() const;

private:
    const Param* find_typed(const std::string& name, std::initializer_list<const char*> types,
                            const char* wanted) const;
    std::vector<Param> m_params;
    FileLoc m_loc;
};

// RGB equivalents of pbrt-v4's named spectra (metal IORs, glasses); nullopt if unknown.
std::optional<RGB> named_spectrum_rgb(const std::string& name);
// Linear sRGB colour of a blackbody at `kelvin`, normalised to a maximum component of 1.
RGB blackbody_rgb(float kelvin);
// pbrt-v4's BlackbodySpectrum (Planck's law divided by its peak value) as linear sRGB, negative
// channels clamped to 0: the emission of a medium's "temperature".
RGB blackbody_radiance_rgb(float kelvin);

}  // namespace ml
