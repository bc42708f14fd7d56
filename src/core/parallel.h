// Threads: the one place that includes TBB (tests/test_layering.cpp checks it). Parallel loops
// here promise nothing about which thread runs which index, so callers that need the same result
// for any schedule write to per-index slots and combine them in index order afterwards.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/blocked_range2d.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/global_control.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>
#include <tbb/task_group.h>

#include <cstddef>

namespace ml {

// A value per thread, made on first use by the thread (from a factory, or default-constructed).
template <typename T>
using ThreadLocal = tbb::enumerable_thread_specific<T>;

// Tasks run concurrently and waited for together.
using TaskGroup = tbb::task_group;

// The number of threads parallel work uses by default (the machine's hardware threads).
inline int default_thread_count() { return tbb::info::default_concurrency(); }

// While alive, at most `threads` threads run parallel work (the --threads option).
class ThreadLimit {
public:
    explicit ThreadLimit(int threads)
        : m_control(tbb::global_control::max_allowed_parallelism, size_t(threads)) {}

private:
    tbb::global_control m_control;
};

// fn(i) for every i in [begin, end).
template <typename Index, typename F>
void parallel_for(Index begin, Index end, const F& fn) {
    tbb::parallel_for(begin, end, fn);
}

// fn(b, e) over chunks [b, e) of [begin, end) of about `grain` indices: for loops whose body is
// too cheap to be a task of its own, or that reuse a per-chunk state.
template <typename Index, typename F>
void parallel_for_chunks(Index begin, Index end, Index grain, const F& fn) {
    tbb::parallel_for(tbb::blocked_range<Index>(begin, end, grain),
                      [&](const tbb::blocked_range<Index>& r) { fn(r.begin(), r.end()); });
}

// fn(y0, y1, x0, x1) over tiles of a width x height image about `tile` pixels on a side.
template <typename F>
void parallel_for_tiles(int width, int height, int tile, const F& fn) {
    tbb::parallel_for(tbb::blocked_range2d<int>(0, height, tile, 0, width, tile),
                      [&](const tbb::blocked_range2d<int>& r) {
                          fn(r.rows().begin(), r.rows().end(), r.cols().begin(), r.cols().end());
                      });
}

// Sorts [begin, end) in parallel (by operator<, or by `less`); not stable.
template <typename It>
void parallel_sort(It begin, It end) {
    tbb::parallel_sort(begin, end);
}

template <typename It, typename Less>
void parallel_sort(It begin, It end, const Less& less) {
    tbb::parallel_sort(begin, end, less);
}

}  // namespace ml
