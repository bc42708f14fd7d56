#include "manylight/pilot.h"

#include <cmath>
#include <vector>

#include "core/parallel.h"

namespace ml {

double pilot_mean_luminance(int width, int height,
                            const std::function<RGB(Point2i pixel)>& estimate) {
    const int w = width, h = height;
    if (w <= 0 || h <= 0) return 0;
    // A grid of about kPilotPixels pixels, each at the middle of its cell.
    int step = std::max(1, int(std::lround(std::sqrt(double(w) * h / kPilotPixels))));
    int nx = (w + step - 1) / step, ny = (h + step - 1) / step;
    std::vector<double> values(size_t(nx) * ny, 0.0);
    parallel_for(size_t(0), values.size(), [&](size_t i) {
        Point2i pixel{std::min(w - 1, int(i % size_t(nx)) * step + step / 2),
                      std::min(h - 1, int(i / size_t(nx)) * step + step / 2)};
        RGB v = estimate(pixel);
        double l = v.luminance();
        values[i] = std::isfinite(l) ? std::max(0.0, l) : 0.0;
    });
    double sum = 0;
    for (double v : values) sum += v;  // in grid order: the same for any schedule
    return sum / double(values.size());
}

}  // namespace ml
