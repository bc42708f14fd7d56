#include "core/math.h"

namespace ml {

namespace {

// Gauss-Jordan inversion with full pivoting in double precision; false if singular.
bool invert4(const float in[4][4], float out[4][4]) {
    double a[4][8];
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            a[i][j] = in[i][j];
            a[i][j + 4] = (i == j) ? 1.0 : 0.0;
        }
    for (int c = 0; c < 4; ++c) {
        int piv = c;
        for (int r = c + 1; r < 4; ++r)
            if (std::abs(a[r][c]) > std::abs(a[piv][c])) piv = r;
        if (std::abs(a[piv][c]) < 1e-300 || !std::isfinite(a[piv][c])) return false;
        if (piv != c)
            for (int j = 0; j < 8; ++j) std::swap(a[c][j], a[piv][j]);
        double inv = 1.0 / a[c][c];
        for (int j = 0; j < 8; ++j) a[c][j] *= inv;
        for (int r = 0; r < 4; ++r) {
            if (r == c) continue;
            double f = a[r][c];
            if (f != 0.0)
                for (int j = 0; j < 8; ++j) a[r][j] -= f * a[c][j];
        }
    }
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            out[i][j] = float(a[i][j + 4]);
            if (!std::isfinite(out[i][j])) return false;
        }
    return true;
}

}  // namespace

Transform Transform::from_matrix(const float m[4][4], bool* ok) {
    Transform t;
    bool good = true;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            t.m_m[i][j] = m[i][j];
            if (!std::isfinite(m[i][j])) good = false;
        }
    if (good) good = invert4(t.m_m, t.m_inv);
    if (!good)
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j) t.m_inv[i][j] = (i == j) ? 1.f : 0.f;
    if (ok) *ok = good;
    return t;
}

Transform Transform::translate(const Vec3& d) {
    float m[4][4] = {{1, 0, 0, d.x}, {0, 1, 0, d.y}, {0, 0, 1, d.z}, {0, 0, 0, 1}};
    Transform t;
    std::copy(&m[0][0], &m[0][0] + 16, &t.m_m[0][0]);
    float mi[4][4] = {{1, 0, 0, -d.x}, {0, 1, 0, -d.y}, {0, 0, 1, -d.z}, {0, 0, 0, 1}};
    std::copy(&mi[0][0], &mi[0][0] + 16, &t.m_inv[0][0]);
    return t;
}

Transform Transform::scale(const Vec3& s) {
    float m[4][4] = {{s.x, 0, 0, 0}, {0, s.y, 0, 0}, {0, 0, s.z, 0}, {0, 0, 0, 1}};
    return from_matrix(m);
}

Transform Transform::rotate(float deg, const Vec3& axis) {
    Vec3 a = normalize(axis);
    float s = std::sin(radians(deg)), c = std::cos(radians(deg));
    float m[4][4] = {{a.x * a.x + (1 - a.x * a.x) * c, a.x * a.y * (1 - c) - a.z * s,
                      a.x * a.z * (1 - c) + a.y * s, 0},
                     {a.x * a.y * (1 - c) + a.z * s, a.y * a.y + (1 - a.y * a.y) * c,
                      a.y * a.z * (1 - c) - a.x * s, 0},
                     {a.x * a.z * (1 - c) - a.y * s, a.y * a.z * (1 - c) + a.x * s,
                      a.z * a.z + (1 - a.z * a.z) * c, 0},
                     {0, 0, 0, 1}};
    return from_matrix(m);
}

// pbrt's LookAt: the world-to-camera transform of a left-handed camera looking down +z.
Transform Transform::look_at(const Vec3& eye, const Vec3& look, const Vec3& up, bool* ok) {
    Vec3 dir = look - eye;
    if (length_squared(dir) == 0.f) {
        *ok = false;
        return Transform();
    }
    dir = normalize(dir);
    Vec3 upn = length_squared(up) > 0 ? normalize(up) : up;
    Vec3 right = cross(upn, dir);
    if (length(right) < 1e-6f) {
        *ok = false;
        return Transform();
    }
    right = normalize(right);
    Vec3 new_up = cross(dir, right);
    float cam_to_world[4][4] = {{right.x, new_up.x, dir.x, eye.x},
                                {right.y, new_up.y, dir.y, eye.y},
                                {right.z, new_up.z, dir.z, eye.z},
                                {0, 0, 0, 1}};
    Transform c2w = from_matrix(cam_to_world, ok);
    return c2w.inverse();
}

Transform Transform::perspective(float fov, float n, float f) {
    float persp[4][4] = {
        {1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, f / (f - n), -f * n / (f - n)}, {0, 0, 1, 0}};
    float inv_tan = 1.f / std::tan(radians(fov) / 2);
    return scale({inv_tan, inv_tan, 1}) * from_matrix(persp);
}

Transform Transform::operator*(const Transform& b) const {
    Transform r;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            r.m_m[i][j] = m_m[i][0] * b.m_m[0][j] + m_m[i][1] * b.m_m[1][j] +
                          m_m[i][2] * b.m_m[2][j] + m_m[i][3] * b.m_m[3][j];
            r.m_inv[i][j] = b.m_inv[i][0] * m_inv[0][j] + b.m_inv[i][1] * m_inv[1][j] +
                            b.m_inv[i][2] * m_inv[2][j] + b.m_inv[i][3] * m_inv[3][j];
        }
    return r;
}

bool Transform::swaps_handedness() const {
    float det = m_m[0][0] * (m_m[1][1] * m_m[2][2] - m_m[1][2] * m_m[2][1]) -
                m_m[0][1] * (m_m[1][0] * m_m[2][2] - m_m[1][2] * m_m[2][0]) +
                m_m[0][2] * (m_m[1][0] * m_m[2][1] - m_m[1][1] * m_m[2][0]);
    return det < 0;
}

}  // namespace ml
