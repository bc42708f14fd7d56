#include "integrators/settings.h"

#include <charconv>

namespace ml {

Settings::Settings(std::string integrator, const ParameterList* scene_params,
                   std::map<std::string, std::string> overrides)
    : m_integrator(std::move(integrator)), m_scene(scene_params) {
    for (auto& [key, value] : overrides) {
        std::string prefix = m_integrator + ".";
        if (key.rfind(prefix, 0) != 0)
            throw UsageError("--set " + key + ": settings of integrator \"" + m_integrator +
                             "\" are named " + prefix + "KEY");
        m_overrides[key.substr(prefix.size())] = value;
        m_used[key.substr(prefix.size())] = false;
    }
}

const std::string* Settings::override_for(const std::string& key) const {
    auto it = m_overrides.find(key);
    if (it == m_overrides.end()) return nullptr;
    m_used[key] = true;
    // The command line wins; the scene's value of the same setting counts as read.
    if (m_scene) m_scene->find(key);
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

int Settings::get_int(const std::string& key, int def) const {
    if (const std::string* s = override_for(key))
        return parse_number<int>(m_integrator + "." + key, *s);
    return m_scene ? m_scene->get_int(key, def) : def;
}

float Settings::get_float(const std::string& key, float def) const {
    if (const std::string* s = override_for(key)) {
        float v = parse_number<float>(m_integrator + "." + key, *s);
        if (!std::isfinite(v))
            throw UsageError("--set " + m_integrator + "." + key + ": not finite");
        return v;
    }
    return m_scene ? m_scene->get_float(key, def) : def;
}

bool Settings::get_bool(const std::string& key, bool def) const {
    if (const std::string* s = override_for(key)) {
        if (*s == "true" || *s == "1") return true;
        if (*s == "false" || *s == "0") return false;
        throw UsageError("--set " + m_integrator + "." + key + "=" + *s + ": not true or false");
    }
    return m_scene ? m_scene->get_bool(key, def) : def;
}

std::string Settings::get_string(const std::string& key, const std::string& def) const {
    if (const std::string* s = override_for(key)) return *s;
    return m_scene ? m_scene->get_string(key, def) : def;
}

void Settings::check_unused() const {
    for (auto& [key, used] : m_used)
        if (!used)
            throw UsageError("--set " + m_integrator + "." + key + ": integrator \"" +
                             m_integrator + "\" has no such setting");
    if (m_scene) m_scene->check_unused();
}

}  // namespace ml
