#include <gtest/gtest.h>

#include "core/math.h"

using namespace ml;

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
