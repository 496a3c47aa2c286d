// Atomic output (docs/DESIGN.md §5.8): a failed or interrupted bake never leaves a partial file at the
// output path, nor damages a file already there.
#include "stages.h"

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace dng {
namespace baker {

BakeStatus writeFileAtomically(const std::string& path, const std::vector<std::uint8_t>& bytes) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  std::error_code error;
  if (fs::is_directory(target, error)) return BakeStatus::failure(BakeError::kIo, "'" + path + "' is a directory");
  const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::string temp = (folder / ("." + target.filename().string() + ".tmp.XXXXXX")).string();
  const int fd = ::mkstemp(temp.data());
  if (fd < 0)
    return BakeStatus::failure(BakeError::kIo,
                               "cannot create a file in '" + folder.string() + "': " + std::strerror(errno));
  auto fail = [&](const std::string& what) {
    const std::string reason = std::strerror(errno);
    ::close(fd);
    ::unlink(temp.c_str());
    return BakeStatus::failure(BakeError::kIo, what + " '" + path + "': " + reason);
  };
  std::size_t written = 0;
  while (written < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + written, bytes.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return fail("cannot write");
    written += std::size_t(n);
  }
  if (::fchmod(fd, 0644) != 0 || ::fsync(fd) != 0) return fail("cannot flush");
  if (::close(fd) != 0) {
    const std::string reason = std::strerror(errno);
    ::unlink(temp.c_str());
    return BakeStatus::failure(BakeError::kIo, "cannot close '" + path + "': " + reason);
  }
  if (::rename(temp.c_str(), path.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    ::unlink(temp.c_str());
    return BakeStatus::failure(BakeError::kIo, "cannot replace '" + path + "': " + reason);
  }
  return BakeStatus::success();
}

} // namespace baker
} // namespace dng
