#include "film/image_metrics.h"

#include <algorithm>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

namespace ml {

namespace {

// Cropped images (a data window inside a display window) compare pixel for pixel only when
// they hold the same crop; a whole image is its own display window.
void require_same_window(const Image& a, const Image& b) {
    if (a.width != b.width || a.height != b.height)
        throw UsageError("images differ in size: " + std::to_string(a.width) + "x" +
                         std::to_string(a.height) + " and " + std::to_string(b.width) + "x" +
                         std::to_string(b.height));
    auto full = [](const Image& i) {
        return std::pair(i.full_width ? i.full_width : i.width,
                         i.full_height ? i.full_height : i.height);
    };
    if (a.x != b.x || a.y != b.y || full(a) != full(b))
        throw UsageError(fmt::format(
            "images differ in their data window: {}x{} at ({}, {}) of {}x{} and {}x{} at ({}, "
            "{}) of {}x{}",
            a.width, a.height, a.x, a.y, full(a).first, full(a).second, b.width, b.height, b.x, b.y,
            full(b).first, full(b).second));
}

}  // namespace

ImageDiff compare_images(const Image& a, const Image& b) {
    require_same_window(a, b);
    ImageDiff d;
    double rel = 0, se = 0, sa[3] = {0, 0, 0}, sb[3] = {0, 0, 0};
    for (size_t i = 0; i < a.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            double x = a.pixels[i][c], r = b.pixels[i][c];
            rel += (x - r) * (x - r) / (r * r + 1e-2);
            se += (x - r) * (x - r);
            sa[c] += x;
            sb[c] += r;
        }
    double n = double(a.pixels.size());
    d.rel_mse = rel / (3 * n);
    d.rmse = std::sqrt(se / (3 * n));
    for (int c = 0; c < 3; ++c) {
        d.mean_a[c] = float(sa[c] / n);
        d.mean_b[c] = float(sb[c] / n);
        d.mean_rel_diff[c] = sb[c] != 0 ? float((sa[c] - sb[c]) / sb[c]) : 0.f;
    }
    return d;
}

Image box_downsample(const Image& img, int k) {
    if (k <= 0 || img.width % k || img.height % k)
        throw UsageError("box_downsample: size is not a multiple of the factor");
    Image out(img.width / k, img.height / k);
    for (int y = 0; y < out.height; ++y)
        for (int x = 0; x < out.width; ++x) {
            RGB s;
            for (int j = 0; j < k; ++j)
                for (int i = 0; i < k; ++i) s += img.at(x * k + i, y * k + j);
            out.at(x, y) = s / float(k * k);
        }
    return out;
}

std::vector<BlockDiff> worst_blocks(const Image& a, const Image& ref, int block, int count,
                                    float min_mean, bool per_channel) {
    if (block <= 0) throw UsageError("worst_blocks: the block is not positive");
    require_same_window(a, ref);
    // The whole blocks only.
    auto whole = [&](const Image& img) {
        Image c((img.width / block) * block, (img.height / block) * block);
        for (int y = 0; y < c.height; ++y)
            for (int x = 0; x < c.width; ++x) c.at(x, y) = img.at(x, y);
        return box_downsample(c, block);
    };
    Image ba = whole(a), br = whole(ref);
    std::vector<BlockDiff> all;
    for (int y = 0; y < ba.height; ++y)
        for (int x = 0; x < ba.width; ++x) {
            if (!per_channel) {
                float r = br.at(x, y).average();
                if (r >= min_mean) all.push_back({x, y, -1, ba.at(x, y).average(), r});
                continue;
            }
            for (int c = 0; c < 3; ++c) {
                float r = br.at(x, y)[c];
                if (r >= min_mean) all.push_back({x, y, c, ba.at(x, y)[c], r});
            }
        }
    size_t n = std::min(all.size(), size_t(std::max(count, 0)));
    std::partial_sort(all.begin(), all.begin() + n, all.end(),
                      [](const BlockDiff& p, const BlockDiff& q) { return p.rel() > q.rel(); });
    all.resize(n);
    return all;
}

double max_block_rel_diff(const Image& a, const Image& ref, int block, float min_mean,
                          bool per_channel) {
    auto w = worst_blocks(a, ref, block, 1, min_mean, per_channel);
    return w.empty() ? 0.0 : w[0].rel();
}

}  // namespace ml
