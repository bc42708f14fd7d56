#include "view_message.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "core/error.h"
#include "core/math.h"

namespace ml {

nlohmann::json ViewSettings::to_json() const {
    return {{"vpls", vpls},       {"interleave", interleave}, {"filter", filter},
            {"preview", preview}, {"exposure", exposure},     {"integrator", integrator},
            {"spp", spp},         {"set", refine_set}};
}

const std::vector<std::string>& view_refine_integrators() {
    static const std::vector<std::string> names = {"path", "lightcuts", "mdlightcuts"};
    return names;
}

std::map<std::string, std::string> parse_view_pairs(const std::string& text) {
    std::map<std::string, std::string> out;
    std::istringstream in(text);
    std::string word;
    while (in >> word) {
        size_t eq = word.find('=');
        if (eq == std::string::npos || eq == 0 || word.find('.') > eq)
            throw UsageError("settings: expected NAME.KEY=VALUE, got \"" + word + "\"");
        out[word.substr(0, eq)] = word.substr(eq + 1);
    }
    return out;
}

void check_view(const std::array<float, 9>& v) {
    for (float x : v)
        if (!std::isfinite(x) || std::abs(x) > 1e7f) throw UsageError("view: numbers out of range");
    Vec3 eye(v[0], v[1], v[2]), target(v[3], v[4], v[5]), up(v[6], v[7], v[8]);
    Vec3 dir = target - eye;
    if (!(length(dir) > 0) || !(length(cross(normalize(dir), up)) > 1e-4f))
        throw UsageError("view: the eye must differ from the target and up from the view");
}

ViewRequest decode_view_request(const std::string& text) {
    nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
    if (j.is_discarded() || !j.is_object() || !j.contains("type") || !j["type"].is_string())
        throw UsageError("not a JSON object with a \"type\"");
    const std::string type = j["type"];
    ViewRequest r;
    if (type == "view") {
        r.kind = ViewRequest::Kind::View;
        int k = 0;
        for (const char* key : {"eye", "target", "up"}) {
            auto a = j.find(key);
            if (a == j.end() || !a->is_array() || a->size() != 3)
                throw UsageError("view: eye, target, up: 3 numbers");
            for (const nlohmann::json& x : *a) {
                if (!x.is_number()) throw UsageError("view: eye, target, up: 3 numbers");
                r.look_at[k++] = x.get<float>();
            }
        }
        if (j.size() != 4) throw UsageError("view: unknown members");
        check_view(r.look_at);
    } else if (type == "settings") {
        r.kind = ViewRequest::Kind::Settings;
        r.settings = std::move(j);
    } else if (type == "reset" && j.size() == 1) {
        r.kind = ViewRequest::Kind::Reset;
    } else if (type == "save" && j.size() == 1) {
        r.kind = ViewRequest::Kind::Save;
    } else {
        throw UsageError("unknown message \"" + type + "\"");
    }
    return r;
}

ViewSettings apply_view_settings(const ViewSettings& current, const nlohmann::json& j) {
    ViewSettings s = current;
    auto number = [&](const char* key, const nlohmann::json& v, double lo, double hi) {
        if (!v.is_number() || !(v.get<double>() >= lo && v.get<double>() <= hi))
            throw UsageError(
                fmt::format("settings: {} must be a number from {} to {}", key, lo, hi));
        return v.get<double>();
    };
    for (const auto& [key, value] : j.items()) {
        if (key == "type") continue;
        if (key == "vpls")
            s.vpls = int(number("vpls", value, 0, 1 << 16));
        else if (key == "filter")
            s.filter = int(number("filter", value, 0, 8));
        else if (key == "preview")
            s.preview = int(number("preview", value, 1, 8));
        else if (key == "exposure")
            s.exposure = float(number("exposure", value, -20, 20));
        else if (key == "spp")
            s.spp = int(number("spp", value, 1, 1 << 16));
        else if (key == "interleave") {
            int n = 0, m = 0;
            char extra = 0;
            if (!value.is_string() ||
                std::sscanf(value.get<std::string>().c_str(), "%dx%d%c", &n, &m, &extra) != 2 ||
                n < 1 || m < 1 || n > 16 || m > 16)
                throw UsageError("settings: interleave must be NxM, 1 to 16 each");
            s.interleave = value.get<std::string>();
        } else if (key == "integrator") {
            const auto& names = view_refine_integrators();
            if (!value.is_string() ||
                std::find(names.begin(), names.end(), value.get<std::string>()) == names.end())
                throw UsageError("settings: integrator must be path, lightcuts or mdlightcuts");
            s.integrator = value.get<std::string>();
        } else if (key == "set") {
            if (!value.is_string() || value.get<std::string>().size() > 1000)
                throw UsageError("settings: set must be a string of NAME.KEY=VALUE words");
            parse_view_pairs(value.get<std::string>());
            s.refine_set = value.get<std::string>();
        } else
            throw UsageError("settings: unknown setting \"" + key + "\"");
    }
    return s;
}

}  // namespace ml
