// The one table of integrators: name, what it is good for, and how to make it.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "render/integrator.h"
#include "render/settings.h"

namespace ml {

struct IntegratorInfo {
    std::string name;
    std::string summary;
    std::function<std::unique_ptr<Integrator>(const Settings&)> create;
};

const std::vector<IntegratorInfo>& integrator_registry();
// Null if no integrator has that name.
const IntegratorInfo* find_integrator(const std::string& name);
// Our integrator for a pbrt-v4 `Integrator` name ("volpath" -> "path"), or "" if none.
std::string integrator_for_pbrt_name(const std::string& pbrt_name);

}  // namespace ml
