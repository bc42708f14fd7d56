// docs/settings.md is `manylight integrators --markdown`: the descriptions live beside the code
// that reads each setting, and the page must be regenerated when one changes.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "integrators/settings_reference.h"

namespace ml {
namespace {

constexpr const char* kRegenerate =
    "regenerate it from the build folder: ./manylight integrators --markdown > "
    "../docs/settings.md (or build/manylight integrators --markdown > docs/settings.md from the "
    "repository root)";

TEST(SettingsReference, DocsPageIsTheGeneratedOutput) {
    const std::string path = std::string(MANYLIGHT_SOURCE_DIR) + "/docs/settings.md";
    std::ifstream in(path, std::ios::binary);
    ASSERT_TRUE(in) << path << " is missing; " << kRegenerate;
    std::stringstream page;
    page << in.rdbuf();
    const std::string want = settings_markdown();
    if (page.str() == want) return;
    // Name the first line that differs, so the failure says which setting changed.
    std::istringstream a(page.str()), b(want);
    std::string la, lb;
    int line = 1;
    while (true) {
        bool more_a = bool(std::getline(a, la)), more_b = bool(std::getline(b, lb));
        if (!more_a && !more_b) break;
        if (!more_a || !more_b || la != lb) break;
        ++line;
    }
    FAIL() << path << " differs from `manylight integrators --markdown` at line " << line
           << ":\n  page:      " << la << "\n  generated: " << lb << "\n"
           << kRegenerate;
}

TEST(SettingsReference, EverySettingHasADescriptionAndARange) {
    for (const IntegratorInfo& info : integrator_registry())
        for (const SettingReference& r : integrator_settings_reference(info)) {
            const SettingDefault& d = r.setting;
            EXPECT_FALSE(d.description.empty())
                << d.key << " (integrator " << info.name
                << ") has no description: give the SettingDoc argument of the get_" << d.type
                << " call that reads it";
            if (d.type != "bool") {
                EXPECT_FALSE(d.range.empty())
                    << d.key << " (integrator " << info.name << ") has no range in its SettingDoc";
            }
        }
}

TEST(SettingsReference, SettingsReadUnderAChoiceAreListedWithIt) {
    const IntegratorInfo* vpl = find_integrator("vpl");
    ASSERT_NE(vpl, nullptr);
    bool found = false;
    for (const SettingReference& r : integrator_settings_reference(*vpl))
        if (r.setting.key == "vpl.pilot_paths") {
            found = true;
            ASSERT_EQ(r.conditions.size(), 1u);
            EXPECT_EQ(r.conditions[0], "vpl.sampler=power");
        }
    EXPECT_TRUE(found) << "vpl.pilot_paths (read with vpl.sampler=power) is not listed";
}

}  // namespace
}  // namespace ml
