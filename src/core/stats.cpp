#include "core/stats.h"

#include <memory>
#include <mutex>
#include <vector>

namespace ml::stats {

namespace {

std::mutex g_mutex;
std::vector<std::unique_ptr<RayCounts>>& registry() {
    static std::vector<std::unique_ptr<RayCounts>> all;
    return all;
}

}  // namespace

RayCounts& local() {
    thread_local RayCounts* mine = [] {
        std::lock_guard<std::mutex> lock(g_mutex);
        registry().push_back(std::make_unique<RayCounts>());
        return registry().back().get();
    }();
    return *mine;
}

RayCounts total() {
    std::lock_guard<std::mutex> lock(g_mutex);
    RayCounts sum;
    for (auto& c : registry()) {
        sum.camera += c->camera;
        sum.closest += c->closest;
        sum.shadow += c->shadow;
        sum.nonfinite_splats += c->nonfinite_splats;
    }
    return sum;
}

void reset() {
    std::lock_guard<std::mutex> lock(g_mutex);
    for (auto& c : registry()) *c = RayCounts();
}

}  // namespace ml::stats
