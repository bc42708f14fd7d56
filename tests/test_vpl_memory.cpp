// VPL counts that do not fit in memory (manylight/vpl_memory.h): `lightcuts` and `mdlightcuts`
// stop before building the set, with a message that says how many VPLs fit, rather than being
// killed part way; the available memory is set small through MANYLIGHT_TEST_AVAILABLE_MB, so
// that no large machine is needed. The estimate is checked against the process's measured peak
// memory (--stats), which it must hold, without exceeding it several times over.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>

#include "core/memory.h"
#include "manylight/vpl_memory.h"
#include "vpl_test_scenes.h"

namespace ml {
namespace {

namespace fs = std::filesystem;

struct Outcome {
    int code = -1;
    std::string output;
};

Outcome run_program(const std::string& env, const std::string& args) {
    std::string cmd = env + " " + std::string(MANYLIGHT_BINARY) + " " + args + " 2>&1";
    Outcome r;
    FILE* p = popen(cmd.c_str(), "r");
    char buf[4096];
    size_t n;
    while ((n = fread(buf, 1, sizeof buf, p)) > 0) r.output.append(buf, n);
    int status = pclose(p);
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    return r;
}

class VplMemory : public ::testing::TestWithParam<const char*> {
protected:
    void SetUp() override {
        m_dir = fs::temp_directory_path() / ("manylight-vpl-memory-" + std::to_string(getpid()));
        fs::create_directories(m_dir);
        m_scene = (m_dir / "box.pbrt").string();
        std::ofstream(m_scene) << R"(LookAt 0 1 -4  0 0.5 0  0 1 0
Camera "perspective" "float fov" [ 50 ]
Film "rgb" "integer xresolution" [ 8 ] "integer yresolution" [ 8 ]
WorldBegin
)" + vpl_test::mixed_box();
    }
    void TearDown() override { fs::remove_all(m_dir); }
    // A 1 spp render of the box with `vpls` VPLs and `mb` MB available; its --stats in *stats.
    Outcome render(int64_t vpls, int mb, nlohmann::json* stats = nullptr) {
        std::string json = (m_dir / "stats.json").string();
        fs::remove(json);
        Outcome r = run_program(
            fmt::format("MANYLIGHT_TEST_AVAILABLE_MB={}", mb),
            fmt::format("render {} --integrator {} --spp 1 --threads 2 --set vpl.count={} "
                        "-q -o {} --stats {}",
                        m_scene, GetParam(), vpls, (m_dir / "out.exr").string(), json));
        if (stats && r.code == 0) *stats = nlohmann::json::parse(std::ifstream(json));
        return r;
    }
    fs::path m_dir;
    std::string m_scene;
};

// The count asked does not fit: exit 2 before building anything, no image, and the message
// names the count that fits; that count renders.
TEST_P(VplMemory, ACountThatDoesNotFitStopsEarlySayingHowManyFit) {
    constexpr int kMb = 48;
    Outcome big = render(10'000'000, kMb);
    EXPECT_EQ(big.code, 2) << big.output;
    EXPECT_FALSE(fs::exists(m_dir / "out.exr"));
    EXPECT_NE(big.output.find("vpl.count=10000000 needs about"), std::string::npos) << big.output;
    std::smatch m;
    ASSERT_TRUE(std::regex_search(big.output, m, std::regex(R"(about (\d+) VPLs fit)")))
        << big.output;
    const int64_t fit = std::stoll(m[1]);
    // What the message says fits is the share of the memory over the bytes per VPL it names.
    const double per_vpl = double(point_light_peak_bytes(kLightTreeReps, true));
    EXPECT_NEAR(double(fit), kMemoryShare * double(int64_t(kMb) << 20) / per_vpl, 1.0);
    ASSERT_GT(fit, 1000);
    Outcome ok = render(fit, kMb);
    EXPECT_EQ(ok.code, 0) << ok.output;
    Outcome over = render(fit * 11 / 10, kMb);
    EXPECT_EQ(over.code, 2) << over.output;
}

// The estimate holds what the VPLs and their tree really take: the measured peak memory of a
// render with n VPLs less that of one with very few is at most the estimate, and at least a
// third of it (an estimate many times too large would refuse renders that fit).
TEST_P(VplMemory, EstimateHoldsTheMeasuredPeak) {
    constexpr int64_t kVpls = 300'000;
    nlohmann::json few, many;
    ASSERT_EQ(render(1000, 1 << 20, &few).code, 0);
    ASSERT_EQ(render(kVpls, 1 << 20, &many).code, 0);
    const double measured =
        (many["memory"]["peak_rss_mb"].get<double>() - few["memory"]["peak_rss_mb"].get<double>()) *
        double(1 << 20);
    const double estimate =
        double(point_light_peak_bytes(kLightTreeReps, true)) * double(kVpls - 1000);
    std::printf("%s: %lld VPLs, measured %.1f MB (%.0f bytes per VPL), estimated %.1f MB\n",
                GetParam(), static_cast<long long>(kVpls), measured / double(1 << 20),
                measured / double(kVpls - 1000), estimate / double(1 << 20));
    EXPECT_LE(measured, estimate);
    EXPECT_GE(measured, estimate / 3);
}

INSTANTIATE_TEST_SUITE_P(ManyLight, VplMemory, ::testing::Values("lightcuts", "mdlightcuts"));

TEST(AvailableMemory, ReadFromTheSystemUnlessOverridden) {
    std::optional<uint64_t> real = available_memory_bytes();
    ASSERT_TRUE(real);  // Linux: /proc/meminfo
    EXPECT_GT(*real, uint64_t(16) << 20);
    setenv("MANYLIGHT_TEST_AVAILABLE_MB", "48", 1);
    std::optional<uint64_t> set = available_memory_bytes();
    unsetenv("MANYLIGHT_TEST_AVAILABLE_MB");
    EXPECT_EQ(set, uint64_t(48) << 20);
}

}  // namespace
}  // namespace ml
