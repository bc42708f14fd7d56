#include "core/spectrum.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace ml {

namespace {

// CIE standard illuminant D65, relative spectral power from 360 to 830 nm every 10 nm (the CIE's
// published table; 100 at 560 nm).
constexpr std::array<double, 48> kD65 = {
    46.6383, 52.0891, 49.9755, 54.6482, 82.7549, 91.486,  93.4318, 86.6823, 104.865, 117.008,
    117.812, 114.861, 115.923, 108.811, 109.354, 107.802, 104.790, 107.689, 104.405, 104.046,
    100.000, 96.3342, 95.788,  88.6856, 90.0062, 89.5991, 87.6987, 83.2886, 83.6992, 80.0268,
    80.2146, 82.2778, 78.2842, 69.7213, 71.6091, 74.349,  61.604,  69.8856, 75.087,  63.5927,
    46.4182, 66.8054, 63.3828, 64.304,  59.4519, 51.959,  57.4406, 60.3125};

double d65(double lambda) {
    double x = std::clamp((lambda - 360) / 10, 0.0, double(kD65.size() - 1));
    size_t i = std::min(size_t(x), kD65.size() - 2);
    double t = x - double(i);
    return (1 - t) * kD65[i] + t * kD65[i + 1];
}

}  // namespace

RGB emission_srgb(const std::function<double(double)>& spectrum) {
    auto g = [](float x, float mu, float s1, float s2) {
        float t = (x - mu) / (x < mu ? s1 : s2);
        return std::exp(-0.5f * t * t);
    };
    double X = 0, Y = 0, Z = 0;
    for (float lambda = 360; lambda <= 830; lambda += 1) {
        const double le = spectrum(lambda);
        float x = 1.056f * g(lambda, 599.8f, 37.9f, 31.0f) +
                  0.362f * g(lambda, 442.0f, 16.0f, 26.7f) -
                  0.065f * g(lambda, 501.1f, 20.4f, 26.2f);
        float y =
            0.821f * g(lambda, 568.8f, 46.9f, 40.5f) + 0.286f * g(lambda, 530.9f, 16.3f, 31.1f);
        float z =
            1.217f * g(lambda, 437.0f, 11.8f, 36.0f) + 0.681f * g(lambda, 459.0f, 26.0f, 13.8f);
        X += le * x, Y += le * y, Z += le * z;
    }
    return RGB(float(3.2404542 * X - 1.5371385 * Y - 0.4985314 * Z),
               float(-0.9692660 * X + 1.8760108 * Y + 0.0415560 * Z),
               float(0.0556434 * X - 0.2040259 * Y + 1.0572252 * Z));
}

RGB reflectance_srgb(const std::function<double(double)>& reflectance) {
    static const RGB white = emission_srgb(d65);
    RGB lit = emission_srgb([&](double l) { return reflectance(l) * d65(l); });
    return RGB(lit.r / white.r, lit.g / white.g, lit.b / white.b);
}

}  // namespace ml
