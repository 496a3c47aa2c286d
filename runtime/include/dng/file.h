// dng::File: owns a memory-mapped .dng file and the validated View onto it.
#pragma once

#include "dng/view.h"

#include <memory>

namespace dng {

/// Move-only owner of a read-only mapping. The View it hands out is valid while the File lives, and
/// keeps its address when the File is moved (into a growing std::vector, say): Bodies point at it.
class File {
public:
  File() = default;
  ~File();
  File(File&& other) noexcept;
  File& operator=(File&& other) noexcept;
  File(const File&) = delete;
  File& operator=(const File&) = delete;

  /// Maps the file at `path` (NUL-terminated) read-only and validates it with View::open. On failure
  /// returns the status, leaves `*out_file` empty and fills `out_diag` when given. Never throws, and
  /// never waits: anything but a regular file (a FIFO, a device, a directory) is refused with kIoError.
  /// The mapping reads the file as it is on disk: replace a baked file by renaming a new one over it
  /// (dngbake does), never by rewriting it in place, since a file cut short under a mapping ends the
  /// process that reads past its new end (SIGBUS).
  static Status open(const char* path, File* out_file, Diagnostic* out_diag = nullptr);

  /// The validated view; an empty View (valid() false) when the File is empty.
  const View& view() const;
  bool valid() const { return view_ != nullptr; }

private:
  void release();

  void* mapping_ = nullptr;
  std::size_t mapped_size_ = 0;
  std::unique_ptr<View> view_; // on the heap so that moving the File never moves the View
};

} // namespace dng
