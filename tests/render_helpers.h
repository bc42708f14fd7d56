// Helpers for statistical render tests: render scene text in-process, image statistics.
#pragma once

#include <cmath>
#include <string>

#include "film/image.h"
#include "integrators/render_job.h"
#include "scene/scene_desc.h"

namespace ml::test {

inline RenderOutput render_text(const std::string& text, RenderOptions opt) {
    opt.progress = false;
    return render_scene(parse_scene_string(text, "."), opt);
}

struct ChannelStats {
    double mean = 0, stderr_of_mean = 0;
};

// Mean of one channel over the image and the standard error of that mean, treating pixels as
// independent samples (true for per-pixel sample sequences).
inline ChannelStats channel_stats(const Image& img, int c) {
    double s = 0, s2 = 0;
    size_t n = img.pixels.size();
    for (const RGB& p : img.pixels) {
        s += p[c];
        s2 += double(p[c]) * p[c];
    }
    ChannelStats st;
    st.mean = s / n;
    double var = std::max(0.0, s2 / n - st.mean * st.mean);
    st.stderr_of_mean = std::sqrt(var / (n - 1));
    return st;
}

}  // namespace ml::test
