#include "hydrolux/core/memory.hpp"

#include <fmt/format.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <fstream>
#include <sstream>
#include <string>

namespace hydrolux {

namespace {

// A field of /proc/<...> files in kB ("MemAvailable:   123456 kB"), in bytes; 0 if absent.
std::uint64_t proc_kb_field(const char* path, const std::string& key) {
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind(key, 0) != 0) continue;
    std::istringstream fields(line.substr(key.size()));
    std::uint64_t kb = 0;
    if (fields >> kb) return kb * 1024;
  }
  return 0;
}

}  // namespace

std::uint64_t available_memory_bytes() {
  std::uint64_t avail = proc_kb_field("/proc/meminfo", "MemAvailable:");
  if (avail == 0) {
    const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
    avail = pages > 0 && page > 0 ? std::uint64_t(pages) * std::uint64_t(page) : UINT64_MAX;
  }
  // A cgroup v2 memory limit (a container's): the limit less what the group uses, not counting the page
  // cache it could drop (inactive_file), so a group that has read many files does not look full. The
  // process's own group, from /proc/self/cgroup ("0::/path").
  {
    std::ifstream self("/proc/self/cgroup");
    std::string group;
    for (std::string line; std::getline(self, line);)
      if (line.rfind("0::", 0) == 0) group = line.substr(3);
    if (!group.empty()) {
      const std::string dir = "/sys/fs/cgroup" + (group == "/" ? std::string() : group);
      std::ifstream max_file(dir + "/memory.max"), current_file(dir + "/memory.current");
      std::string max_text;
      std::uint64_t current = 0;
      if (max_file >> max_text && max_text != "max" && current_file >> current) {
        std::uint64_t limit = 0;
        const auto [ptr, ec] = std::from_chars(max_text.data(), max_text.data() + max_text.size(), limit);
        if (ec == std::errc() && ptr == max_text.data() + max_text.size()) {
          std::uint64_t reclaimable = 0;
          std::ifstream stat(dir + "/memory.stat");
          for (std::string key; stat >> key;) {
            std::uint64_t value = 0;
            if (!(stat >> value)) break;
            if (key == "inactive_file") reclaimable = value;
          }
          const std::uint64_t used = current > reclaimable ? current - reclaimable : 0;
          avail = std::min(avail, limit > used ? limit - used : 0);
        }
      }
    }
  }
  rlimit as{};
  if (getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY) {
    const std::uint64_t mapped = proc_kb_field("/proc/self/status", "VmSize:");
    const std::uint64_t left = as.rlim_cur > mapped ? std::uint64_t(as.rlim_cur) - mapped : 0;
    avail = std::min(avail, left);
  }
  return avail;
}

std::string format_bytes(double bytes) {
  if (bytes >= 1e9) return fmt::format("{:.1f} GB", bytes / 1e9);
  if (bytes >= 1e6) return fmt::format("{:.0f} MB", bytes / 1e6);
  return fmt::format("{:.0f} kB", bytes / 1e3);
}

}  // namespace hydrolux
