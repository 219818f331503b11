// NumPy .npy files written row by row: see include/rigidae/record/npy_file.hpp.
#include "rigidae/record/npy_file.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <bit>
#include <cerrno>
#include <cstring>

namespace rigidae {

static_assert(std::endian::native == std::endian::little, "rows are written as the machine holds them: '<' types");

namespace {

constexpr std::size_t kAlignment = 64;      // numpy aligns the data to 64 bytes
constexpr std::size_t kPreambleBytes = 10;  // magic (6), version (2), header length (2)
constexpr int kCountDigits = 20;            // room for any row count (2^64 has 20 digits)

}  // namespace

NpyFile::NpyFile(const std::filesystem::path& path, std::vector<NpyField> fields)
    : path_(path), fields_(std::move(fields)), stream_(path) {
  for (const NpyField& f : fields_) row_bytes_ += f.bytes;
  const std::string h = header(0);
  header_bytes_ = h.size();
  stream_.write(h);
}

// The preamble and the dict, padded so that the data starts at a multiple of
// kAlignment whatever the count (the count field has a fixed width).
std::string NpyFile::header(std::size_t rows) const {
  std::string descr;
  for (const NpyField& f : fields_) descr += fmt::format("{}('{}', '{}')", descr.empty() ? "" : ", ", f.name, f.type);
  std::string dict = fmt::format("{{'descr': [{}], 'fortran_order': False, 'shape': ({},), }}", descr, rows);
  // Spaces stand in for the digits a larger count would take, so the length never changes.
  dict.append(static_cast<std::size_t>(kCountDigits) - fmt::formatted_size("{}", rows), ' ');
  const std::size_t unpadded = kPreambleBytes + dict.size() + 1;  // + '\n'
  dict.append((kAlignment - unpadded % kAlignment) % kAlignment, ' ');
  dict.push_back('\n');
  const std::size_t n = dict.size();
  if (n > 0xffff) throw OutputError(fmt::format("{}: {} columns do not fit a .npy 1.0 header", path_.string(), fields_.size()));
  std::string out = "\x93NUMPY";
  out += '\x01';
  out += '\x00';
  out += static_cast<char>(n & 0xff);
  out += static_cast<char>(n >> 8);
  return out + dict;
}

void NpyFile::close() {
  if (closed_) return;
  closed_ = true;
  std::string first;
  try {
    stream_.close();
  } catch (const OutputError& e) {
    first = e.what();
  }
  // The rows wholly on disk: the file's size says (a failed write may have left part of one).
  auto fail = [&](const char* what) {
    const int err = errno;
    if (first.empty()) first = fmt::format("{}: {}: {}", path_.string(), what, std::strerror(err ? err : EIO));
  };
  const int fd = ::open(path_.c_str(), O_WRONLY | O_CLOEXEC);
  if (fd < 0) {
    fail("cannot reopen to write the row count");
  } else {
    struct stat st {};
    if (::fstat(fd, &st) != 0) {
      fail("cannot read its size");
    } else {
      const std::size_t size = static_cast<std::size_t>(st.st_size);
      const std::size_t rows = size > header_bytes_ && row_bytes_ > 0 ? (size - header_bytes_) / row_bytes_ : 0;
      const std::string h = header(rows);
      const off_t whole = static_cast<off_t>(header_bytes_ + rows * row_bytes_);
      if (size >= header_bytes_ && static_cast<off_t>(size) != whole && ::ftruncate(fd, whole) != 0)
        fail("cannot cut the last partial row");
      if (::pwrite(fd, h.data(), h.size(), 0) != static_cast<ssize_t>(h.size()))
        fail("cannot write the row count into the header");
      else if (::fsync(fd) != 0 && errno != EINVAL && errno != EROFS)
        fail("fsync failed");
    }
    if (::close(fd) != 0) fail("close failed");
  }
  if (!first.empty()) throw OutputError(first);
}

}  // namespace rigidae
