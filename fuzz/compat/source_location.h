// Included before every source of the fuzz build (fuzz/CMakeLists.txt): Debian 12's clang 14
// lacks the __builtin_source_location that libstdc++ 12's <source_location> needs, so that header
// declares nothing there. This supplies std::source_location from the builtins clang 14 does
// have (file and line, what core/error.h reports), for the fuzz build alone; GCC builds never
// see it.
#pragma once

#include <version>

#if !defined(__cpp_lib_source_location) && defined(__clang__)
#include <cstdint>
#include <source_location>

namespace std {
struct source_location {
    static constexpr source_location current(const char* file = __builtin_FILE(),
                                             const char* function = __builtin_FUNCTION(),
                                             uint_least32_t line = __builtin_LINE()) noexcept {
        source_location s;
        s.m_file = file;
        s.m_function = function;
        s.m_line = line;
        return s;
    }
    constexpr const char* file_name() const noexcept { return m_file; }
    constexpr const char* function_name() const noexcept { return m_function; }
    constexpr uint_least32_t line() const noexcept { return m_line; }
    constexpr uint_least32_t column() const noexcept { return 0; }

private:
    const char* m_file = "";
    const char* m_function = "";
    uint_least32_t m_line = 0;
};
}  // namespace std
#endif
