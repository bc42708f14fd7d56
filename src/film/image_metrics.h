// Comparing images the way DESIGN.md section 4 asks: relMSE, RMSE, the relative difference of
// each channel's mean, and block means for structure at a coarser scale.
#pragma once

#include <cmath>
#include <vector>

#include "film/image.h"

namespace ml {

struct ImageDiff {
    double rel_mse = 0;  // mean over pixels and channels of (x - r)^2 / (r^2 + 1e-2)
    double rmse = 0;     // sqrt of the mean squared difference
    RGB mean_a, mean_b;  // per-channel image means
    RGB mean_rel_diff;   // (mean_a - mean_b) / mean_b per channel
};

// Compares `a` against the reference `b`; they must have the same size.
ImageDiff compare_images(const Image& a, const Image& b);

// Averages k x k blocks (the image size must be a multiple of k).
Image box_downsample(const Image& img, int k);

// The largest relative difference of a block's channel mean, over all whole `block` x `block`
// blocks (from the top-left corner: the pixels past the last whole block of a row or column are
// in none, as the bottom 4 rows of a 320x180 image with 16x16 blocks), ignoring blocks whose
// reference mean is below `min_mean` in that channel.
double max_block_rel_diff(const Image& a, const Image& ref, int block, float min_mean = 1e-3f,
                          bool per_channel = true);

struct BlockDiff {
    int x = 0, y = 0, channel = 0;  // block column, row and channel
    float a = 0, ref = 0;           // the two block means
    double rel() const { return std::abs(a - ref) / ref; }
};
// The `count` whole blocks with the largest relative difference, worst first: per channel, or of
// the mean of the three channels (channel = -1 in the result) when `per_channel` is false.
std::vector<BlockDiff> worst_blocks(const Image& a, const Image& ref, int block, int count,
                                    float min_mean = 1e-3f, bool per_channel = true);

}  // namespace ml
