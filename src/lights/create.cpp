// Placeholder until the light factories land (replaced by the lights work).
#include "lights/create.h"

namespace ml {

std::unique_ptr<Light> create_light(const std::string& type, const ParameterList& params,
                                    const Transform& light_to_world, const std::string& base_dir,
                                    const FileLoc& loc) {
    throw_input_error(loc, "light \"{}\" is not supported yet", type);
}

std::unique_ptr<Light> create_area_light(const std::string& type, const ParameterList& params,
                                         const TriangleMesh* mesh, const FileLoc& loc) {
    throw_input_error(loc, "area light \"{}\" is not supported yet", type);
}

}  // namespace ml
