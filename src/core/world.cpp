#include "core/world.h"

#include <cstdio>
#include <cstdlib>

namespace ml {

void LocalWorld::abort(const std::string& message, int code) {
    std::fprintf(stderr, "%s\n", message.c_str());
    std::fflush(stderr);
    std::_Exit(code);
}

World& local_world() {
    static LocalWorld world;
    return world;
}

}  // namespace ml
