// Files under ../shared (external scenes and pbrt-v4 references). A user's clone has no
// ../shared, so a test that needs one of them skips with one line naming the missing path; with
// MANYLIGHT_REQUIRE_SHARED=1 in the environment (CI) it fails instead, so CI never passes by
// skipping. MANYLIGHT_SHARED_DIR in the environment overrides the folder (the skip is tested so).
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

namespace ml::test {

inline std::string shared_dir() {
    const char* env = std::getenv("MANYLIGHT_SHARED_DIR");
    return env && *env ? env : MANYLIGHT_SHARED_DIR;
}

// `rel` is relative to the shared folder: "scenes/kitchen/scene-v4.pbrt".
inline std::string shared_path(const std::string& rel) { return shared_dir() + "/" + rel; }

inline bool shared_required() {
    const char* env = std::getenv("MANYLIGHT_REQUIRE_SHARED");
    return env && std::string(env) == "1";
}

}  // namespace ml::test

// In a test body, before anything that reads shared/REL: skip (or, in CI, fail) when it is missing.
#define ML_NEED_SHARED(rel)                                                                    \
    do {                                                                                       \
        const std::string ml_need_path_ = ::ml::test::shared_path(rel);                        \
        if (!std::filesystem::exists(ml_need_path_)) {                                         \
            if (::ml::test::shared_required())                                                 \
                FAIL() << "missing " << ml_need_path_ << " (MANYLIGHT_REQUIRE_SHARED=1)";      \
            else                                                                               \
                GTEST_SKIP() << "needs " << ml_need_path_                                      \
                             << ", which is missing (the shared scenes sit beside the clone)"; \
        }                                                                                      \
    } while (0)
