// The memory a process may still take: what the machine has available, within the limit of its
// control group, so that a render too large for it stops before allocating instead of being
// killed.
#pragma once

#include <cstdint>
#include <optional>

namespace ml {

// Bytes this process may still allocate: the least of the machine's available memory
// (/proc/meminfo MemAvailable, else sysconf's available pages) and, where a cgroup v2 limit is
// set on the process's group or a group above it, that limit less the group's usage. The
// environment variable MANYLIGHT_TEST_AVAILABLE_MB replaces it (tests: a small machine on a big
// one). Empty when none of these can be read.
std::optional<uint64_t> available_memory_bytes();

}  // namespace ml
