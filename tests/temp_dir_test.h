// A test fixture with a folder of its own under the system's temporary folder, named after the
// process and the test, made before each test and removed after it.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <utility>

namespace ml::test {

class TempDirTest : public ::testing::Test {
protected:
    // `prefix` names the suite's folders: /tmp/manylight-PREFIX-PID-TEST.
    explicit TempDirTest(std::string prefix) : m_prefix(std::move(prefix)) {}
    void SetUp() override {
        m_dir = std::filesystem::temp_directory_path() /
                ("manylight-" + m_prefix + "-" + std::to_string(::getpid()) + "-" +
                 ::testing::UnitTest::GetInstance()->current_test_info()->name());
        std::filesystem::create_directories(m_dir);
    }
    void TearDown() override { std::filesystem::remove_all(m_dir); }
    std::string path(const std::string& name) const { return (m_dir / name).string(); }

    std::filesystem::path m_dir;

private:
    std::string m_prefix;
};

}  // namespace ml::test
