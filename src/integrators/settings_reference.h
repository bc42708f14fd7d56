// The settings reference (docs/settings.md): every integrator's settings with their type,
// default, range and description, from the registry and the SettingDoc beside each get_* call.
#pragma once

#include <string>
#include <vector>

#include "integrators/registry.h"

namespace ml {

// A setting as the reference lists it: `conditions` are the --set choices under which it is
// read ("vpl.sampler=power"), empty when it is always read.
struct SettingReference {
    SettingDefault setting;
    std::vector<std::string> conditions;
};

// Everything `info`'s integrator reads: what it reads with nothing set, then what it reads only
// under another value of one of those settings (each choice a string setting's range lists, the
// other value of a bool), in the order first read.
std::vector<SettingReference> integrator_settings_reference(const IntegratorInfo& info);

// The whole reference as Markdown: what `manylight integrators --markdown` prints and
// docs/settings.md holds.
std::string settings_markdown();

}  // namespace ml
