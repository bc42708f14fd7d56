#include "core/noise.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace ml {

namespace {

// Ken Perlin's permutation of 0..255 (his reference implementation of improved noise), the table
// pbrt-v4 uses; read through perm() below, which wraps instead of doubling the table.
constexpr std::array<uint8_t, 256> kPerm = {
    151, 160, 137, 91,  90,  15,  131, 13,  201, 95,  96,  53,  194, 233, 7,   225, 140, 36,  103,
    30,  69,  142, 8,   99,  37,  240, 21,  10,  23,  190, 6,   148, 247, 120, 234, 75,  0,   26,
    197, 62,  94,  252, 219, 203, 117, 35,  11,  32,  57,  177, 33,  88,  237, 149, 56,  87,  174,
    20,  125, 136, 171, 168, 68,  175, 74,  165, 71,  134, 139, 48,  27,  166, 77,  146, 158, 231,
    83,  111, 229, 122, 60,  211, 133, 230, 220, 105, 92,  41,  55,  46,  245, 40,  244, 102, 143,
    54,  65,  25,  63,  161, 1,   216, 80,  73,  209, 76,  132, 187, 208, 89,  18,  169, 200, 196,
    135, 130, 116, 188, 159, 86,  164, 100, 109, 198, 173, 186, 3,   64,  52,  217, 226, 250, 124,
    123, 5,   202, 38,  147, 118, 126, 255, 82,  85,  212, 207, 206, 59,  227, 47,  16,  58,  17,
    182, 189, 28,  42,  223, 183, 170, 213, 119, 248, 152, 2,   44,  154, 163, 70,  221, 153, 101,
    155, 167, 43,  172, 9,   129, 22,  39,  253, 19,  98,  108, 110, 79,  113, 224, 232, 178, 185,
    112, 104, 218, 246, 97,  228, 251, 34,  242, 193, 238, 210, 144, 12,  191, 179, 162, 241, 81,
    51,  145, 235, 249, 14,  239, 107, 49,  192, 214, 31,  181, 199, 106, 157, 184, 84,  204, 176,
    115, 121, 50,  45,  127, 4,   150, 254, 138, 236, 205, 93,  222, 114, 67,  29,  24,  72,  243,
    141, 128, 195, 78,  66,  215, 61,  156, 180};

int perm(int i) { return kPerm[size_t(i & 255)]; }

// The gradient of lattice corner (x, y, z) dotted with the offset (dx, dy, dz) from it: the low
// four bits of the corner's hash pick one of the 12 edge directions of a cube (four repeated).
float gradient(int x, int y, int z, float dx, float dy, float dz) {
    int h = perm(perm(perm(x) + y) + z) & 15;
    float u = h < 8 || h == 12 || h == 13 ? dx : dy;
    float v = h < 4 || h == 12 || h == 13 ? dy : dz;
    return ((h & 1) ? -u : u) + ((h & 2) ? -v : v);
}

// 6t^5 - 15t^4 + 10t^3: zero first and second derivatives at the lattice.
float fade(float t) { return t * t * t * (t * (t * 6 - 15) + 10); }

float smooth_step(float x, float a, float b) {
    float t = std::clamp((x - a) / (b - a), 0.f, 1.f);
    return t * t * (3 - 2 * t);
}

}  // namespace

float perlin_noise(float x, float y, float z) {
    // 1. The lattice cell and the offset in it (coordinates folded below 2^30 so that the cell
    //    index fits an int).
    x = std::fmod(x, float(1 << 30));
    y = std::fmod(y, float(1 << 30));
    z = std::fmod(z, float(1 << 30));
    const float fx = std::floor(x), fy = std::floor(y), fz = std::floor(z);
    const int ix = int(fx) & 255, iy = int(fy) & 255, iz = int(fz) & 255;
    const float dx = x - fx, dy = y - fy, dz = z - fz;
    // 2. The eight corners' gradient ramps, blended trilinearly by the faded offsets.
    const float wx = fade(dx), wy = fade(dy), wz = fade(dz);
    auto along_x = [&](int j, int k, float ddy, float ddz) {
        return lerp(wx, gradient(ix, iy + j, iz + k, dx, ddy, ddz),
                    gradient(ix + 1, iy + j, iz + k, dx - 1, ddy, ddz));
    };
    float y0 = lerp(wy, along_x(0, 0, dy, dz), along_x(1, 0, dy - 1, dz));
    float y1 = lerp(wy, along_x(0, 1, dy, dz - 1), along_x(1, 1, dy - 1, dz - 1));
    return lerp(wz, y0, y1);
}

Vec3 perlin_noise_gradient(const Vec3& p) {
    const float delta = 0.01f, n = perlin_noise(p);
    return Vec3(perlin_noise(p + Vec3(delta, 0, 0)) - n, perlin_noise(p + Vec3(0, delta, 0)) - n,
                perlin_noise(p + Vec3(0, 0, delta)) - n) /
           delta;
}

float noise_octaves(float footprint2, int max_octaves) {
    if (!(footprint2 > 0)) return float(max_octaves);
    return std::clamp(-1 - std::log2(footprint2) / 2, 0.f, float(max_octaves));
}

float fbm(const Vec3& p, float footprint2, float omega, int max_octaves) {
    const float n = noise_octaves(footprint2, max_octaves);
    const int whole = int(std::floor(n));
    float sum = 0, lambda = 1, o = 1;
    for (int i = 0; i < whole; ++i) {
        sum += o * perlin_noise(p * lambda);
        lambda *= 1.99f;
        o *= omega;
    }
    return sum + o * smooth_step(n - float(whole), .3f, .7f) * perlin_noise(p * lambda);
}

float turbulence(const Vec3& p, float footprint2, float omega, int max_octaves) {
    const float n = noise_octaves(footprint2, max_octaves);
    const int whole = int(std::floor(n));
    float sum = 0, lambda = 1, o = 1;
    for (int i = 0; i < whole; ++i) {
        sum += o * std::abs(perlin_noise(p * lambda));
        lambda *= 1.99f;
        o *= omega;
    }
    // The partial octave fades from the mean of |noise| (0.2) to its value; the octaves beyond
    // it count at their mean.
    sum +=
        o * lerp(smooth_step(n - float(whole), .3f, .7f), 0.2f, std::abs(perlin_noise(p * lambda)));
    for (int i = whole; i < max_octaves; ++i) {
        sum += o * 0.2f;
        o *= omega;
    }
    return sum;
}

}  // namespace ml
