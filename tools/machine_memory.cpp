#include "machine_memory.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace dng {
namespace tools {

namespace {

constexpr std::uint64_t kUnknown = 0;
constexpr std::uint64_t kNoLimit = ~std::uint64_t(0);

// The value after `key` in a file of "key value" lines (/proc/meminfo's "MemAvailable: 123 kB",
// memory.stat's "inactive_file 123"), times `unit`; false when the file or the key is missing.
bool readKeyed(const std::string& path, const std::string& key, std::uint64_t unit, std::uint64_t* out) {
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    std::string name;
    unsigned long long value = 0;
    if (fields >> name >> value && (name == key || name == key + ":")) {
      *out = std::uint64_t(value) * unit;
      return true;
    }
  }
  return false;
}

// A cgroup file's amount in bytes (a limit or a usage), or kNoLimit for v2's "max" and v1's "no limit"
// (a page-rounded 2^63 - 1).
bool readAmount(const std::string& path, std::uint64_t* out) {
  std::ifstream in(path);
  std::string text;
  if (!(in >> text)) return false;
  if (text == "max") {
    *out = kNoLimit;
    return true;
  }
  char* end = nullptr;
  const unsigned long long value = std::strtoull(text.c_str(), &end, 10);
  if (end == text.c_str()) return false;
  *out = value >= (1ull << 62) ? kNoLimit : std::uint64_t(value);
  return true;
}

// What one cgroup level leaves: its limit less its usage without the file cache; kNoLimit when it has
// no limit (or its files are not there: a level outside this mount namespace).
std::uint64_t levelHeadroom(const std::string& dir, bool v2) {
  std::uint64_t limit = kNoLimit, usage = 0, inactive = 0, active = 0;
  if (!readAmount(dir + (v2 ? "/memory.max" : "/memory.limit_in_bytes"), &limit) || limit == kNoLimit) return kNoLimit;
  if (!readAmount(dir + (v2 ? "/memory.current" : "/memory.usage_in_bytes"), &usage)) return kNoLimit;
  const std::string stat = dir + "/memory.stat";
  readKeyed(stat, v2 ? "inactive_file" : "total_inactive_file", 1, &inactive);
  readKeyed(stat, v2 ? "active_file" : "total_active_file", 1, &active);
  const std::uint64_t cache = std::min(usage, inactive + active);
  const std::uint64_t used = usage - cache;
  return limit > used ? limit - used : 0;
}

// The smallest headroom over the levels of cgroup `path` under `mount`, from the process's own level
// up to the mount's root: every level's limit applies to everything below it.
std::uint64_t cgroupHeadroom(const std::string& mount, std::string path, bool v2) {
  std::uint64_t least = kNoLimit;
  for (;;) {
    least = std::min(least, levelHeadroom(mount + path, v2));
    if (path.empty() || path == "/") break;
    const std::size_t slash = path.find_last_of('/');
    path = slash == std::string::npos ? std::string() : path.substr(0, slash);
  }
  return least;
}

// A cgroup file system mounted here: where (under `root`), which part of the hierarchy its root shows,
// and whether it is v2's or v1's memory controller.
struct CgroupMount {
  std::string point, shows;
  bool v2 = false;
};

// mountinfo writes a space, tab, newline or backslash in a path as a backslash and three octal digits.
std::string unescapeMountPath(const std::string& text) {
  const auto octal = [](char c) { return c >= '0' && c <= '7'; };
  std::string out;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '\\' && i + 3 < text.size() && octal(text[i + 1]) && octal(text[i + 2]) && octal(text[i + 3])) {
      out += char((text[i + 1] - '0') * 64 + (text[i + 2] - '0') * 8 + (text[i + 3] - '0'));
      i += 3;
    } else {
      out += text[i];
    }
  }
  return out;
}

// The memory cgroup mounts of /proc/self/mountinfo ("id parent dev shows point options [tags] - type
// source super-options"): type cgroup2, or cgroup with the memory controller among its options. Where
// the file cannot be read or lists none, the usual places: v2 at /sys/fs/cgroup (or /sys/fs/cgroup/unified
// beside v1 controllers), v1's memory at /sys/fs/cgroup/memory, each showing the whole hierarchy.
std::vector<CgroupMount> cgroupMounts(const std::string& root) {
  std::vector<CgroupMount> mounts;
  std::ifstream in(root + "/proc/self/mountinfo");
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    std::string id, parent, dev, shows, point, word;
    if (!(fields >> id >> parent >> dev >> shows >> point)) continue;
    while (fields >> word && word != "-") {
    }
    std::string type, source, options;
    if (!(fields >> type >> source >> options)) continue;
    const bool v1_memory = type == "cgroup" && ("," + options + ",").find(",memory,") != std::string::npos;
    if (type == "cgroup2" || v1_memory)
      mounts.push_back({root + unescapeMountPath(point), unescapeMountPath(shows), type == "cgroup2"});
  }
  if (!mounts.empty()) return mounts;
  return {{root + "/sys/fs/cgroup", "/", true},
          {root + "/sys/fs/cgroup/unified", "/", true},
          {root + "/sys/fs/cgroup/memory", "/", false}};
}

// `path` (from /proc/self/cgroup) below a mount that shows `shows` of the hierarchy: the part past it,
// or all of it when the mount shows the root (or another branch, as a cgroup namespace's mounts do).
std::string pathUnder(const std::string& path, const std::string& shows) {
  if (shows == "/" || path.compare(0, shows.size(), shows) != 0) return path;
  if (path.size() != shows.size() && path[shows.size()] != '/') return path;
  return path.substr(shows.size());
}

// The cgroups of this process (/proc/self/cgroup: "id:controllers:path"): v2's (controllers empty) and
// the v1 memory hierarchy's, each under every mount of its kind.
std::uint64_t cgroupsHeadroom(const std::string& root) {
  const std::vector<CgroupMount> mounts = cgroupMounts(root);
  std::ifstream in(root + "/proc/self/cgroup");
  std::string line;
  std::uint64_t least = kNoLimit;
  while (std::getline(in, line)) {
    const std::size_t first = line.find(':'), second = line.find(':', first + 1);
    if (first == std::string::npos || second == std::string::npos) continue;
    const std::string controllers = "," + line.substr(first + 1, second - first - 1) + ",";
    const std::string path = line.substr(second + 1);
    const bool v2 = controllers == ",,";
    if (!v2 && controllers.find(",memory,") == std::string::npos) continue;
    for (const CgroupMount& mount : mounts)
      if (mount.v2 == v2) least = std::min(least, cgroupHeadroom(mount.point, pathUnder(path, mount.shows), v2));
  }
  return least;
}

} // namespace

std::uint64_t residentBytes() {
  // open and read, not streams: this runs inside operator new.
  const int fd = ::open("/proc/self/statm", O_RDONLY | O_CLOEXEC);
  if (fd < 0) return kUnknown;
  char text[128];
  const ssize_t got = ::read(fd, text, sizeof text - 1);
  ::close(fd);
  if (got <= 0) return kUnknown;
  text[got] = '\0';
  char* end = nullptr;
  std::strtoull(text, &end, 10); // the first field is the address space; the second is resident
  const unsigned long long pages = std::strtoull(end, nullptr, 10);
  const long page = ::sysconf(_SC_PAGESIZE);
  return page > 0 ? std::uint64_t(pages) * std::uint64_t(page) : kUnknown;
}

std::optional<std::uint64_t> memoryHeadroomBytes(const std::string& root) {
  const std::string meminfo = root + "/proc/meminfo";
  // Swap is not counted: the cap compares resident memory, which leaves swapped-out pages out, so a
  // cap that counted swap could lie beyond anything the process's resident size ever reaches.
  std::uint64_t available = 0;
  if (!readKeyed(meminfo, "MemAvailable", 1024, &available)) return std::nullopt;
  return std::min(available, cgroupsHeadroom(root));
}

} // namespace tools
} // namespace dng
