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
    FilterSample sample(const Vec2& u) const override {
        return {Vec2(sample_tent(u.x, m_r.x), sample_tent(u.y, m_r.y)), 1.f};
    }

private:
    Vec2 m_r;
};

// A separable filter sampled through per-axis piecewise-constant tables; the weight f/pdf
// corrects for the tabulation, so the estimate stays exact in expectation.
class GaussianFilter final : public Filter {
public:
    GaussianFilter(Vec2 r, float sigma) : m_r(r), m_sigma(sigma) {
        for (int a = 0; a < 2; ++a) {
            float ra = a == 0 ? r.x : r.y;
            std::vector<float>& cdf = m_cdf[a];
            cdf.resize(kBins + 1);
            cdf[0] = 0;
            for (int i = 0; i < kBins; ++i) {
                float x = -ra + (i + 0.5f) * 2 * ra / kBins;
                m_pdf[a][i] = g1(x, ra);
                cdf[i + 1] = cdf[i] + m_pdf[a][i];
            }
            float total = cdf[kBins];
            for (int i = 0; i < kBins; ++i) m_pdf[a][i] *= kBins / (total * 2 * ra);
            for (float& c : cdf) c /= total;
        }
    }
    Vec2 radius() const override { return m_r; }
    float eval(const Vec2& p) const override { return g1(p.x, m_r.x) * g1(p.y, m_r.y); }
    FilterSample sample(const Vec2& u) const override {
        float pdf_x, pdf_y;
        float x = sample_axis(0, u.x, m_r.x, &pdf_x);
        float y = sample_axis(1, u.y, m_r.y, &pdf_y);
        Vec2 p(x, y);
        return {p, eval(p) / (pdf_x * pdf_y)};
    }

private:
    static constexpr int kBins = 64;
    float gauss(float x) const {
        return std::exp(-x * x / (2 * m_sigma * m_sigma)) / std::sqrt(2 * kPi * m_sigma * m_sigma);
    }
    float g1(float x, float r) const {
        return std::abs(x) > r ? 0.f : std::max(0.f, gauss(x) - gauss(r));
    }
    float sample_axis(int a, float u, float r, float* pdf) const {
        const std::vector<float>& cdf = m_cdf[a];
        int i = int(std::upper_bound(cdf.begin(), cdf.end(), u) - cdf.begin()) - 1;
        i = std::clamp(i, 0, kBins - 1);
        float span = cdf[i + 1] - cdf[i];
        float t = span > 0 ? (u - cdf[i]) / span : 0.5f;
        *pdf = m_pdf[a][i];
        return -r + (i + t) * 2 * r / kBins;
    }
    Vec2 m_r;
    float m_sigma;
    std::vector<float> m_cdf[2];
    float m_pdf[2][kBins];
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
