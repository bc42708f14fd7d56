// Camera importance for light tracing and BDPT: We integrates to one over the film, pdf_we is
// the density generate_ray() samples with, and sample_wi() finds the film position and lens
// point that see a scene point.
#include <gtest/gtest.h>

#include "camera/camera.h"
#include "core/rng.h"
#include "sampling/warps.h"

using namespace ml;

namespace {

ParameterList lens_params(float fov, float lens_radius, float focal_distance) {
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

Transform camera_pose() {
    bool ok = false;
    return Transform::look_at(Vec3(1, 2, 3), Vec3(0, 0, -2), Vec3(0, 1, 0), &ok).inverse();
}

struct Estimate {
    double mean = 0, stderr_of_mean = 0;
};

template <typename F>
Estimate monte_carlo(int n, uint64_t seed, F&& f) {
    Rng rng(seed);
    double s = 0, s2 = 0;
    for (int i = 0; i < n; ++i) {
        double v = f(Vec2(rng.next_float(), rng.next_float()));
        s += v;
        s2 += v * v;
    }
    Estimate e;
    e.mean = s / n;
    e.stderr_of_mean = std::sqrt(std::max(0.0, s2 / n - e.mean * e.mean) / (n - 1));
    return e;
}

}  // namespace

TEST(CameraImportance, PinholeImportanceIntegratesToOneOverTheFilm) {
    PerspectiveCamera cam(lens_params(50, 0, 1), camera_pose(), 64, 48);
    Vec3 eye = camera_pose().point(Vec3(0, 0, 0));
    // Over all directions: the integral of We cos(theta) is 1, and pdf_we's solid-angle density
    // integrates to 1.
    Estimate we = monte_carlo(400000, 1, [&](Vec2 u) {
        Vec3 w = sample_uniform_sphere(u);
        float cos = dot(w, cam.forward(0.f));
        return cam.importance(Ray{eye, w}) * std::max(0.f, cos) / pdf_uniform_sphere();
    });
    EXPECT_NEAR(we.mean, 1.0, 5 * we.stderr_of_mean + 1e-3);
    Estimate pdf = monte_carlo(400000, 2, [&](Vec2 u) {
        Vec3 w = sample_uniform_sphere(u);
        float pdf_area, pdf_dir;
        cam.pdf_we(Ray{eye, w}, &pdf_area, &pdf_dir);
        return pdf_dir / pdf_uniform_sphere();
    });
    EXPECT_NEAR(pdf.mean, 1.0, 5 * pdf.stderr_of_mean + 1e-3);
    // Behind the camera: nothing.
    EXPECT_EQ(cam.importance(Ray{eye, -cam.forward(0.f)}), 0.f);
}

TEST(CameraImportance, GeneratedRaysCarryTheirOwnRasterPositionAndDensity) {
    for (float lens : {0.f, 0.2f}) {
        PerspectiveCamera cam(lens_params(40, lens, 4), camera_pose(), 40, 30);
        Rng rng(5);
        for (int i = 0; i < 200; ++i) {
            CameraSample cs{Vec2(40 * rng.next_float(), 30 * rng.next_float()),
                            Vec2(rng.next_float(), rng.next_float()), 0};
            Ray r = cam.generate_ray(cs);
            Vec2 p;
            float We = cam.importance(r, &p);
            ASSERT_GT(We, 0.f);
            EXPECT_NEAR(p.x, cs.p_film.x, 2e-3f);
            EXPECT_NEAR(p.y, cs.p_film.y, 2e-3f);
            float pdf_area, pdf_dir;
            cam.pdf_we(r, &pdf_area, &pdf_dir);
            EXPECT_NEAR(pdf_area, 1 / cam.lens_area(), 1e-4f);
            // We = pdf_dir / (lens area cos): the camera samples in proportion to importance.
            float cos = dot(r.d, cam.forward(0.f));
            EXPECT_NEAR(We, pdf_dir / (cam.lens_area() * cos), 1e-3f * We);
        }
    }
}

TEST(CameraImportance, SampleWiFindsTheLensPointAndPixelThatSeeAPoint) {
    for (float lens : {0.f, 0.2f}) {
        PerspectiveCamera cam(lens_params(40, lens, 4), camera_pose(), 40, 30);
        Rng rng(9);
        int found = 0;
        for (int i = 0; i < 300; ++i) {
            Vec3 p(rng.next_float() * 4 - 2, rng.next_float() * 4 - 2, -rng.next_float() * 4);
            Vec2 u(rng.next_float(), rng.next_float());
            auto s = cam.sample_wi(p, u, 0.f);
            if (!s) continue;
            ++found;
            // The ray the camera makes for that pixel and lens point passes through p.
            Ray r = cam.generate_ray({s->p_raster, u, 0});
            EXPECT_NEAR(distance(r.o, s->p_lens), 0.f, 1e-4f);
            EXPECT_GT(dot(r.d, -s->wi), 1 - 1e-4f);
            // Area density 1 / lens area on the lens, seen as solid angle from p.
            float d2 = distance_squared(p, s->p_lens);
            EXPECT_NEAR(s->pdf_solid_angle, d2 / (abs_dot(s->wi, s->n_lens) * cam.lens_area()),
                        1e-4f * s->pdf_solid_angle);
            EXPECT_NEAR(s->We, cam.importance(Ray{s->p_lens, -s->wi}), 1e-5f * s->We);
        }
        EXPECT_GT(found, 50);
    }
}

TEST(CameraImportance, ThinLensImportanceIntegratesToOneOverFilmAndLens) {
    // Pick a lens point uniformly (density 1 / lens area) and a direction uniformly: the
    // integral of We cos over lens area and directions is 1.
    PerspectiveCamera cam(lens_params(50, 0.25f, 3), camera_pose(), 32, 32);
    Rng rng(4);
    Estimate e = monte_carlo(400000, 3, [&](Vec2 u) {
        Vec2 l = sample_uniform_disk_concentric(Vec2(rng.next_float(), rng.next_float())) * 0.25f;
        Vec3 o = camera_pose().point(Vec3(l.x, l.y, 0));
        Vec3 w = sample_uniform_sphere(u);
        float cos = dot(w, cam.forward(0.f));
        return cam.importance(Ray{o, w}) * std::max(0.f, cos) * cam.lens_area() /
               pdf_uniform_sphere();
    });
    EXPECT_NEAR(e.mean, 1.0, 5 * e.stderr_of_mean + 1e-3);
}
