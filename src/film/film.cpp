#include "film/film.h"

#include "core/assert.h"

namespace ml {

Film::Film(int width, int height, float max_component_value, float imaging_ratio)
    : m_width(width),
      m_height(height),
      m_max_component(max_component_value),
      m_imaging_ratio(imaging_ratio),
      m_pixels(size_t(width) * height),
      m_splats(size_t(width) * height * 3) {
    clear();
}

void Film::clear() {
    for (Pixel& p : m_pixels) p = Pixel();
    for (auto& s : m_splats) s.store(0.f, std::memory_order_relaxed);
    m_nonfinite.store(0, std::memory_order_relaxed);
}

void Film::reduce_to_root(World& world) {
    if (world.size() == 1) return;
    bool any_sample = false, any_splat = false;
    for (const Pixel& p : m_pixels) any_sample = any_sample || p.weight != 0;
    for (const auto& s : m_splats) any_splat = any_splat || s.load(std::memory_order_relaxed) != 0;
    if (world.all_sum(any_sample ? 1 : 0) > 0) {
        std::vector<double> all = sums();
        world.reduce_sum(all.data(), all.size());
        if (world.root()) set_sums(all, nonfinite_samples());
    }
    if (world.all_sum(any_splat ? 1 : 0) > 0) {
        std::vector<float> splats(m_splats.size());
        for (size_t i = 0; i < splats.size(); ++i)
            splats[i] = m_splats[i].load(std::memory_order_relaxed);
        world.reduce_sum(splats.data(), splats.size());
        if (world.root())
            for (size_t i = 0; i < splats.size(); ++i)
                m_splats[i].store(splats[i], std::memory_order_relaxed);
    }
    uint64_t dropped = uint64_t(world.all_sum(int64_t(nonfinite_samples())));
    m_nonfinite.store(dropped, std::memory_order_relaxed);
}

std::vector<double> Film::sums() const {
    std::vector<double> sums(m_pixels.size() * 4);
    for (size_t i = 0; i < m_pixels.size(); ++i) {
        const Pixel& p = m_pixels[i];
        double* d = &sums[i * 4];
        d[0] = p.rgb[0], d[1] = p.rgb[1], d[2] = p.rgb[2], d[3] = p.weight;
    }
    return sums;
}

void Film::set_sums(const std::vector<double>& sums, uint64_t nonfinite) {
    ML_ASSERT(sums.size() == m_pixels.size() * 4, "film sums of another size");
    for (size_t i = 0; i < m_pixels.size(); ++i) {
        Pixel& p = m_pixels[i];
        const double* d = &sums[i * 4];
        p.rgb[0] = d[0], p.rgb[1] = d[1], p.rgb[2] = d[2], p.weight = d[3];
    }
    m_nonfinite.store(nonfinite, std::memory_order_relaxed);
}

size_t Film::pixels_without_samples() const {
    size_t n = 0;
    for (const Pixel& p : m_pixels) n += p.weight == 0;
    return n;
}

void Film::add_sample(Point2i p, RGB L, float weight) {
    ML_ASSERT(p.x >= 0 && p.y >= 0 && p.x < m_width && p.y < m_height,
              fmt::format("pixel ({}, {}) outside the {}x{} film", p.x, p.y, m_width, m_height));
    // Drop what cannot be a radiance (a NaN would poison the pixel), counted for --stats, and
    // clamp, if asked, as pbrt's "maxcomponentvalue" does.
    if (!L.is_finite()) {
        m_nonfinite.fetch_add(1, std::memory_order_relaxed);
        return;
    }
    L *= m_imaging_ratio;  // the sensor's response first, then the clamp, as pbrt-v4
    float m = L.max_component();
    if (m > m_max_component) L *= m_max_component / m;
    Pixel& px = m_pixels[size_t(p.y) * m_width + p.x];
    px.rgb[0] += double(L.r) * weight;
    px.rgb[1] += double(L.g) * weight;
    px.rgb[2] += double(L.b) * weight;
    px.weight += weight;
}

void Film::add_splat(const Vec2& p_film, RGB v) {
    int x = int(std::floor(p_film.x)), y = int(std::floor(p_film.y));
    if (!v.is_finite()) {
        m_nonfinite.fetch_add(1, std::memory_order_relaxed);
        return;
    }
    if (x < 0 || y < 0 || x >= m_width || y >= m_height) return;
    v *= m_imaging_ratio;
    size_t i = (size_t(y) * m_width + x) * 3;
    for (int c = 0; c < 3; ++c) m_splats[i + c].fetch_add(v[c], std::memory_order_relaxed);
}

Image Film::to_image(float splat_scale) const {
    Image img(m_width, m_height);
    for (size_t i = 0; i < m_pixels.size(); ++i) {
        const Pixel& p = m_pixels[i];
        RGB c;
        if (p.weight != 0)
            c = RGB(float(p.rgb[0] / p.weight), float(p.rgb[1] / p.weight),
                    float(p.rgb[2] / p.weight));
        for (int k = 0; k < 3; ++k)
            c[k] += splat_scale * m_splats[3 * i + k].load(std::memory_order_relaxed);
        img.pixels[i] = c;
    }
    return img;
}

}  // namespace ml
