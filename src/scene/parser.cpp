// Placeholder until the pbrt-v4 parser lands (replaced by the parser work).
#include "scene/scene_desc.h"

namespace ml {

SceneDesc parse_scene_file(const std::string& path) {
    throw_input_error(FileLoc{path}, "the scene parser is not built yet");
}

SceneDesc parse_scene_string(const std::string& text, const std::string& base_dir,
                             const std::string& name) {
    throw_input_error(FileLoc{name}, "the scene parser is not built yet");
}

}  // namespace ml
