// A progress bar on standard error: drawn only on a terminal, at most ten times a second.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace ml {

class Progress {
public:
    Progress(std::string title, bool enabled);
    ~Progress() { done(); }
    // Sets the fraction of the work done, in [0, 1].
    void set_fraction(double f);
    void done();

private:
    void draw(double f);
    std::string m_title;
    bool m_enabled;
    bool m_finished = false;
    std::mutex m_mutex;
    std::chrono::steady_clock::time_point m_start, m_last_draw;
};

}  // namespace ml
