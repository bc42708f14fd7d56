// An integrator's settings: the scene's `Integrator` parameters (pbrt-v4 names) overridden by
// `--set NAME.KEY=VALUE` from the command line. Every setting must be read by the integrator,
// or check_unused() reports it (scene parameters as input errors, --set keys as usage errors).
#pragma once

#include <map>
#include <stdexcept>
#include <string>

#include "scene/params.h"

namespace ml {

// A --set key the integrator does not know, or a value that does not parse.
class UsageError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

class Settings {
public:
    Settings(std::string integrator, const ParameterList* scene_params,
             std::map<std::string, std::string> overrides);

    int get_int(const std::string& key, int def) const;
    float get_float(const std::string& key, float def) const;
    bool get_bool(const std::string& key, bool def) const;
    std::string get_string(const std::string& key, const std::string& def) const;
    void check_unused() const;

private:
    const std::string* override_for(const std::string& key) const;
    std::string m_integrator;
    const ParameterList* m_scene;                    // may be null
    std::map<std::string, std::string> m_overrides;  // keys without the "name." prefix
    mutable std::map<std::string, bool> m_used;
};

}  // namespace ml
