// Helpers for the parser tests: scratch files and checks of an InputError's place and message.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include "core/error.h"
#include "scene/scene_desc.h"

namespace ml::test {

// A fresh directory per test, removed afterwards.
class ScratchDir {
public:
    ScratchDir() {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        m_path = std::filesystem::temp_directory_path() /
                 ("manylight_" + std::string(info->test_suite_name()) + "_" + info->name() + "_" +
                  std::to_string(::getpid()));
        std::filesystem::remove_all(m_path);
        std::filesystem::create_directories(m_path);
    }
    ~ScratchDir() { std::filesystem::remove_all(m_path); }
    std::string path() const { return m_path.string(); }
    std::string file(const std::string& name) const { return (m_path / name).string(); }
    std::string write(const std::string& name, const std::string& text) const {
        std::ofstream out(file(name), std::ios::binary);
        out << text;
        return file(name);
    }

private:
    std::filesystem::path m_path;
};

// Runs `f`, which must throw an InputError at file:line:column whose message holds `fragment`.
inline void expect_input_error(const std::function<void()>& f, const std::string& file, int line,
                               int column, const std::string& fragment) {
    try {
        f();
        ADD_FAILURE() << "no InputError thrown (expected \"" << fragment << "\")";
    } catch (const InputError& e) {
        EXPECT_EQ(e.loc().file, file) << e.formatted();
        EXPECT_EQ(e.loc().line, line) << e.formatted();
        EXPECT_EQ(e.loc().column, column) << e.formatted();
        EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos)
            << "message: " << e.what() << "\nexpected to contain: " << fragment;
    }
}

// The same for scene text held in memory, named "test.pbrt".
inline void expect_scene_error(const std::string& text, int line, int column,
                               const std::string& fragment, const std::string& base_dir = ".") {
    expect_input_error([&] { parse_scene_string(text, base_dir, "test.pbrt"); }, "test.pbrt", line,
                       column, fragment);
}

}  // namespace ml::test
