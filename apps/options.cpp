#include "options.h"

#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <filesystem>

namespace ml {

namespace {

std::string got(const std::string& s) { return ", got \"" + s + "\""; }

// The whole string as a decimal integer, or false.
bool parse_integer(const std::string& s, long long& v) {
    if (s.empty() || s.find_first_not_of("+-0123456789") != std::string::npos) return false;
    errno = 0;
    char* end = nullptr;
    v = std::strtoll(s.c_str(), &end, 10);
    return errno == 0 && end == s.c_str() + s.size();
}

CLI::Validator integer_at_least(long long lowest, long long highest, const std::string& what) {
    return CLI::Validator(
        [=](std::string& s) -> std::string {
            long long v = 0;
            if (!parse_integer(s, v) || v < lowest || v > highest)
                return "expected " + what + got(s);
            return {};
        },
        what);
}

}  // namespace

CLI::Validator positive_integer() { return integer_at_least(1, INT_MAX, "a positive integer"); }
CLI::Validator non_negative_integer() {
    return integer_at_least(0, INT_MAX, "a non-negative integer");
}
CLI::Validator seed_value() { return integer_at_least(0, LLONG_MAX, "a non-negative integer"); }

CLI::Validator positive_seconds() {
    return CLI::Validator(
        [](std::string& s) -> std::string {
            char* end = nullptr;
            double v = s.empty() ? 0 : std::strtod(s.c_str(), &end);
            if (s.empty() || end != s.c_str() + s.size() || !std::isfinite(v) || v <= 0)
                return "expected a positive number of seconds" + got(s);
            return {};
        },
        "SECONDS");
}

CLI::Validator non_negative_seconds() {
    return CLI::Validator(
        [](std::string& s) -> std::string {
            char* end = nullptr;
            double v = s.empty() ? 0 : std::strtod(s.c_str(), &end);
            if (s.empty() || end != s.c_str() + s.size() || !std::isfinite(v) || v < 0)
                return "expected a number of seconds, 0 or more" + got(s);
            return {};
        },
        "SECONDS");
}

CLI::Validator share_of_time() {
    return CLI::Validator(
        [](std::string& s) -> std::string {
            char* end = nullptr;
            double v = s.empty() ? 0 : std::strtod(s.c_str(), &end);
            if (s.empty() || end != s.c_str() + s.size() || !(v > 0 && v <= 0.5))
                return "expected a share of the time in (0, 0.5], e.g. 0.1" + got(s);
            return {};
        },
        "SHARE");
}

CLI::Validator image_size() {
    return CLI::Validator(
        [](std::string& s) -> std::string {
            size_t x = s.find_first_of("xX");
            long long w = 0, h = 0;
            if (x == std::string::npos || !parse_integer(s.substr(0, x), w) ||
                !parse_integer(s.substr(x + 1), h) || w <= 0 || h <= 0 || w > 65536 || h > 65536)
                return "expected WIDTHxHEIGHT, e.g. 640x360" + got(s);
            return {};
        },
        "WxH");
}

CLI::Validator one_of(const std::vector<std::string>& names, const std::string& what) {
    std::string list;
    for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
    return CLI::Validator(
        [=](std::string& s) -> std::string {
            for (const std::string& n : names)
                if (s == n) return {};
            return "unknown " + what + " \"" + s + "\"; expected one of: " + list;
        },
        what);
}

CLI::Validator setting() {
    return CLI::Validator(
        [](std::string& s) -> std::string {
            size_t eq = s.find('=');
            if (eq == std::string::npos || eq == 0 || s.find('.') > eq)
                return "expected NAME.KEY=VALUE, e.g. vpl.count=100000" + got(s);
            return {};
        },
        "NAME.KEY=VALUE");
}

namespace {

// "" when the folder `s` names a file in exists, else the message.
std::string missing_folder(const std::string& s) {
    std::filesystem::path dir = std::filesystem::path(s).parent_path();
    std::error_code ec;
    if (!dir.empty() && !std::filesystem::is_directory(dir, ec))
        return "no such folder \"" + dir.string() + "\" for \"" + s + "\"";
    return {};
}

}  // namespace

CLI::Validator file_in_existing_folder() {
    return CLI::Validator([](std::string& s) { return missing_folder(s); }, "FILE");
}

CLI::Validator output_image() {
    return CLI::Validator(
        [](std::string& s) -> std::string {
            std::filesystem::path p(s);
            std::string ext = p.extension().string();
            for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
            if (ext != ".exr" && ext != ".png" && ext != ".pfm")
                return "expected an image name ending in .exr, .png or .pfm" + got(s);
            return missing_folder(s);
        },
        "FILE");
}

}  // namespace ml
