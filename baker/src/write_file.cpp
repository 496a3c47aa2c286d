// Atomic outputs (docs/DESIGN.md §5.8): a failed or interrupted bake never leaves a partial file at an
// output path, nor damages a file already there, nor writes over its own input.
#include "stages.h"

#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace dng {
namespace baker {

namespace fs = std::filesystem;

namespace {

// Whether two paths name one file: the same file when both exist (links included), else the same
// place once resolved as far as the folders exist.
bool sameFile(const std::string& a, const std::string& b) {
  std::error_code error;
  if (fs::exists(a, error) && fs::exists(b, error)) return fs::equivalent(a, b, error);
  return fs::weakly_canonical(a, error) == fs::weakly_canonical(b, error);
}

BakeStatus refuseExisting(const std::string& path) {
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  if (!fs::exists(status) || fs::is_regular_file(status)) return BakeStatus::success();
  const char* what = fs::is_directory(status) ? "a directory" : "not a regular file (a device, pipe or socket)";
  return BakeStatus::failure(BakeError::kIo, "'" + path + "' is " + what + ": an output must be a file");
}

} // namespace

BakeStatus checkOutputPaths(const std::vector<std::string>& inputs, const BakeOutputs& outputs) {
  std::vector<std::string> paths{outputs.dng};
  if (!outputs.vdb.empty()) paths.push_back(outputs.vdb);
  for (const std::string& out : paths) {
    if (BakeStatus status = refuseExisting(out); !status.ok()) return status;
    for (const std::string& in : inputs) {
      if (sameFile(in, out))
        return BakeStatus::failure(BakeError::kBadOption,
                                   "the output '" + out + "' is the input '" + in + "': refusing to write over it");
    }
  }
  if (paths.size() == 2 && sameFile(paths[0], paths[1]))
    return BakeStatus::failure(BakeError::kBadOption,
                               "the .dng and the OpenVDB export would both be '" + outputs.vdb + "'");
  return BakeStatus::success();
}

StagedOutputs::~StagedOutputs() {
  for (const Entry& e : entries_)
    ::unlink(e.temp.c_str());
}

BakeStatus StagedOutputs::reserve(const std::string& path, std::string* out_temp) {
  const fs::path target(path);
  const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
  // A new name of our own, created exclusively with the mode a plain create gets (0666 less the
  // umask): mkstemp's files are private, and the outputs are meant to be shared as usual.
  static std::atomic<unsigned> counter{0};
  for (int attempt = 0; attempt < 100; ++attempt) {
    const std::string temp = (folder / ("." + target.filename().string() + ".tmp." + std::to_string(::getpid()) + "." +
                                        std::to_string(counter++)))
                                 .string();
    const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0 && errno == EEXIST) continue;
    if (fd < 0)
      return BakeStatus::failure(BakeError::kIo,
                                 "cannot create a file in '" + folder.string() + "': " + std::strerror(errno));
    ::close(fd);
    entries_.push_back({temp, path}); // removed on destruction unless committed
    *out_temp = temp;
    return BakeStatus::success();
  }
  return BakeStatus::failure(BakeError::kIo, "cannot find a free temporary name in '" + folder.string() + "'");
}

BakeStatus StagedOutputs::write(const std::string& path, const std::vector<std::uint8_t>& bytes) {
  std::string temp;
  if (BakeStatus status = reserve(path, &temp); !status.ok()) return status;
  const int fd = ::open(temp.c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC);
  auto fail = [&](const std::string& what) {
    const std::string reason = std::strerror(errno);
    if (fd >= 0) ::close(fd);
    return BakeStatus::failure(BakeError::kIo, what + " '" + path + "': " + reason);
  };
  if (fd < 0) return fail("cannot open a temporary file for");
  std::size_t written = 0;
  while (written < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + written, bytes.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return fail("cannot write");
    written += std::size_t(n);
  }
  if (::close(fd) != 0)
    return BakeStatus::failure(BakeError::kIo, "cannot close '" + path + "': " + std::strerror(errno));
  return BakeStatus::success();
}

BakeStatus StagedOutputs::commit() {
  // Every temporary on disk first (OpenVDB's writer does not flush its file): a rename must never put
  // a file in place whose bytes a crash could still lose.
  for (const Entry& e : entries_) {
    const int fd = ::open(e.temp.c_str(), O_RDONLY | O_CLOEXEC);
    const bool flushed = fd >= 0 && ::fsync(fd) == 0;
    const std::string reason = std::strerror(errno);
    if (fd >= 0) ::close(fd);
    if (!flushed) return BakeStatus::failure(BakeError::kIo, "cannot flush '" + e.path + "': " + reason);
  }
  for (std::size_t n = 0; n < entries_.size(); ++n) {
    if (::rename(entries_[n].temp.c_str(), entries_[n].path.c_str()) != 0) {
      const std::string message = "cannot replace '" + entries_[n].path + "': " + std::strerror(errno);
      entries_.erase(entries_.begin(), entries_.begin() + std::ptrdiff_t(n)); // the rest are removed
      return BakeStatus::failure(BakeError::kIo, message);
    }
  }
  entries_.clear();
  return BakeStatus::success();
}

} // namespace baker
} // namespace dng
