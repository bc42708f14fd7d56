// A progress bar on standard error: drawn only on a terminal, at most ten times a second.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>

namespace ml {

class Progress {
public:
    // `observer`, if any, is given every fraction set_fraction is, from the thread that sets it
    // (render threads: it must be cheap and thread-safe), whether the bar is drawn or not.
    Progress(std::string title, bool enabled, std::function<void(double)> observer = {});
    ~Progress() { done(); }
    // Sets the fraction of the work done, in [0, 1] (of the span's part, see set_span).
    void set_fraction(double f);
    // Until the next call, set_fraction(f) stands for from + f (to - from) of the whole: a part
    // of the work that reports its own progress (a block of passes). Call while nothing reports.
    void set_span(double from, double to) { m_from = from, m_to = to; }
    void done();

private:
    void draw(double f);
    std::string m_title;
    bool m_enabled;
    std::function<void(double)> m_observer;
    bool m_finished = false;
    double m_from = 0, m_to = 1;
    std::mutex m_mutex;
    std::chrono::steady_clock::time_point m_start, m_last_draw;
};

}  // namespace ml
