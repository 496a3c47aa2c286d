// dngbake's default memory limit rests on machine_memory.h: what the machine and its memory cgroups
// leave free. Checked on made-up /proc and /sys trees (cgroup v1 and v2, limits on several levels, file
// cache, no limit at all) against the numbers written into them, and on this machine's real ones.
#include "machine_memory.h"
#include "temp_dir.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

namespace dng {
namespace {

namespace fs = std::filesystem;

constexpr std::uint64_t kMiB = std::uint64_t(1) << 20;

class MachineMemoryTest : public ::testing::Test {
protected:
  testing::TempDir dir_{"machine_memory"};

  std::string root() const { return dir_.path().string(); }

  // Writes `text` to the file at `relative` under the made-up root, making its folders.
  void write(const std::string& relative, const std::string& text) {
    const fs::path file = dir_.path() / relative;
    fs::create_directories(file.parent_path());
    std::ofstream(file) << text;
  }

  // /proc/meminfo with these free amounts, in MiB.
  void meminfo(std::uint64_t available_mib, std::uint64_t swap_free_mib) {
    write("proc/meminfo", "MemTotal:       24683620 kB\nMemFree:         1000 kB\nMemAvailable:   " +
                              std::to_string(available_mib * 1024) + " kB\nSwapTotal:  0 kB\nSwapFree:       " +
                              std::to_string(swap_free_mib * 1024) + " kB\n");
  }

  // A cgroup v1 memory level: its limit, its usage and the file cache in it, in MiB.
  void levelV1(const std::string& path, const std::string& limit, std::uint64_t usage_mib, std::uint64_t cache_mib) {
    const std::string dir = "sys/fs/cgroup/memory" + path;
    write(dir + "/memory.limit_in_bytes", limit + "\n");
    write(dir + "/memory.usage_in_bytes", std::to_string(usage_mib * kMiB) + "\n");
    write(dir + "/memory.stat", "cache 1\nrss 2\ntotal_inactive_file " + std::to_string(cache_mib / 2 * kMiB) +
                                    "\ntotal_active_file " + std::to_string((cache_mib - cache_mib / 2) * kMiB) + "\n");
  }

  std::uint64_t headroom() const {
    const std::optional<std::uint64_t> h = tools::memoryHeadroomBytes(root());
    EXPECT_TRUE(h.has_value());
    return h.value_or(0);
  }
};

// Free swap does not count: the cap compares resident memory, which leaves swapped-out pages out.
TEST_F(MachineMemoryTest, WithoutCgroupLimitsTheFreeMemoryCounts) {
  meminfo(3000, 500);
  write("proc/self/cgroup", "4:memory:/\n0::/\n");
  levelV1("", "9223372036854771712", 100, 0); // the root: v1's "no limit"
  EXPECT_EQ(headroom(), 3000 * kMiB);
}

// Every level's limit applies to what is below it; the file cache is reclaimed, not counted as used.
TEST_F(MachineMemoryTest, TheTightestCgroupLevelDecides) {
  meminfo(20000, 0);
  write("proc/self/cgroup", "9:pids:/\n4:memory:/jobs/runner\n1:cpu:/\n");
  levelV1("", "9223372036854771712", 5000, 0);
  levelV1("/jobs", std::to_string(4096 * kMiB), 1500, 1000);      // 4096 - (1500 - 1000) = 3596 left
  levelV1("/jobs/runner", std::to_string(2048 * kMiB), 900, 300); // 2048 - 600 = 1448 left
  EXPECT_EQ(headroom(), 1448 * kMiB);
  // With the parent tighter than the child, the parent decides.
  levelV1("/jobs", std::to_string(1024 * kMiB), 1500, 1000);
  EXPECT_EQ(headroom(), 524 * kMiB);
  // And with free memory tighter than both, the machine does.
  meminfo(300, 100);
  EXPECT_EQ(headroom(), 300 * kMiB);
}

// cgroup v2: "max" is no limit; memory.current and memory.stat's file lines give what is used.
TEST_F(MachineMemoryTest, CgroupV2LimitsAreRead) {
  meminfo(20000, 0);
  write("proc/self/cgroup", "0::/user.slice/bake.scope\n");
  write("sys/fs/cgroup/cgroup.controllers", "cpu memory pids\n");
  write("sys/fs/cgroup/user.slice/memory.max", "max\n");
  write("sys/fs/cgroup/user.slice/memory.current", std::to_string(8000 * kMiB) + "\n");
  write("sys/fs/cgroup/user.slice/bake.scope/memory.max", std::to_string(3000 * kMiB) + "\n");
  write("sys/fs/cgroup/user.slice/bake.scope/memory.current", std::to_string(1200 * kMiB) + "\n");
  write("sys/fs/cgroup/user.slice/bake.scope/memory.stat", "anon 1\nfile 2\nactive_file " + std::to_string(150 * kMiB) +
                                                               "\ninactive_file " + std::to_string(50 * kMiB) + "\n");
  EXPECT_EQ(headroom(), 2000 * kMiB);
}

// A level already over its limit leaves nothing (the bake then stops at its first large allocation).
TEST_F(MachineMemoryTest, AFullCgroupLeavesNothing) {
  meminfo(20000, 0);
  write("proc/self/cgroup", "4:memory:/full\n");
  levelV1("/full", std::to_string(512 * kMiB), 700, 0);
  EXPECT_EQ(headroom(), 0u);
}

// The mounts come from /proc/self/mountinfo: a v1 memory hierarchy mounted somewhere unusual (a space
// in its path, written \040 there) is read there, not at /sys/fs/cgroup/memory, whose made-up tree here
// says otherwise.
TEST_F(MachineMemoryTest, CgroupMountsAreFoundWhereverTheyAre) {
  meminfo(20000, 0);
  write("proc/self/mountinfo", "30 22 0:27 / /sys/fs/cgroup rw,relatime - tmpfs tmpfs rw,mode=755\n"
                               "31 30 0:28 / /sys/fs/cgroup/cpu rw,relatime - cgroup cgroup rw,cpu\n"
                               "34 22 0:31 / /cgroup/mem\\040ory rw,relatime shared:9 - cgroup cgroup rw,memory\n");
  write("proc/self/cgroup", "3:cpu:/\n4:memory:/jobs\n");
  levelV1("/jobs", std::to_string(100 * kMiB), 10, 0); // the decoy at the usual place
  const std::string level = "cgroup/mem ory/jobs";
  write(level + "/memory.limit_in_bytes", std::to_string(3000 * kMiB) + "\n");
  write(level + "/memory.usage_in_bytes", std::to_string(1000 * kMiB) + "\n");
  EXPECT_EQ(headroom(), 2000 * kMiB);
}

// A container without its own cgroup namespace sees its host's path in /proc/self/cgroup and a mount
// whose root is that path: the levels are found below the mount's root, the container's own level
// first (here a job inside the container, tighter than the container).
TEST_F(MachineMemoryTest, AMountShowingItsContainersBranchIsReadBelowIt) {
  meminfo(20000, 0);
  write("proc/self/mountinfo", "34 30 0:31 /docker/abc /sys/fs/cgroup/memory ro,nosuid - cgroup cgroup rw,memory\n");
  write("proc/self/cgroup", "4:memory:/docker/abc/job\n");
  levelV1("", std::to_string(3000 * kMiB), 500, 0);     // the container: 2500 left
  levelV1("/job", std::to_string(1000 * kMiB), 400, 0); // its job: 600 left
  EXPECT_EQ(headroom(), 600 * kMiB);
}

TEST_F(MachineMemoryTest, WithoutMeminfoTheHeadroomIsUnknown) {
  EXPECT_FALSE(tools::memoryHeadroomBytes(root()).has_value());
}

// This machine's own: the headroom can be read, and this process holds some resident memory.
TEST_F(MachineMemoryTest, ThisMachineHasSomeFreeMemory) {
  if (!fs::exists("/proc/meminfo")) GTEST_SKIP() << "no /proc here";
  const std::optional<std::uint64_t> h = tools::memoryHeadroomBytes();
  ASSERT_TRUE(h.has_value());
  EXPECT_GT(*h, 0u);
  EXPECT_GT(tools::residentBytes(), kMiB);
}

} // namespace
} // namespace dng
