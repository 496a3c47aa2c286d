// Internal: the band's blocks processed on TBB's threads with progress and cancel, for the stages that
// work block by block (distance_field.cpp, conservative_planes.cpp).
#pragma once

#include "stages.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <cstddef>
#include <mutex>

namespace dng {
namespace baker {

/// Calls work(b) for every b in [0, count) on any threads, reporting `stage` with the fraction done
/// after each block, one callback at a time (callbacks need no locks). False when the callback asked
/// to stop: blocks not yet started are then skipped.
template <class Work>
bool forEachBlockInParallel(std::size_t count, const char* stage, ProgressFn progress, void* progress_user, Work work) {
  std::atomic<std::size_t> blocks_done{0};
  std::atomic<bool> cancelled{false};
  std::mutex reporting;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 1), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t b = r.begin(); b != r.end() && !cancelled.load(); ++b) {
      work(b);
      const double fraction = double(++blocks_done) / double(count);
      if (progress != nullptr && reporting.try_lock()) {
        if (!progress(progress_user, stage, fraction)) cancelled = true;
        reporting.unlock();
      }
    }
  });
  return !cancelled;
}

} // namespace baker
} // namespace dng
