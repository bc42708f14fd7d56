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
    // Sets the fraction of the work done, in [0, 1].
    void set_fraction(double f);
    void done();

private:
    void draw(double f);
    std::string m_title;
    bool m_enabled;
    std::function<void(double)> m_observer;
    bool m_finished = false;
    std::mutex m_mutex;
    std::chrono::steady_clock::time_point m_start, m_last_draw;
};

}  // namespace ml
