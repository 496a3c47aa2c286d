// How much memory this process holds, and how much more it may take before the kernel's out-of-memory
// killer ends it: the machine's free memory, and the limits of the memory cgroups it runs in
// (containers, CI runners, systemd slices). Linux; elsewhere, or where nothing can be read, "unknown".
//
// residentBytes() does not allocate from the heap: memory_cap.cpp calls it from inside operator new.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace dng {
namespace tools {

/// This process's resident memory now (/proc/self/statm), in bytes. 0: unknown.
std::uint64_t residentBytes();

/// Bytes this process may add to what it holds now: the smallest of the machine's MemAvailable
/// (/proc/meminfo; swap not counted, as resident memory does not count it) and, for every level of its memory cgroup
/// (v1 or v2, mounted where /proc/self/mountinfo says) that has a limit, that limit less the level's usage without its
/// file cache (which the kernel reclaims before it kills). Empty when /proc/meminfo cannot be read. `root`: a directory
/// that stands for / (a test's made-up /proc and /sys); empty for the real ones.
std::optional<std::uint64_t> memoryHeadroomBytes(const std::string& root = std::string());

} // namespace tools
} // namespace dng
