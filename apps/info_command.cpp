#include <fmt/format.h>

#include <map>
#include <set>

#include "commands.h"
#include "scene/scene_desc.h"

namespace ml {

void add_info_command(CLI::App& app, InfoArgs& a) {
    CLI::App* i =
        app.add_subcommand("info", "describe a scene: triangles, lights, bounds, materials");
    i->add_option("scene", a.scene, "scene file (.pbrt)")->required();
}

int run_info(const InfoArgs& a) {
    SceneDesc desc = parse_scene_file(a.scene);
    size_t tris = 0, verts = 0;
    Bounds3 bounds;
    for (const auto& m : desc.meshes) {
        tris += m->triangle_count();
        verts += m->p.size();
        bounds.expand(m->bounds());
    }
    std::map<std::string, int> lights;
    for (const auto& l : desc.lights) {
        switch (l->type()) {
            case LightType::DeltaPosition:
                ++lights["point/spot"];
                break;
            case LightType::DeltaDirection:
                ++lights["distant"];
                break;
            case LightType::Area:
                ++lights["area"];
                break;
            case LightType::Infinite:
                ++lights["infinite"];
                break;
        }
    }
    std::map<std::string, int> materials;
    std::set<const Material*> used;
    for (const auto& m : desc.meshes)
        if (m->material && used.insert(m->material).second) ++materials[m->material->type()];
    fmt::print("scene      {}\n", a.scene);
    fmt::print("meshes     {}\ntriangles  {}\nvertices   {}\n", desc.meshes.size(), tris, verts);
    if (!bounds.empty())
        fmt::print("bounds     ({:.4g}, {:.4g}, {:.4g}) - ({:.4g}, {:.4g}, {:.4g})\n", bounds.lo.x,
                   bounds.lo.y, bounds.lo.z, bounds.hi.x, bounds.hi.y, bounds.hi.z);
    fmt::print("lights     {}\n", desc.lights.size());
    for (auto& [k, n] : lights) fmt::print("  {:<10} {}\n", k, n);
    fmt::print("materials  {} in use\n", used.size());
    for (auto& [k, n] : materials) fmt::print("  {:<20} {}\n", k, n);
    fmt::print("integrator {}\n", desc.integrator.name.empty() ? "(none)" : desc.integrator.name);
    return 0;
}

}  // namespace ml
