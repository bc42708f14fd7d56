#include "core/animated_transform.h"

#include <algorithm>
#include <cmath>

namespace ml {

namespace {

using M3 = double[3][3];

bool invert3(const M3 a, M3 out) {
    double c00 = a[1][1] * a[2][2] - a[1][2] * a[2][1];
    double c01 = a[1][2] * a[2][0] - a[1][0] * a[2][2];
    double c02 = a[1][0] * a[2][1] - a[1][1] * a[2][0];
    double det = a[0][0] * c00 + a[0][1] * c01 + a[0][2] * c02;
    if (!(std::abs(det) > 1e-300)) return false;
    double id = 1 / det;
    out[0][0] = c00 * id;
    out[1][0] = c01 * id;
    out[2][0] = c02 * id;
    out[0][1] = (a[0][2] * a[2][1] - a[0][1] * a[2][2]) * id;
    out[1][1] = (a[0][0] * a[2][2] - a[0][2] * a[2][0]) * id;
    out[2][1] = (a[0][1] * a[2][0] - a[0][0] * a[2][1]) * id;
    out[0][2] = (a[0][1] * a[1][2] - a[0][2] * a[1][1]) * id;
    out[1][2] = (a[0][2] * a[1][0] - a[0][0] * a[1][2]) * id;
    out[2][2] = (a[0][0] * a[1][1] - a[0][1] * a[1][0]) * id;
    return true;
}

double det3(const M3 a) {
    return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
           a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
           a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
}

// The unit quaternion of a rotation matrix (Shoemake's method).
Quaternion quaternion_of(const M3 m) {
    double trace = m[0][0] + m[1][1] + m[2][2];
    double q[4];  // x, y, z, w
    if (trace > 0) {
        double s = std::sqrt(trace + 1.0);
        q[3] = s / 2;
        s = 0.5 / s;
        q[0] = (m[2][1] - m[1][2]) * s;
        q[1] = (m[0][2] - m[2][0]) * s;
        q[2] = (m[1][0] - m[0][1]) * s;
    } else {
        int i = 0;
        if (m[1][1] > m[0][0]) i = 1;
        if (m[2][2] > m[i][i]) i = 2;
        int j = (i + 1) % 3, k = (j + 1) % 3;
        double s = std::sqrt(m[i][i] - (m[j][j] + m[k][k]) + 1.0);
        q[i] = s * 0.5;
        if (s != 0) s = 0.5 / s;
        q[3] = (m[k][j] - m[j][k]) * s;
        q[j] = (m[j][i] + m[i][j]) * s;
        q[k] = (m[k][i] + m[i][k]) * s;
    }
    double l = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    return Quaternion{Vec3(float(q[0] / l), float(q[1] / l), float(q[2] / l)), float(q[3] / l)};
}

void rotation_matrix(const Quaternion& q, double m[3][3]) {
    double x = q.v.x, y = q.v.y, z = q.v.z, w = q.w;
    m[0][0] = 1 - 2 * (y * y + z * z);
    m[0][1] = 2 * (x * y - z * w);
    m[0][2] = 2 * (x * z + y * w);
    m[1][0] = 2 * (x * y + z * w);
    m[1][1] = 1 - 2 * (x * x + z * z);
    m[1][2] = 2 * (y * z - x * w);
    m[2][0] = 2 * (x * z - y * w);
    m[2][1] = 2 * (y * z + x * w);
    m[2][2] = 1 - 2 * (x * x + y * y);
}

float qdot(const Quaternion& a, const Quaternion& b) { return dot(a.v, b.v) + a.w * b.w; }

Quaternion slerp(float t, const Quaternion& a, Quaternion b) {
    float c = qdot(a, b);
    if (c < 0) b = Quaternion{-b.v, -b.w}, c = -c;
    Quaternion r;
    if (c > 0.9995f) {
        r = Quaternion{a.v * (1 - t) + b.v * t, a.w * (1 - t) + b.w * t};
    } else {
        float theta = std::acos(std::clamp(c, -1.f, 1.f));
        float s = std::sin(theta);
        float wa = std::sin((1 - t) * theta) / s, wb = std::sin(t * theta) / s;
        r = Quaternion{a.v * wa + b.v * wb, a.w * wa + b.w * wb};
    }
    float l = std::sqrt(qdot(r, r));
    return Quaternion{r.v / l, r.w / l};
}

}  // namespace

AnimatedTransform::AnimatedTransform(const Transform& start, float start_time, const Transform& end,
                                     float end_time)
    : m_start(start), m_end(end), m_start_time(start_time), m_end_time(end_time) {
    for (int r = 0; r < 4 && !m_animated; ++r)
        for (int c = 0; c < 4; ++c)
            if (start.m(r, c) != end.m(r, c)) m_animated = true;
    if (m_animated) {
        m_parts[0] = decompose(start);
        m_parts[1] = decompose(end);
    }
}

AnimatedTransform::Parts AnimatedTransform::decompose(const Transform& m) {
    Parts p;
    p.t = Vec3(m.m(0, 3), m.m(1, 3), m.m(2, 3));
    double a[3][3], r[3][3];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) a[i][j] = r[i][j] = m.m(i, j);
    // The polar decomposition's rotation: average R with its inverse transpose until it stops.
    for (int it = 0; it < 100; ++it) {
        double inv[3][3];
        if (!invert3(r, inv)) break;
        double norm = 0;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) {
                double n = 0.5 * (r[i][j] + inv[j][i]);
                norm = std::max(norm, std::abs(n - r[i][j]));
                r[i][j] = n;
            }
        if (norm < 1e-12) break;
    }
    // A reflection goes to S, so that R is a rotation.
    if (det3(r) < 0)
        for (auto& row : r)
            for (double& x : row) x = -x;
    p.r = quaternion_of(r);
    // S = R^T A.
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            double s = 0;
            for (int k = 0; k < 3; ++k) s += r[k][i] * a[k][j];
            p.s[i][j] = float(s);
        }
    return p;
}

float AnimatedTransform::fraction(float time) const {
    if (!(m_end_time > m_start_time)) return time < m_end_time ? 0.f : 1.f;
    return std::clamp((time - m_start_time) / (m_end_time - m_start_time), 0.f, 1.f);
}

float AnimatedTransform::rotation_angle() const {
    if (!m_animated) return 0;
    return 2 * std::acos(std::clamp(std::abs(qdot(m_parts[0].r, m_parts[1].r)), 0.f, 1.f));
}

Transform AnimatedTransform::at(float time) const {
    if (!m_animated) return m_start;
    float f = fraction(time);
    if (f <= 0) return m_start;
    if (f >= 1) return m_end;
    const Parts &a = m_parts[0], &b = m_parts[1];
    Vec3 t = a.t * (1 - f) + b.t * f;
    double r[3][3];
    rotation_matrix(slerp(f, a.r, b.r), r);
    float m[4][4] = {};
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            double x = 0;
            for (int k = 0; k < 3; ++k) x += r[i][k] * lerp(f, a.s[k][j], b.s[k][j]);
            m[i][j] = float(x);
        }
        m[i][3] = t[i];
    }
    m[3][3] = 1;
    return Transform::from_matrix(m);
}

}  // namespace ml
