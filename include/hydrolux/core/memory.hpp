#pragma once
// How much memory a job may count on, so that work too large for the machine is refused before it
// starts (naming what would fit) instead of running for a minute and ending in "out of memory".
#include <cstdint>
#include <string>

namespace hydrolux {

// The memory this process can still expect to get, in bytes: the kernel's MemAvailable (free memory
// plus what the page cache would give back), capped by the process's cgroup v2 memory limit (a
// container's) less what the group uses beyond its reclaimable page cache, and by the address-space limit (RLIMIT_AS, as set by `ulimit -v`) less what the
// process has mapped already. Falls back to the physical memory where
// /proc/meminfo cannot be read.
std::uint64_t available_memory_bytes();

// "1.5 GB", "820 MB": a byte count for a message.
std::string format_bytes(double bytes);

}  // namespace hydrolux
