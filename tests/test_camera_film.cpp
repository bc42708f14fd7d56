// The thin-lens camera and the pixel filters.
#include <gtest/gtest.h>

#include "camera/camera.h"
#include "core/rng.h"
#include "core/stats.h"
#include "film/film.h"
#include "film/filter.h"
#include "render/splats.h"

using namespace ml;

namespace {

ParameterList camera_params(float fov, float lens_radius, float focal_distance) {
    ParameterList p;
    auto add = [&](const char* name, float v) {
        Param q;
        q.type = "float";
        q.name = name;
        q.numbers = {v};
        p.add(q);
    };
    add("fov", fov);
    add("lensradius", lens_radius);
    add("focaldistance", focal_distance);
    return p;
}

}  // namespace

TEST(Camera, PinholeRaysLeaveTheEyeThroughTheImagePlane) {
    PerspectiveCamera cam(camera_params(90, 0, 1), Transform(), 100, 50);
    // The centre of the image looks down +z; fov spans the shorter (vertical) axis.
    Ray c = cam.generate_ray({Vec2(50, 25), Vec2(0.5f, 0.5f), 0});
    EXPECT_NEAR(c.d.z, 1.f, 1e-6f);
    Ray top = cam.generate_ray({Vec2(50, 0), Vec2(0.5f, 0.5f), 0});
    EXPECT_NEAR(top.d.y / top.d.z, 1.f, 1e-5f);  // tan(45 degrees), +y up
    Ray right = cam.generate_ray({Vec2(100, 25), Vec2(0.5f, 0.5f), 0});
    EXPECT_NEAR(right.d.x / right.d.z, 2.f, 1e-5f);  // aspect 2
}

TEST(Camera, ThinLensFocusesOnTheFocalPlane) {
    const float focal = 5.f;
    PerspectiveCamera cam(camera_params(60, 0.3f, focal), Transform::translate({1, 2, 3}), 64, 64);
    Rng rng(3);
    for (Vec2 film : {Vec2(32, 32), Vec2(3, 60), Vec2(50, 10)}) {
        Ray pin = cam.generate_ray({film, Vec2(0.5f, 0.5f), 0});  // lens centre
        Vec3 focus = pin.at((focal) / pin.d.z);
        float spread = 0;
        for (int i = 0; i < 64; ++i) {
            Ray r = cam.generate_ray({film, Vec2(rng.next_float(), rng.next_float()), 0});
            // Every ray through the lens meets the pinhole ray on the plane z = focal...
            Vec3 p = r.at((3 + focal - r.o.z) / r.d.z);
            EXPECT_NEAR(distance(p, focus + Vec3(0, 0, 0)), 0.f, 2e-4f);
            // ...and starts somewhere on the lens disk.
            spread = std::max(spread, distance(r.o, Vec3(1, 2, 3)));
            EXPECT_LE(distance(r.o, Vec3(1, 2, 3)), 0.3f + 1e-5f);
        }
        EXPECT_GT(spread, 0.1f);
    }
}

namespace {

// E[w h(x)] / E[w] over filter samples must equal the filter-weighted mean of h.
void expect_filter_consistent(const std::string& name) {
    ParameterList p;
    auto filter = create_filter(name, p, {});
    Vec2 r = filter->radius();
    auto h = [](Vec2 x) { return 1 + x.x * x.x + 0.5f * x.y + x.x * x.y * x.y; };
    double num = 0, den = 0;
    const int n = 400;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            Vec2 x((2 * (i + 0.5f) / n - 1) * r.x, (2 * (j + 0.5f) / n - 1) * r.y);
            num += filter->eval(x) * h(x);
            den += filter->eval(x);
        }
    double expected = num / den;
    Rng rng(5);
    double sw = 0, swh = 0;
    for (int i = 0; i < 400000; ++i) {
        FilterSample s = filter->sample({rng.next_float(), rng.next_float()});
        ASSERT_LE(std::abs(s.p.x), r.x + 1e-6f);
        ASSERT_LE(std::abs(s.p.y), r.y + 1e-6f);
        sw += s.weight;
        swh += s.weight * h(s.p);
    }
    EXPECT_NEAR(swh / sw, expected, 5e-3 * expected) << name;
}

}  // namespace

TEST(Filter, BoxSamplesMatchItsWeights) { expect_filter_consistent("box"); }
TEST(Filter, TriangleSamplesMatchItsWeights) { expect_filter_consistent("triangle"); }
TEST(Filter, GaussianSamplesMatchItsWeights) { expect_filter_consistent("gaussian"); }
TEST(Filter, MitchellSamplesMatchItsWeights) { expect_filter_consistent("mitchell"); }
TEST(Filter, SincSamplesMatchItsWeights) { expect_filter_consistent("sinc"); }
TEST(Filter, NegativeLobesCarryNegativeWeightsAveragingOne) {
    for (const char* name : {"mitchell", "sinc"}) {
        ParameterList p;
        auto filter = create_filter(name, p, {});
        // The table's integral is the filter's: Mitchell's is r^2 / 4 per pbrt-v4 (1 at radius 2).
        if (std::string(name) == "mitchell") {
            EXPECT_NEAR(filter->integral(), 1.f, 1e-3f);
        }
        Rng rng(7);
        double sw = 0;
        int negative = 0, sign_differs = 0;  // (at most at a sign change, on a bin's edge)
        const int n = 200000;
        for (int i = 0; i < n; ++i) {
            FilterSample s = filter->sample({rng.next_float(), rng.next_float()});
            sign_differs += (s.weight < 0) != (filter->eval(s.p) < 0);
            negative += s.weight < 0;
            sw += s.weight;
        }
        EXPECT_LT(sign_differs, n / 1000) << name;
        EXPECT_GT(negative, n / 100) << name;
        EXPECT_NEAR(sw / n, 1.0, 0.02) << name;
    }
}
TEST(Filter, UnknownFilterIsAnInputError) {
    ParameterList p;
    EXPECT_THROW(create_filter("lanczos", p, {}), InputError);
}

TEST(Film, NonFiniteSamplesAreCountedAndLeaveThePixelAlone) {
    Film film(2, 1);
    film.add_sample({0, 0}, RGB(1, 2, 3), 1.f);
    film.add_sample({0, 0}, RGB(std::nanf(""), 0, 0), 1.f);
    film.add_sample({0, 0}, RGB(0, kInfinity, 0), 1.f);
    film.add_splat(Vec2(1.5f, 0.5f), RGB(0, 0, std::nanf("")));
    EXPECT_EQ(film.nonfinite_samples(), 3u);
    Image img = film.to_image();
    EXPECT_EQ(img.at(0, 0).g, 2.f);
    EXPECT_EQ(img.at(1, 0).b, 0.f);
    EXPECT_EQ(film.pixels_without_samples(), 1u);
}

TEST(Film, ImagingRatioScalesBeforeTheClamp) {
    Film film(1, 1, /*max_component_value=*/4.f, /*imaging_ratio=*/2.f);
    film.add_sample({0, 0}, RGB(1, 3, 0.5f), 1.f);  // scaled (2, 6, 1), clamped to (4/3, 4, 2/3)
    RGB c = film.to_image().at(0, 0);
    EXPECT_NEAR(c.r, 4.f / 3, 1e-6f);
    EXPECT_NEAR(c.g, 4.f, 1e-6f);
    EXPECT_NEAR(c.b, 2.f / 3, 1e-6f);
}

TEST(Film, NonFiniteSplatsAreCounted) {
    stats::reset();
    std::vector<Splat> out;
    SplatList list(out, 4, 4);
    list.add(Vec2(1.5f, 1.5f), RGB(std::nanf(""), 1, 1));
    list.add_to_pixel({2, 2}, RGB(0, kInfinity, 0), 0);
    list.add(Vec2(1.5f, 1.5f), RGB(1, 1, 1));
    EXPECT_EQ(out.size(), 1u);
    EXPECT_EQ(stats::total().nonfinite_splats, 2u);
}
