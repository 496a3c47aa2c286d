// dng::File: read-only memory mapping (POSIX mmap) plus validation.
#include "dng/file.h"
#include "diagnostic.h"

#include <cerrno>
#include <cstring>
#include <new>
#include <utility>

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

namespace dng {

File::~File() { release(); }

File::File(File&& other) noexcept
    : mapping_(std::exchange(other.mapping_, nullptr)), mapped_size_(std::exchange(other.mapped_size_, 0)),
      view_(std::move(other.view_)) {}

const View& File::view() const {
  static const View empty;
  return view_ != nullptr ? *view_ : empty;
}

File& File::operator=(File&& other) noexcept {
  if (this != &other) {
    release();
    mapping_ = std::exchange(other.mapping_, nullptr);
    mapped_size_ = std::exchange(other.mapped_size_, 0);
    view_ = std::move(other.view_);
  }
  return *this;
}

void File::release() {
  if (mapping_ != nullptr) munmap(mapping_, mapped_size_);
  mapping_ = nullptr;
  mapped_size_ = 0;
  view_.reset();
}

Status File::open(const char* path, File* out_file, Diagnostic* out_diag) {
  if (path == nullptr || out_file == nullptr)
    return writeDiagnostic(out_diag, Status::kInvalidArgument, "path and out_file must not be null");
  out_file->release();
  // O_NONBLOCK: opening a FIFO would otherwise wait for a writer; a regular file (all that is mapped,
  // checked below) ignores it.
  const int fd = ::open(path, O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) return writeDiagnostic(out_diag, Status::kIoError, "cannot open '%s': %s", path, std::strerror(errno));
  struct stat info;
  if (fstat(fd, &info) != 0) {
    const int error = errno;
    ::close(fd);
    return writeDiagnostic(out_diag, Status::kIoError, "cannot stat '%s': %s", path, std::strerror(error));
  }
  if (!S_ISREG(info.st_mode)) {
    ::close(fd);
    return writeDiagnostic(out_diag, Status::kIoError, "'%s' is not a regular file", path);
  }
  const auto size = std::size_t(info.st_size);
  if (size == 0) {
    ::close(fd);
    return writeRuleDiagnostic(out_diag, Status::kTruncated, "V3", "'%s' is empty", path);
  }
  void* mapping = mmap(nullptr, size, PROT_READ, MAP_PRIVATE, fd, 0);
  const int map_error = errno;
  ::close(fd); // the mapping keeps the file alive
  if (mapping == MAP_FAILED)
    return writeDiagnostic(out_diag, Status::kIoError, "cannot map '%s': %s", path, std::strerror(map_error));
  File file;
  file.mapping_ = mapping;
  file.mapped_size_ = size;
  file.view_.reset(new (std::nothrow) View());
  if (file.view_ == nullptr) return writeDiagnostic(out_diag, Status::kOutOfMemory, "no memory for the view");
  const Status status = View::open(mapping, size, file.view_.get(), out_diag);
  if (status != Status::kOk) return status; // `file` unmaps on the way out
  *out_file = std::move(file);
  return Status::kOk;
}

} // namespace dng
