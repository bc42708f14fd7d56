// What a page may say to the viewer, decoded apart from the server and the renderer: the text of
// a WebSocket message becomes a checked request, or a UsageError saying what is wrong with it.
// The server (view_server.cpp) acts on the request; the fuzzer (fuzz/) feeds it arbitrary text.
#pragma once

#include <nlohmann/json.hpp>

#include <array>
#include <map>
#include <string>
#include <vector>

namespace ml {

// What the viewer can change (the `settings` message).
struct ViewSettings {
    int vpls = 256;
    std::string interleave = "4x4";
    int filter = 1;  // interleave patterns the blur spans
    // Moving frames render at 1/preview of the width and height, each of their pixels shown
    // as preview x preview; then one frame at full resolution once the view stops (1: always full).
    int preview = 2;
    float exposure = 0;  // stops
    std::string integrator = "path";
    int spp = 64;
    std::string refine_set;  // "key=value key=value" for the refining integrator
    nlohmann::json to_json() const;
};

// A page's message: {"type": "view", "eye": [3], "target": [3], "up": [3]},
// {"type": "settings", ...members to change}, {"type": "reset"} or {"type": "save"}.
struct ViewRequest {
    enum class Kind { View, Settings, Reset, Save };
    Kind kind = Kind::Reset;
    std::array<float, 9> look_at{};  // View: eye, target, up (check_view holds)
    nlohmann::json settings;         // Settings: the message, for apply_view_settings
};

// Decodes a text message. Throws UsageError with what is wrong.
ViewRequest decode_view_request(const std::string& text);

// `current` with the members of a settings message applied. Throws UsageError for an unknown
// member or a value out of range.
ViewSettings apply_view_settings(const ViewSettings& current, const nlohmann::json& j);

// Throws UsageError unless eye, target and up are finite, in range and make a view.
void check_view(const std::array<float, 9>& look_at);

// "NAME.KEY=VALUE NAME.KEY=VALUE" (the settings' `set`) as a map. Throws UsageError.
std::map<std::string, std::string> parse_view_pairs(const std::string& text);

// The integrators the viewer refines with.
const std::vector<std::string>& view_refine_integrators();

}  // namespace ml
