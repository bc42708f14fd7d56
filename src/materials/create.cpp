// Placeholder until the material factories land (replaced by the materials work).
#include "materials/create.h"

namespace ml {

std::shared_ptr<const Image> ImageCache::get(const std::string& path, const FileLoc& loc) {
    auto it = images.find(path);
    if (it != images.end()) return it->second;
    auto img = std::make_shared<const Image>(read_image(path, loc));
    images[path] = img;
    return img;
}

void create_texture(const std::string& name, const std::string& kind, const std::string& cls,
                    const ParameterList& params, const std::string& base_dir,
                    NamedTextures& textures, ImageCache& images, const FileLoc& loc) {
    throw_input_error(loc, "texture class \"{}\" is not supported yet", cls);
}

std::unique_ptr<Material> create_material(const std::string& type, const ParameterList& params,
                                          const NamedTextures& textures, const FileLoc& loc) {
    throw_input_error(loc, "material \"{}\" is not supported yet", type);
}

}  // namespace ml
