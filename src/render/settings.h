// An integrator's settings: the scene's `Integrator` parameters (pbrt-v4 names) overridden by
// `--set NAME.KEY=VALUE` from the command line. A plain key ("maxdepth") is the integrator's own:
// `--set path.maxdepth=...` or the scene's "maxdepth". A dotted key ("vpl.count") names a group
// shared by several integrators (the VPL settings read by both `vpl` and `lightcuts`) and comes
// from the command line only. Every setting must be read, or check_unused() reports it (scene
// parameters as input errors, --set keys as usage errors).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/params.h"

namespace ml {

// What a setting is for, written beside the code that reads it (the last argument of the
// get_* calls) and printed by `manylight integrators --markdown` as docs/settings.md.
struct SettingDoc {
    const char* range = "";  // the values it takes: "1 to 256", ">= 0", "bsdf, diffuse, skip"
    const char* text = "";   // one line: what it does
};

// A setting an integrator read, with the default it gave (Settings::record_defaults).
struct SettingDefault {
    std::string key;          // full name: "path.maxdepth", "vpl.count"
    std::string type;         // "int", "float", "bool" or "string"
    std::string value;        // the default as --set takes it: "5", "0.1", "true", "tree"
    std::string range;        // SettingDoc::range
    std::string description;  // SettingDoc::text
};

class Settings {
public:
    Settings(std::string integrator, const ParameterList* scene_params,
             std::map<std::string, std::string> overrides);

    int get_int(const std::string& key, int def, const SettingDoc& doc = {}) const;
    float get_float(const std::string& key, float def, const SettingDoc& doc = {}) const;
    bool get_bool(const std::string& key, bool def, const SettingDoc& doc = {}) const;
    std::string get_string(const std::string& key, const std::string& def,
                           const SettingDoc& doc = {}) const;
    // True when the scene or --set gives `key` (it is not marked read).
    bool has(const std::string& key) const;
    const std::string& integrator() const { return m_integrator; }
    void check_unused() const;
    // From now on every get_* adds its key, type, default and SettingDoc to `out` (a key read
    // twice keeps the last default, and the last description given): an integrator made from empty
    // Settings lists what it reads, with the defaults its own code gives (integrator_settings in
    // integrators/registry.h).
    void record_defaults(std::vector<SettingDefault>* out) { m_record = out; }

private:
    // The --set value for `key` (full name: "path.maxdepth", "vpl.count"), marked used.
    const std::string* override_for(const std::string& key) const;
    std::string full_name(const std::string& key) const {
        return key.find('.') == std::string::npos ? m_integrator + "." + key : key;
    }
    // The scene's parameters answer only the integrator's own (undotted) keys.
    const ParameterList* scene_for(const std::string& key) const {
        return key.find('.') == std::string::npos ? m_scene : nullptr;
    }
    void record(const std::string& key, const char* type, std::string value,
                const SettingDoc& doc) const;
    std::string m_integrator;
    const ParameterList* m_scene;                    // may be null
    std::map<std::string, std::string> m_overrides;  // full names
    mutable std::map<std::string, bool> m_used;
    std::vector<SettingDefault>* m_record = nullptr;
};

}  // namespace ml
