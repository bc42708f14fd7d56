// Errors: every problem with input is an exception carrying the place it came from. Library code
// never exits; the command line prints `file:line:col: message` (with the source line and a
// caret when the file can be read) and exits with status 1.
#pragma once

#include <fmt/format.h>

#include <stdexcept>
#include <string>

namespace ml {

struct FileLoc {
    std::string file;  // empty: no file (command line, built-in scene)
    int line = 0;      // 1-based; 0 when unknown
    int column = 0;    // 1-based; 0 when unknown
    std::string to_string() const;
};

// Bad input: a scene, mesh, image or parameter that cannot be used.
class InputError : public std::runtime_error {
public:
    InputError(FileLoc loc, const std::string& message)
        : std::runtime_error(message), m_loc(std::move(loc)) {}
    const FileLoc& loc() const { return m_loc; }
    // `file:line:col: message`, followed by the offending source line and a caret when known.
    std::string formatted() const;

private:
    FileLoc m_loc;
};

template <typename... Args>
[[noreturn]] void throw_input_error(const FileLoc& loc, fmt::format_string<Args...> f,
                                    Args&&... args) {
    throw InputError(loc, fmt::format(f, std::forward<Args>(args)...));
}

}  // namespace ml
