#include "film/filter.h"

#include <algorithm>
#include <cmath>

namespace ml {

namespace {

class BoxFilter final : public Filter {
public:
    explicit BoxFilter(Vec2 r) : m_r(r) {}
    Vec2 radius() const override { return m_r; }
    float eval(const Vec2& p) const override {
        return (std::abs(p.x) <= m_r.x && std::abs(p.y) <= m_r.y) ? 1.f : 0.f;
    }
    float integral() const override { return 4 * m_r.x * m_r.y; }
    FilterSample sample(const Vec2& u) const override {
        return {Vec2((2 * u.x - 1) * m_r.x, (2 * u.y - 1) * m_r.y), 1.f};
    }

private:
    Vec2 m_r;
};

// Inverse CDF of the tent max(0, r - |x|) on [-r, r].
float sample_tent(float u, float r) {
    if (u < 0.5f) return -r + r * std::sqrt(2 * u);
    return r - r * std::sqrt(2 * (1 - u));
}

class TriangleFilter final : public Filter {
public:
    explicit TriangleFilter(Vec2 r) : m_r(r) {}
    Vec2 radius() const override { return m_r; }
    float eval(const Vec2& p) const override {
        return std::max(0.f, m_r.x - std::abs(p.x)) * std::max(0.f, m_r.y - std::abs(p.y));
    }
    float integral() const override { return sqr(m_r.x) * sqr(m_r.y); }
    FilterSample sample(const Vec2& u) const override {
        return {Vec2(sample_tent(u.x, m_r.x), sample_tent(u.y, m_r.y)), 1.f};
    }

private:
    Vec2 m_r;
};

// The Gaussian (pbrt-v4's: g(x) - g(r) per axis, separable), tabulated per axis into
// piecewise-constant bins 1/64 of a pixel wide and sampled exactly from that table, so every
// sample carries weight 1. The table is the filter: eval() returns the same values, and the
// difference from the smooth curve is far below anything a pixel shows.
class GaussianFilter final : public Filter {
public:
    GaussianFilter(Vec2 r, float sigma) : m_r(r), m_sigma(sigma) {
        for (int a = 0; a < 2; ++a) {
            Axis& ax = m_axis[a];
            ax.r = a == 0 ? r.x : r.y;
            int bins = std::max(8, int(std::ceil(2 * ax.r * 64)));
            ax.f.resize(bins);
            ax.cdf.resize(bins + 1);
            ax.cdf[0] = 0;
            for (int i = 0; i < bins; ++i) {
                float x = -ax.r + (i + 0.5f) * 2 * ax.r / bins;
                ax.f[i] = g1(x, ax.r);
                ax.cdf[i + 1] = ax.cdf[i] + ax.f[i];
            }
            ax.integral = ax.cdf[bins] * 2 * ax.r / float(bins);
            for (float& c : ax.cdf) c /= ax.cdf[bins];
            // Where each of kGuide equal steps of u starts its search: sampling is a lookup plus
            // a step or two along the CDF.
            ax.guide.resize(kGuide + 1);
            int i = 0;
            for (int k = 0; k <= kGuide; ++k) {
                float u = float(k) / kGuide;
                while (i < bins - 1 && ax.cdf[i + 1] <= u) ++i;
                ax.guide[k] = i;
            }
        }
    }
    Vec2 radius() const override { return m_r; }
    float eval(const Vec2& p) const override { return m_axis[0].eval(p.x) * m_axis[1].eval(p.y); }
    float integral() const override { return m_axis[0].integral * m_axis[1].integral; }
    FilterSample sample(const Vec2& u) const override {
        return {Vec2(m_axis[0].sample(u.x), m_axis[1].sample(u.y)), 1.f};
    }

private:
    static constexpr int kGuide = 256;
    struct Axis {
        float r;
        float integral = 0;  // of the table
        std::vector<float> f, cdf;
        std::vector<int> guide;
        float eval(float x) const {
            if (std::abs(x) > r) return 0.f;
            int bins = int(f.size());
            int i = std::min(bins - 1, int((x + r) / (2 * r) * bins));
            return f[i];
        }
        float sample(float u) const {
            int bins = int(f.size());
            int i = guide[std::min(kGuide, int(u * kGuide))];
            while (i < bins - 1 && cdf[i + 1] <= u) ++i;
            float span = cdf[i + 1] - cdf[i];
            float t = span > 0 ? (u - cdf[i]) / span : 0.5f;
            return -r + (i + t) * 2 * r / bins;
        }
    };
    float gauss(float x) const {
        return std::exp(-x * x / (2 * m_sigma * m_sigma)) / std::sqrt(2 * kPi * m_sigma * m_sigma);
    }
    float g1(float x, float r) const {
        return std::abs(x) > r ? 0.f : std::max(0.f, gauss(x) - gauss(r));
    }
    Vec2 m_r;
    float m_sigma;
    Axis m_axis[2];
};

// A separable filter with negative lobes (pbrt-v4's "mitchell" and "sinc"), tabulated per axis
// in bins 1/64 of a pixel wide. Offsets are drawn in proportion to |f| and carry the sign of f
// in their weight, scaled so that weights average 1 (pbrt-v4's FilterSampler: f / pdf, up to
// that constant, which the film's weighted average cancels). eval() and integral() are the
// table's, signed, for splats.
class SignedSeparableFilter final : public Filter {
public:
    template <typename F>
    SignedSeparableFilter(Vec2 r, F&& f1d) : m_r(r) {
        for (int a = 0; a < 2; ++a) {
            Axis& ax = m_axis[a];
            ax.r = a == 0 ? r.x : r.y;
            int bins = std::max(8, int(std::ceil(2 * ax.r * 64)));
            float width = 2 * ax.r / float(bins);
            ax.f.resize(bins);
            ax.cdf.resize(bins + 1);
            ax.cdf[0] = 0;
            double signed_sum = 0;
            for (int i = 0; i < bins; ++i) {
                ax.f[i] = f1d(-ax.r + (i + 0.5f) * width, ax.r);
                ax.cdf[i + 1] = ax.cdf[i] + std::abs(ax.f[i]);
                signed_sum += ax.f[i];
            }
            ax.integral = float(signed_sum * width);
            ax.weight = float(ax.cdf[bins] / signed_sum);
            for (float& c : ax.cdf) c /= ax.cdf[bins];
        }
    }
    Vec2 radius() const override { return m_r; }
    float eval(const Vec2& p) const override { return m_axis[0].eval(p.x) * m_axis[1].eval(p.y); }
    float integral() const override { return m_axis[0].integral * m_axis[1].integral; }
    FilterSample sample(const Vec2& u) const override {
        float wx, wy;
        Vec2 p(m_axis[0].sample(u.x, &wx), m_axis[1].sample(u.y, &wy));
        return {p, wx * wy};
    }

private:
    struct Axis {
        float r, integral = 0, weight = 1;
        std::vector<float> f, cdf;
        float eval(float x) const {
            if (std::abs(x) > r) return 0.f;
            int bins = int(f.size());
            return f[std::min(bins - 1, int((x + r) / (2 * r) * bins))];
        }
        float sample(float u, float* w) const {
            int bins = int(f.size());
            int i = int(std::upper_bound(cdf.begin(), cdf.end(), u) - cdf.begin()) - 1;
            i = std::clamp(i, 0, bins - 1);
            while (i < bins - 1 && cdf[i + 1] == cdf[i]) ++i;  // skip bins of zero mass
            float span = cdf[i + 1] - cdf[i];
            float t = span > 0 ? std::clamp((u - cdf[i]) / span, 0.f, 1.f) : 0.5f;
            *w = f[i] < 0 ? -weight : weight;
            return -r + (i + t) * 2 * r / bins;
        }
    };
    Vec2 m_r;
    Axis m_axis[2];
};

// Mitchell and Netravali's cubic, over |x| <= 2.
float mitchell_1d(float x, float b, float c) {
    x = std::abs(x);
    if (x <= 1)
        return ((12 - 9 * b - 6 * c) * x * x * x + (-18 + 12 * b + 6 * c) * x * x + (6 - 2 * b)) /
               6;
    if (x <= 2)
        return ((-b - 6 * c) * x * x * x + (6 * b + 30 * c) * x * x + (-12 * b - 48 * c) * x +
                (8 * b + 24 * c)) /
               6;
    return 0;
}

float sinc(float x) {
    x *= kPi;
    return std::abs(x) < 1e-5f ? 1 - x * x / 6 : std::sin(x) / x;
}

}  // namespace

// Besides the header's three: "mitchell" (radius 2, B = C = 1/3) and "sinc" (Lanczos, radius 4,
// tau 3), with pbrt-v4's parameter names.
std::unique_ptr<Filter> create_filter(const std::string& name, const ParameterList& params,
                                      const FileLoc& loc) {
    auto radius = [&](float def) {
        Vec2 r(params.get_float("xradius", def), params.get_float("yradius", def));
        if (!(r.x > 0 && r.y > 0)) throw_input_error(loc, "filter radii must be positive");
        return r;
    };
    if (name == "box") return std::make_unique<BoxFilter>(radius(0.5f));
    if (name == "triangle") return std::make_unique<TriangleFilter>(radius(2.f));
    if (name == "gaussian") {
        Vec2 r = radius(1.5f);
        float sigma = params.get_float("sigma", 0.5f);
        if (!(sigma > 0)) throw_input_error(loc, "gaussian filter \"sigma\" must be positive");
        return std::make_unique<GaussianFilter>(r, sigma);
    }
    if (name == "mitchell") {
        Vec2 r = radius(2.f);
        float b = params.get_float("B", 1.f / 3), c = params.get_float("C", 1.f / 3);
        // pbrt-v4 stretches the cubic's [-2, 2] over the radius.
        return std::make_unique<SignedSeparableFilter>(
            r, [b, c](float x, float rx) { return mitchell_1d(2 * x / rx, b, c); });
    }
    if (name == "sinc") {
        Vec2 r = radius(4.f);
        float tau = params.get_float("tau", 3.f);
        if (!(tau > 0)) throw_input_error(loc, "sinc filter \"tau\" must be positive");
        // Lanczos: sinc windowed by a sinc tau times wider, cut at the radius.
        return std::make_unique<SignedSeparableFilter>(
            r, [tau](float x, float) { return sinc(x) * sinc(x / tau); });
    }
    throw_input_error(
        loc, "unknown pixel filter \"{}\" (box, gaussian, triangle, mitchell and sinc)", name);
}

}  // namespace ml
