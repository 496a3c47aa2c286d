#include "memory_cap.h"

#include "machine_memory.h"
#include "sanitized_build.h"

#include <atomic>
#include <cstdlib>
#include <new>

namespace dng {
namespace tools {

namespace {

std::atomic<std::uint64_t> g_cap{0};   // the cap being enforced: the one set, plus a reserve per refusal
std::atomic<std::uint64_t> g_limit{0}; // the cap as set
std::atomic<bool> g_reached{false};

#ifndef DNG_SANITIZED_BUILD
/// Resident memory is read again after this many bytes more have been allocated.
constexpr std::uint64_t kCheckEvery = std::uint64_t(16) << 20;

/// What each refusal adds to the cap.
constexpr std::uint64_t kReserve = std::uint64_t(64) << 20;

std::atomic<std::uint64_t> g_allocated{0}; // every byte asked of operator new while a cap was set

// Throws std::bad_alloc when `size` more bytes would take the process past the cap. Cheap between
// checks: one relaxed atomic add.
void chargeAllocation(std::size_t size) {
  const std::uint64_t cap = g_cap.load(std::memory_order_relaxed);
  if (cap == 0) return;
  const std::uint64_t before = g_allocated.fetch_add(size, std::memory_order_relaxed);
  if (size < kCheckEvery && before / kCheckEvery == (before + size) / kCheckEvery) return;
  const std::uint64_t resident = residentBytes();
  if (resident == 0 || resident + size <= cap) return;
  // Room for the unwinding and the report, and for a caller that recovers (std::stable_sort falls back
  // to sorting in place): the limit moves up by a reserve per refusal, never away.
  g_cap.fetch_add(kReserve, std::memory_order_relaxed);
  g_reached.store(true, std::memory_order_relaxed);
  throw std::bad_alloc();
}
#endif

} // namespace

bool memoryCapSupported() {
#ifdef DNG_SANITIZED_BUILD
  return false;
#else
  return true;
#endif
}

void setMemoryCap(std::uint64_t bytes) {
  if (!memoryCapSupported()) return;
  g_limit.store(bytes, std::memory_order_relaxed);
  g_cap.store(bytes, std::memory_order_relaxed);
}

std::uint64_t memoryCap() { return g_limit.load(std::memory_order_relaxed); }

bool memoryCapReached() { return g_reached.load(std::memory_order_relaxed); }

} // namespace tools
} // namespace dng

#ifndef DNG_SANITIZED_BUILD
// The one replacement the cap needs: libstdc++'s array and nothrow forms call this one. Its other
// operators (delete, aligned new) pair with malloc and free as before.
void* operator new(std::size_t size) {
  dng::tools::chargeAllocation(size);
  for (;;) {
    if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
    const std::new_handler handler = std::get_new_handler();
    if (handler == nullptr) throw std::bad_alloc();
    handler();
  }
}
#endif
