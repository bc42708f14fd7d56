// `manylight integrators [NAME]`: the integrators, what each is for, and the settings each reads
// with their defaults, from the registry (integrator_settings), as the Python module's
// integrators() lists them. `--markdown`: the settings reference, docs/settings.md.
#include <cstdio>

#include "commands.h"
#include "core/error.h"
#include "integrators/registry.h"
#include "integrators/settings_reference.h"

namespace ml {

void add_integrators_command(CLI::App& app, IntegratorsArgs& a) {
    CLI::App* c = app.add_subcommand(
        "integrators", "list the integrators and the settings (--set NAME.KEY=VALUE) each reads");
    c->add_option("name", a.name, "only this integrator");
    c->add_flag("--markdown", a.markdown,
                "every integrator's settings with type, default, range and description, as "
                "Markdown (docs/settings.md)");
}

int run_integrators(const IntegratorsArgs& a) {
    if (!a.name.empty() && !find_integrator(a.name))
        throw UsageError("integrators: unknown integrator \"" + a.name + "\"");
    if (a.markdown) {
        if (!a.name.empty()) throw UsageError("integrators: --markdown lists every integrator");
        std::fputs(settings_markdown().c_str(), stdout);
        return 0;
    }
    for (const IntegratorInfo& info : integrator_registry()) {
        if (!a.name.empty() && info.name != a.name) continue;
        std::printf("%s: %s\n", info.name.c_str(), info.summary.c_str());
        for (const SettingDefault& d : integrator_settings(info))
            std::printf("  %s=%s (%s)\n", d.key.c_str(), d.value.c_str(), d.type.c_str());
    }
    return 0;
}

}  // namespace ml
