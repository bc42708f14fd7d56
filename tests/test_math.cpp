#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "core/math.h"

using namespace ml;

// next_float_up and next_float_down step the bits inline: the same floats as std::nextafter
// towards +-infinity for zeros of both signs, the least and greatest floats, infinities,
// subnormals and random bit patterns; NaN stays NaN.
TEST(Math, NextFloatIsNextafter) {
    std::vector<float> values = {0.f,
                                 -0.f,
                                 1.f,
                                 -1.f,
                                 std::numeric_limits<float>::denorm_min(),
                                 -std::numeric_limits<float>::denorm_min(),
                                 std::numeric_limits<float>::min(),
                                 -std::numeric_limits<float>::min(),
                                 std::numeric_limits<float>::max(),
                                 -std::numeric_limits<float>::max(),
                                 kInfinity,
                                 -kInfinity};
    uint32_t state = 12345;
    for (int i = 0; i < 200000; ++i) {
        state = state * 1664525u + 1013904223u;
        float v = std::bit_cast<float>(state);
        if (!std::isnan(v)) values.push_back(v);
    }
    for (float v : values) {
        float up = next_float_up(v), down = next_float_down(v);
        ASSERT_EQ(std::bit_cast<uint32_t>(up),
                  std::bit_cast<uint32_t>(std::nextafter(v, kInfinity)))
            << v;
        ASSERT_EQ(std::bit_cast<uint32_t>(down),
                  std::bit_cast<uint32_t>(std::nextafter(v, -kInfinity)))
            << v;
    }
    const float nan = std::numeric_limits<float>::quiet_NaN();
    EXPECT_TRUE(std::isnan(next_float_up(nan)));
    EXPECT_TRUE(std::isnan(next_float_down(nan)));
    EXPECT_TRUE(std::isnan(next_float_up(std::bit_cast<float>(0x7f800001u))));
    EXPECT_TRUE(std::isnan(next_float_down(std::bit_cast<float>(0xff800001u))));
}

TEST(Transform, InverseRoundTrips) {
    Transform t = Transform::translate({1, 2, 3}) * Transform::rotate(30, {1, 1, 0}) *
                  Transform::scale({2, 3, 4});
    Vec3 p(0.3f, -2.f, 5.f);
    Vec3 q = t.inverse().point(t.point(p));
    EXPECT_NEAR(q.x, p.x, 1e-4f);
    EXPECT_NEAR(q.y, p.y, 1e-4f);
    EXPECT_NEAR(q.z, p.z, 1e-4f);
}

TEST(Transform, NormalsStayPerpendicular) {
    Transform t = Transform::scale({1, 5, 0.5f}) * Transform::rotate(40, {0, 0, 1});
    Vec3 a(1, 0, 0), b(0, 1, 1), n = cross(a, b);
    EXPECT_NEAR(dot(t.normal(n), t.vector(a)), 0.f, 1e-4f);
    EXPECT_NEAR(dot(t.normal(n), t.vector(b)), 0.f, 1e-4f);
}

TEST(Frame, IsOrthonormal) {
    for (Vec3 n : {Vec3(0, 0, 1), Vec3(0, 0, -1), normalize(Vec3(1, 2, 3))}) {
        Frame f = Frame::from_z(n);
        EXPECT_NEAR(dot(f.s, f.t), 0.f, 1e-6f);
        EXPECT_NEAR(dot(f.s, f.n), 0.f, 1e-6f);
        EXPECT_NEAR(length(f.s), 1.f, 1e-6f);
        Vec3 v(0.2f, -0.5f, 0.7f);
        Vec3 r = f.to_world(f.to_local(v));
        EXPECT_NEAR(r.x, v.x, 1e-6f);
    }
}
