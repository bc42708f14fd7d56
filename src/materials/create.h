// Factories for the scene's `Texture` and material directives: each consumes its parameters
// from the list (unknown ones are left for ParameterList::check_unused to report).
#pragma once

#include <map>
#include <memory>
#include <string>

#include "core/params.h"
#include "film/image.h"
#include "materials/material.h"
#include "materials/texture.h"

namespace ml {

// Images loaded once per scene and shared by every texture that names them.
struct ImageCache {
    std::map<std::string, std::shared_ptr<const Image>> images;
    std::shared_ptr<const Image> get(const std::string& path, const FileLoc& loc);
};

// `Texture "name" "float"|"spectrum" "class" params...`; adds it to `textures`. Relative file
// names resolve against `base_dir`; `to_world` is the CTM at the directive (texture space, for
// the spherical, cylindrical and planar mappings and 3D textures).
void create_texture(const std::string& name, const std::string& kind, const std::string& cls,
                    const ParameterList& params, const std::string& base_dir,
                    NamedTextures& textures, ImageCache& images, const FileLoc& loc,
                    const Transform& to_world = Transform());

// `Material "type" params...` / `MakeNamedMaterial` with "string type". Throws InputError for an
// unknown type or an undefined texture.
// `named` holds the named materials defined so far ("mix" names two of them). A "normalmap" file
// is read through `images`, relative to `base_dir` (without `images` it is refused).
std::unique_ptr<Material> create_material(const std::string& type, const ParameterList& params,
                                          const NamedTextures& textures, const FileLoc& loc,
                                          const std::map<std::string, const Material*>& named = {},
                                          ImageCache* images = nullptr,
                                          const std::string& base_dir = "");

}  // namespace ml
