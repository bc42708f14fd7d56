#include "render/settings.h"

#include <fmt/format.h>

#include <charconv>
#include <cmath>

namespace ml {

Settings::Settings(std::string integrator, const ParameterList* scene_params,
                   std::map<std::string, std::string> overrides)
    : m_integrator(std::move(integrator)),
      m_scene(scene_params),
      m_overrides(std::move(overrides)) {
    for (auto& [key, value] : m_overrides) {
        if (key.find('.') == std::string::npos)
            throw UsageError("--set " + key + ": settings are named INTEGRATOR.KEY or GROUP.KEY");
        m_used[key] = false;
    }
}

const std::string* Settings::override_for(const std::string& key) const {
    std::string name = full_name(key);
    auto it = m_overrides.find(name);
    if (it == m_overrides.end()) return nullptr;
    m_used[name] = true;
    // The command line wins; the scene's value of the same setting counts as read.
    if (const ParameterList* scene = scene_for(key)) scene->find(key);
    return &it->second;
}

namespace {

template <typename T>
T parse_number(const std::string& name, const std::string& s) {
    T v{};
    auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || ptr != s.data() + s.size())
        throw UsageError("--set " + name + "=" + s + ": not a number");
    return v;
}

}  // namespace

bool Settings::has(const std::string& key) const {
    if (m_overrides.count(full_name(key))) return true;
    const ParameterList* scene = scene_for(key);
    return scene && scene->has(key);
}

void Settings::record(const std::string& key, const char* type, std::string value,
                      const SettingDoc& doc) const {
    if (!m_record) return;
    SettingDefault entry{full_name(key), type, std::move(value), doc.range, doc.text};
    for (SettingDefault& d : *m_record)
        if (d.key == entry.key) {
            // A second read without a description (a check of another integrator's setting)
            // keeps the first one's.
            if (entry.description.empty()) {
                entry.range = d.range;
                entry.description = d.description;
            }
            d = std::move(entry);
            return;
        }
    m_record->push_back(std::move(entry));
}

int Settings::get_int(const std::string& key, int def, const SettingDoc& doc) const {
    record(key, "int", std::to_string(def), doc);
    if (const std::string* s = override_for(key)) return parse_number<int>(full_name(key), *s);
    const ParameterList* scene = scene_for(key);
    return scene ? scene->get_int(key, def) : def;
}

float Settings::get_float(const std::string& key, float def, const SettingDoc& doc) const {
    record(key, "float", fmt::format("{}", def),
           doc);  // the shortest text that reads back as `def`
    if (const std::string* s = override_for(key)) {
        float v = parse_number<float>(full_name(key), *s);
        if (!std::isfinite(v)) throw UsageError("--set " + full_name(key) + ": not finite");
        return v;
    }
    const ParameterList* scene = scene_for(key);
    return scene ? scene->get_float(key, def) : def;
}

bool Settings::get_bool(const std::string& key, bool def, const SettingDoc& doc) const {
    record(key, "bool", def ? "true" : "false", doc);
    if (const std::string* s = override_for(key)) {
        if (*s == "true" || *s == "1") return true;
        if (*s == "false" || *s == "0") return false;
        throw UsageError("--set " + full_name(key) + "=" + *s + ": not true or false");
    }
    const ParameterList* scene = scene_for(key);
    return scene ? scene->get_bool(key, def) : def;
}

std::string Settings::get_string(const std::string& key, const std::string& def,
                                 const SettingDoc& doc) const {
    record(key, "string", def, doc);
    if (const std::string* s = override_for(key)) return *s;
    const ParameterList* scene = scene_for(key);
    return scene ? scene->get_string(key, def) : def;
}

void Settings::check_unused() const {
    for (auto& [key, used] : m_used)
        if (!used)
            throw UsageError("--set " + key + ": integrator \"" + m_integrator +
                             "\" has no such setting");
    if (m_scene) m_scene->check_unused();
}

}  // namespace ml
