// Runs an importer in a child process, so that a reader which crashes on a malformed file (assimp's
// ASE reader segfaults on a misspelt vertex count, found by tests/fuzz/fuzz_assimp.cpp) ends the child,
// not the bake: the parent reports invalid input. The child sends its soup and report back through a
// pipe in a plain length-prefixed encoding; nothing else crosses.
#include "dng/baker/import.h"

#include "stages.h"

#include <cerrno>
#include <csignal>
#include <cstring>
#include <new>
#include <string>
#include <type_traits>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

namespace dng {
namespace baker {

namespace {

class Writer {
public:
  template <typename T> void pod(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>, "plain values only");
    const auto* p = reinterpret_cast<const char*>(&v);
    bytes_.append(p, sizeof v);
  }
  void text(const std::string& s) {
    pod(std::uint64_t(s.size()));
    bytes_ += s;
  }
  template <typename T> void array(const std::vector<T>& v) {
    pod(std::uint64_t(v.size()));
    bytes_.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
  }
  void texts(const std::vector<std::string>& v) {
    pod(std::uint64_t(v.size()));
    for (const std::string& s : v)
      text(s);
  }
  const std::string& bytes() const { return bytes_; }

private:
  std::string bytes_;
};

class Reader {
public:
  explicit Reader(const std::string& bytes) : bytes_(bytes) {}
  template <typename T> bool pod(T* out) {
    if (bytes_.size() - at_ < sizeof(T)) return false;
    std::memcpy(out, bytes_.data() + at_, sizeof(T));
    at_ += sizeof(T);
    return true;
  }
  bool text(std::string* out) {
    std::uint64_t n = 0;
    if (!pod(&n) || bytes_.size() - at_ < n) return false;
    out->assign(bytes_, at_, std::size_t(n));
    at_ += std::size_t(n);
    return true;
  }
  template <typename T> bool array(std::vector<T>* out) {
    std::uint64_t n = 0;
    if (!pod(&n) || (bytes_.size() - at_) / sizeof(T) < n) return false;
    out->resize(std::size_t(n));
    if (n > 0) std::memcpy(out->data(), bytes_.data() + at_, std::size_t(n) * sizeof(T)); // data() may be null
    at_ += std::size_t(n) * sizeof(T);
    return true;
  }
  bool texts(std::vector<std::string>* out) {
    std::uint64_t n = 0;
    if (!pod(&n) || n > bytes_.size()) return false;
    out->resize(std::size_t(n));
    for (std::string& s : *out)
      if (!text(&s)) return false;
    return true;
  }

private:
  const std::string& bytes_;
  std::size_t at_ = 0;
};

std::string encode(const BakeStatus& status, const TriangleSoup& soup, const ImportReport& r) {
  Writer w;
  w.pod(status.code);
  w.text(status.message);
  w.array(soup.vertices);
  w.array(soup.triangles);
  w.pod(r.units);
  w.pod(r.triangles);
  w.pod(r.skipped_primitives);
  w.pod(std::uint64_t(r.nodes.size()));
  for (const NodeImport& n : r.nodes) {
    w.text(n.name);
    w.text(n.mesh);
    w.pod(n.triangles);
    w.pod(n.skipped_primitives);
    w.pod(n.transform);
  }
  w.texts(r.messages);
  w.texts(r.matched_nodes);
  return w.bytes();
}

bool decode(const std::string& bytes, BakeStatus* status, TriangleSoup* soup, ImportReport* r) {
  Reader in(bytes);
  std::uint64_t nodes = 0;
  if (!in.pod(&status->code) || !in.text(&status->message) || !in.array(&soup->vertices) ||
      !in.array(&soup->triangles) || !in.pod(&r->units) || !in.pod(&r->triangles) || !in.pod(&r->skipped_primitives) ||
      !in.pod(&nodes) || nodes > bytes.size())
    return false;
  r->nodes.resize(std::size_t(nodes));
  for (NodeImport& n : r->nodes) {
    if (!in.text(&n.name) || !in.text(&n.mesh) || !in.pod(&n.triangles) || !in.pod(&n.skipped_primitives) ||
        !in.pod(&n.transform))
      return false;
  }
  return in.texts(&r->messages) && in.texts(&r->matched_nodes);
}

bool writeAll(int fd, const std::string& bytes) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += std::size_t(n);
  }
  return true;
}

std::string readAll(int fd) {
  std::string bytes;
  char chunk[1 << 16];
  for (;;) {
    const ssize_t n = ::read(fd, chunk, sizeof chunk);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return bytes;
    bytes.append(chunk, std::size_t(n));
  }
}

// In the child: import, send, leave without running the parent's exit handlers.
[[noreturn]] void runChild(int fd, ImportFn importer, const std::string& path, const ImportOptions& options,
                           const ImportReport& start) {
  TriangleSoup soup;
  ImportReport report = start;
  BakeStatus status;
  try {
    status = importer(path, options, &soup, &report);
  } catch (const std::bad_alloc&) {
    status = outOfMemoryFailure();
  } catch (const std::exception& e) {
    status = BakeStatus::failure(BakeError::kInternal, std::string("the importer failed: ") + e.what());
  }
  const bool sent = writeAll(fd, encode(status, soup, report));
  ::_exit(sent ? 0 : 1);
}

} // namespace

BakeStatus importIsolated(ImportFn importer, const std::string& path, const ImportOptions& options,
                          TriangleSoup* io_soup, ImportReport* io_report) {
  int fds[2];
  if (::pipe(fds) != 0) return BakeStatus::failure(BakeError::kInternal, "cannot make a pipe for the importer");
  const pid_t child = ::fork();
  if (child < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    return BakeStatus::failure(BakeError::kInternal, "cannot start the importer's process");
  }
  if (child == 0) {
    ::close(fds[0]);
    runChild(fds[1], importer, path, options, *io_report);
  }
  ::close(fds[1]);
  const std::string bytes = readAll(fds[0]); // until the child exits or dies: then the pipe closes
  ::close(fds[0]);
  int wait_status = 0;
  while (::waitpid(child, &wait_status, 0) < 0 && errno == EINTR) {
  }
  if (WIFSIGNALED(wait_status))
    return BakeStatus::failure(BakeError::kInvalidInput, std::string(io_report->importer) + " crashed reading it (" +
                                                             ::strsignal(WTERMSIG(wait_status)) + ")");
  BakeStatus status;
  TriangleSoup soup;
  ImportReport report = *io_report;
  if (!WIFEXITED(wait_status) || WEXITSTATUS(wait_status) != 0 || !decode(bytes, &status, &soup, &report))
    return BakeStatus::failure(BakeError::kInternal, "the importer's process ended without an answer");
  const auto base = std::uint32_t(io_soup->vertices.size());
  io_soup->vertices.insert(io_soup->vertices.end(), soup.vertices.begin(), soup.vertices.end());
  for (const auto& t : soup.triangles)
    io_soup->triangles.push_back({base + t[0], base + t[1], base + t[2]});
  *io_report = std::move(report);
  return status;
}

} // namespace baker
} // namespace dng
