// A transform that moves while the shutter is open (pbrt-v4's AnimatedTransform): two keyframes
// at the times TransformTimes gives, each decomposed into translation T, rotation R (a unit
// quaternion) and scale/shear S, M = T R S; between them T and S are interpolated linearly and R
// by spherical interpolation; before the start time the start transform holds, after the end
// time the end transform.
#pragma once

#include "core/math.h"

namespace ml {

struct Quaternion {
    Vec3 v;
    float w = 1;
};

class AnimatedTransform {
public:
    AnimatedTransform() = default;
    // A transform that does not move (implicit: wherever a motion is expected, a fixed
    // transform will do).
    AnimatedTransform(const Transform& t) : AnimatedTransform(t, 0, t, 1) {}  // NOLINT
    AnimatedTransform(const Transform& start, float start_time, const Transform& end,
                      float end_time);

    bool is_animated() const { return m_animated; }
    Transform at(float time) const;
    const Transform& start() const { return m_start; }
    const Transform& end() const { return m_end; }
    float start_time() const { return m_start_time; }
    float end_time() const { return m_end_time; }
    // The fraction of the motion at `time`: 0 up to the start time, 1 from the end time on.
    float fraction(float time) const;
    // The angle (radians, in [0, pi]) the rotation turns through between the keyframes.
    float rotation_angle() const;

private:
    struct Parts {
        Vec3 t;
        Quaternion r;
        float s[3][3];
    };
    static Parts decompose(const Transform& m);
    Transform m_start, m_end;
    float m_start_time = 0, m_end_time = 1;
    bool m_animated = false;
    Parts m_parts[2];
};

}  // namespace ml
