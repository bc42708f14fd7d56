#include "core/memory.h"

#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace ml {

namespace {

// The first number of a file ("max" or a missing file: none).
std::optional<uint64_t> read_number(const std::filesystem::path& path) {
    std::ifstream in(path);
    uint64_t v = 0;
    if (in >> v) return v;
    return std::nullopt;
}

std::optional<uint64_t> machine_available() {
    std::ifstream meminfo("/proc/meminfo");
    std::string line;
    while (std::getline(meminfo, line))
        if (line.rfind("MemAvailable:", 0) == 0) {
            std::istringstream in(line.substr(13));
            uint64_t kb = 0;
            if (in >> kb) return kb * 1024;
        }
#ifdef _SC_AVPHYS_PAGES
    long pages = sysconf(_SC_AVPHYS_PAGES), size = sysconf(_SC_PAGESIZE);
    if (pages > 0 && size > 0) return uint64_t(pages) * uint64_t(size);
#endif
    return std::nullopt;
}

// The least headroom (memory.max - memory.current) of the process's cgroup v2 group and the
// groups above it that set a limit.
std::optional<uint64_t> cgroup_available() {
    std::ifstream self("/proc/self/cgroup");
    std::string line, group;
    while (std::getline(self, line))
        if (line.rfind("0::", 0) == 0) group = line.substr(3);
    if (group.empty()) return std::nullopt;
    std::optional<uint64_t> least;
    for (std::filesystem::path dir = std::filesystem::path("/sys/fs/cgroup") / group.substr(1);;
         dir = dir.parent_path()) {
        std::optional<uint64_t> limit = read_number(dir / "memory.max");
        if (limit) {
            uint64_t used = read_number(dir / "memory.current").value_or(0);
            uint64_t left = *limit > used ? *limit - used : 0;
            least = least ? std::min(*least, left) : left;
        }
        if (dir == "/sys/fs/cgroup" || dir == dir.parent_path()) break;
    }
    return least;
}

}  // namespace

std::optional<uint64_t> available_memory_bytes() {
    if (const char* mb = std::getenv("MANYLIGHT_TEST_AVAILABLE_MB"))
        return uint64_t(std::strtoull(mb, nullptr, 10)) << 20;
    std::optional<uint64_t> machine = machine_available(), group = cgroup_available();
    if (machine && group) return std::min(*machine, *group);
    return machine ? machine : group;
}

}  // namespace ml
