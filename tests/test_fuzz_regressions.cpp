// Every input the fuzzers (fuzz/) found a crash, hang or sanitizer report with, replayed through
// the same entry point (fuzz/entry_points.h): each must now end in a clean error, an InputError
// with the place (scenes and meshes) or a UsageError (the viewer's messages). The inputs live in
// fuzz/regressions/<target>/, one file each, named after what went wrong.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "entry_points.h"

namespace {

std::vector<std::filesystem::path> regressions(const std::string& target) {
    std::vector<std::filesystem::path> files;
    for (const auto& e : std::filesystem::directory_iterator(
             std::filesystem::path(MANYLIGHT_SOURCE_DIR) / "fuzz" / "regressions" / target))
        if (e.is_regular_file()) files.push_back(e.path());
    std::sort(files.begin(), files.end());
    return files;
}

std::string contents(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// Each input of `target` through `entry` throws `E`, whose message is not empty.
template <typename E, typename F>
void expect_clean_errors(const std::string& target, F entry, size_t at_least) {
    auto files = regressions(target);
    EXPECT_GE(files.size(), at_least) << "fuzz/regressions/" << target << " lost its inputs";
    for (const auto& f : files) {
        SCOPED_TRACE(f.filename().string());
        try {
            entry(contents(f));
            ADD_FAILURE() << "no error for " << f;
        } catch (const E& e) {
            EXPECT_NE(std::string(e.what()), "");
        }
    }
}

}  // namespace

TEST(FuzzRegressions, Ply) { expect_clean_errors<ml::InputError>("ply", ml::fuzz::read_ply, 1); }
