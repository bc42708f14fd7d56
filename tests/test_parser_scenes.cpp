// Every shared scene parsed end to end (materials, textures and lights from their factories).
#include <gtest/gtest.h>

#include <chrono>

#include "scene/scene_desc.h"
#include "shared_files.h"

using namespace ml;

namespace {

struct Loaded {
    SceneDesc desc;
    size_t triangles = 0;
    size_t area_lights = 0;
    double seconds = 0;
};

Loaded load(const std::string& rel) {
    Loaded l;
    auto t0 = std::chrono::steady_clock::now();
    l.desc = parse_scene_file(ml::test::shared_dir() + "/scenes/" + rel);
    l.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    for (const auto& m : l.desc.meshes) {
        l.triangles += m->triangle_count();
        l.area_lights += m->area_light != nullptr;
        EXPECT_NE(m->material, nullptr);
        for (const Vec3& p : m->p) EXPECT_TRUE(is_finite(p));
    }
    return l;
}

}  // namespace

TEST(ParserScenes, CornellBox) {
    ML_NEED_SHARED("scenes/cornell-box/scene-v4.pbrt");
    Loaded l = load("cornell-box/scene-v4.pbrt");
    EXPECT_EQ(l.triangles, 36u);
    EXPECT_EQ(l.area_lights, 1u);
    EXPECT_EQ(l.desc.lights.size(), 1u);
    EXPECT_EQ(l.desc.camera.name, "perspective");
}

TEST(ParserScenes, CornellBoxPointLights) {
    ML_NEED_SHARED("scenes/cornell-box/scene-pointlights-4096.pbrt");
    Loaded l = load("cornell-box/scene-pointlights-4096.pbrt");
    EXPECT_EQ(l.triangles, 34u);  // the box without its light quad
    EXPECT_EQ(l.desc.lights.size(), 4096u + l.area_lights);
}

TEST(ParserScenes, VeachMis) {
    ML_NEED_SHARED("scenes/veach-mis/scene-v4.pbrt");
    Loaded l = load("veach-mis/scene-v4.pbrt");
    EXPECT_GT(l.triangles, 0u);
    EXPECT_GE(l.desc.lights.size(), 3u);  // three sphere lights and more
}

TEST(ParserScenes, VeachBidir) {
    ML_NEED_SHARED("scenes/veach-bidir/scene-v4.pbrt");
    Loaded l = load("veach-bidir/scene-v4.pbrt");
    EXPECT_GT(l.triangles, 10000u);
    EXPECT_GE(l.area_lights, 2u);
}

TEST(ParserScenes, Kitchen) {
    ML_NEED_SHARED("scenes/kitchen/scene-v4.pbrt");
    Loaded l = load("kitchen/scene-v4.pbrt");
    EXPECT_GT(l.triangles, 1'400'000u);
    EXPECT_GE(l.area_lights, 1u);
    std::printf("kitchen: %zu meshes, %zu triangles, %zu lights, parsed and loaded in %.3f s\n",
                l.desc.meshes.size(), l.triangles, l.desc.lights.size(), l.seconds);
}

TEST(ParserScenes, Classroom) {
    ML_NEED_SHARED("scenes/classroom/scene-v4.pbrt");
    Loaded l = load("classroom/scene-v4.pbrt");
    EXPECT_GT(l.triangles, 100'000u);
    EXPECT_GE(l.desc.lights.size(), 2u);  // sun and sky
}

TEST(ParserScenes, Coffee) {
    ML_NEED_SHARED("scenes/coffee/scene-v4.pbrt");
    Loaded l = load("coffee/scene-v4.pbrt");
    EXPECT_GT(l.triangles, 200'000u);
    EXPECT_GE(l.area_lights, 1u);
}
