// Errors: one hierarchy under ml::Error, so that the command line can tell whose fault a failure
// is. Library code never exits; it throws
//   - InputError: bad input (a scene, mesh, image or parameter), with the place it came from; the
//     command line prints `file:line:col: message` (with the source line and a caret when the
//     file can be read) and exits with status 1;
//   - UsageError: a bad command-line option or --set value; exit status 2;
//   - InternalError: a broken invariant or a library (Embree) reporting a failure, with the
//     source location that raised it; exit status 1 (as any other failure).
// Assertions (core/assert.h) raise InternalError too.
#pragma once

#include <fmt/format.h>

#include <source_location>
#include <stdexcept>
#include <string>

namespace ml {

struct FileLoc {
    std::string file;  // empty: no file (command line, built-in scene)
    int line = 0;      // 1-based; 0 when unknown
    int column = 0;    // 1-based; 0 when unknown
    std::string to_string() const;
};

// The base of every error manylight raises.
class Error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// Bad input: a scene, mesh, image or parameter that cannot be used.
class InputError : public Error {
public:
    InputError(FileLoc loc, const std::string& message) : Error(message), m_loc(std::move(loc)) {}
    const FileLoc& loc() const { return m_loc; }
    // `file:line:col: message`, followed by the offending source line and a caret when known.
    std::string formatted() const;

private:
    FileLoc m_loc;
};

// A command-line option, --set key or setting value that cannot be used (or that nobody reads).
class UsageError : public Error {
public:
    using Error::Error;
};

// A bug: an invariant that does not hold, or a library failing where it should not. what() is
// `file:line: message` of the code that raised it.
class InternalError : public Error {
public:
    explicit InternalError(const std::string& message,
                           std::source_location where = std::source_location::current());
};

template <typename... Args>
[[noreturn]] void throw_input_error(const FileLoc& loc, fmt::format_string<Args...> f,
                                    Args&&... args) {
    throw InputError(loc, fmt::format(f, std::forward<Args>(args)...));
}

}  // namespace ml
