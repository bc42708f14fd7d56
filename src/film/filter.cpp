#include "film/filter.h"

#include <algorithm>

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

}  // namespace

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
    throw_input_error(loc, "unsupported pixel filter \"{}\" (box, gaussian and triangle are)",
                      name);
}

}  // namespace ml
