// The entry points of the fuzz targets (fuzz/<name>.cpp), shared with the regression tests
// (tests/test_fuzz_regressions.cpp) so that a crash input found by a fuzzer is replayed through
// exactly the code that found it. Bad input may only end in InputError (scenes and meshes) or
// UsageError (the viewer's messages): anything else that escapes, a signal or a sanitizer report
// is a bug.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "core/error.h"
#include "geometry/ply.h"
#include "scene/scene.h"
#include "scene/scene_desc.h"
#include "scene/tokenizer.h"
#include "view_message.h"

namespace ml::fuzz {

// Files a scene names (Include, PLY meshes, image textures) are looked up here, a directory
// that does not exist, so that only the input itself is read.
inline const char* const kNoFiles = "/nonexistent-fuzz-dir";

// The scene language: every token of the text, then the whole parse (directives, parameters and
// what they make: meshes, materials, textures, lights).
inline void parse_text(const std::string& text) {
    Tokenizer tokens(text, "fuzz.pbrt");
    while (tokens.next().kind != TokenKind::End) {
    }
    parse_scene_string(text, kNoFiles, "fuzz.pbrt");
}

// Scene building: the text parsed, then the Scene a render starts from (Embree's BVH over the
// meshes, the lights preprocessed against the scene's bounds). No render.
inline void build_scene(const std::string& text) {
    Scene scene(parse_scene_string(text, kNoFiles, "fuzz.pbrt"));
}

// The PLY reader: header checks, the body walk, and OpenMesh's reader on the same bytes.
inline void read_ply(const std::string& bytes) {
    load_ply_data(bytes, "fuzz.ply", FileLoc{"fuzz.pbrt", 1, 1});
}

// The viewer's WebSocket messages: the text a page sends, decoded as the server decodes it, and
// a settings message applied to the default settings.
inline void decode_view_message(const std::string& text) {
    ViewRequest r = decode_view_request(text);
    if (r.kind == ViewRequest::Kind::Settings) apply_view_settings(ViewSettings{}, r.settings);
}

// libFuzzer's input through `entry`; the errors bad input may give end here.
template <typename F>
int run(const uint8_t* data, size_t size, F&& entry) {
    std::string text(reinterpret_cast<const char*>(data), size);
    try {
        entry(text);
    } catch (const InputError&) {
    } catch (const UsageError&) {
    }
    return 0;
}

}  // namespace ml::fuzz
