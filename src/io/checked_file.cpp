// Checked output files: see include/rigidae/io/checked_file.hpp.
#include "rigidae/io/checked_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <fmt/format.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "rigidae/core/error.hpp"

namespace rigidae {

namespace {

// Hidden, unique per process, in the same folder (rename needs one file system).
std::filesystem::path temporary_sibling(const std::filesystem::path& path) {
  return path.parent_path() / fmt::format(".{}.tmp-{}", path.filename().string(), ::getpid());
}

[[noreturn]] void throw_errno(const std::filesystem::path& path, const char* what, int err) {
  throw OutputError(fmt::format("{}: {}: {}", path.string(), what, std::strerror(err)));
}

// A name that exists and is not a regular file (after links): a device such
// as /dev/stdout or /dev/null, a FIFO, a socket. Renaming over it would put a
// regular file in its place (as root, in /dev); it is written in place.
bool names_a_special_file(const std::filesystem::path& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode) && !S_ISDIR(st.st_mode);
}

}  // namespace

void write_file_atomically(const std::filesystem::path& path, std::string_view text) {
  const bool in_place = names_a_special_file(path);
  const std::filesystem::path tmp = in_place ? path : temporary_sibling(path);
  const int fd = in_place ? ::open(path.c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC)
                          : ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw_errno(path, "cannot open for writing", errno);
  auto give_up = [&](const char* what) {
    const int err = errno;
    ::close(fd);
    if (!in_place) ::unlink(tmp.c_str());
    throw_errno(path, what, err);
  };
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      if (n == 0) errno = EIO;
      give_up(fmt::format("write failed after {} of {} bytes", done, text.size()).c_str());
    }
    done += static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0 && errno != EINVAL && errno != EROFS) give_up("fsync failed");
  if (::close(fd) != 0) {
    const int err = errno;
    if (!in_place) ::unlink(tmp.c_str());
    throw_errno(path, "close failed", err);
  }
  if (in_place) return;
  if (::rename(tmp.c_str(), path.c_str()) != 0) {
    const int err = errno;
    ::unlink(tmp.c_str());
    throw_errno(path, "cannot rename the completed temporary file into place", err);
  }
}

CheckedStream::CheckedStream(std::filesystem::path path, std::size_t buffer_bytes)
    : path_(std::move(path)), buffer_(buffer_bytes) {
  f_ = std::fopen(path_.c_str(), "w");
  if (!f_) throw InputError(fmt::format("{}: cannot open for writing: {}", path_.string(), std::strerror(errno)));
  std::setvbuf(f_, buffer_.data(), _IOFBF, buffer_.size());
}

CheckedStream::~CheckedStream() {
  if (f_) std::fclose(f_);
}

void CheckedStream::fail(const char* what) {
  if (!failure_.empty()) throw OutputError(failure_);
  const int err = errno;
  // What the system accepted stays; the stream stops here. Closing now keeps a
  // later flush from writing a partial buffer after the failure.
  std::FILE* f = f_;
  f_ = nullptr;
  struct stat st {};
  const bool sized = f && ::fstat(::fileno(f), &st) == 0;
  if (f) std::fclose(f);
  failure_ = fmt::format("{}: {} ({} of {} bytes on disk): {}", path_.string(), what,
                         sized ? std::to_string(st.st_size) : "?", bytes_, std::strerror(err ? err : EIO));
  throw OutputError(failure_);
}

void CheckedStream::flush() {
  if (!f_) return;
  errno = 0;
  if (std::fflush(f_) != 0) fail("write failed");
}

void CheckedStream::close() {
  if (!f_) return;
  flush();
  if (::fsync(::fileno(f_)) != 0 && errno != EINVAL && errno != EROFS) fail("fsync failed");
  std::FILE* f = f_;
  f_ = nullptr;
  errno = 0;
  if (std::fclose(f) != 0) {
    const int err = errno;
    throw OutputError(fmt::format("{}: close failed: {}", path_.string(), std::strerror(err ? err : EIO)));
  }
}

}  // namespace rigidae
