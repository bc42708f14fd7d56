#include "core/progress.h"

#include <unistd.h>

#include <cstdio>

namespace ml {

Progress::Progress(std::string title, bool enabled, std::function<void(double)> observer)
    : m_title(std::move(title)),
      m_enabled(enabled && isatty(fileno(stderr))),
      m_observer(std::move(observer)) {
    m_start = m_last_draw = std::chrono::steady_clock::now();
    if (m_enabled) draw(0.0);
}

void Progress::set_fraction(double f) {
    f = m_from + f * (m_to - m_from);
    if (m_observer) m_observer(f);
    if (!m_enabled) return;
    std::lock_guard<std::mutex> lock(m_mutex);
    auto now = std::chrono::steady_clock::now();
    if (now - m_last_draw < std::chrono::milliseconds(100)) return;
    m_last_draw = now;
    draw(f);
}

void Progress::done() {
    std::lock_guard<std::mutex> lock(m_mutex);
    if (!m_enabled || m_finished) return;
    m_finished = true;
    draw(1.0);
    std::fputc('\n', stderr);
}

void Progress::draw(double f) {
    constexpr int kWidth = 40;
    f = f < 0 ? 0 : (f > 1 ? 1 : f);
    int filled = int(f * kWidth);
    double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count();
    std::string bar(filled, '#');
    bar += std::string(kWidth - filled, '.');
    if (f > 0.01 && f < 1.0)
        std::fprintf(stderr, "\r%s [%s] %3d%% %6.1fs (~%.0fs left) ", m_title.c_str(), bar.c_str(),
                     int(f * 100), elapsed, elapsed / f - elapsed);
    else
        std::fprintf(stderr, "\r%s [%s] %3d%% %6.1fs            ", m_title.c_str(), bar.c_str(),
                     int(f * 100), elapsed);
    std::fflush(stderr);
}

}  // namespace ml
