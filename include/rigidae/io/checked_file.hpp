#pragma once
// Output files whose success means every byte reached the file system.
//
// Every write, flush, fsync and close is checked; the first failure throws
// OutputError naming the file and the system's reason (strerror). Large
// streams (the CSV files of a run) are written in place and keep whatever was
// written before the failure; small files (summaries, run records, tables)
// are written whole to a temporary name in the same folder, synced, and
// renamed over the final name, so a reader sees the old file or the complete
// new one, never a truncated one.
#include <cstddef>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace rigidae {

// An output file could not be written completely. The CLI maps it to exit 1
// (the run's results are incomplete, not the input wrong).
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Writes `text` to `path` through a temporary sibling and a rename.
// Throws OutputError (the temporary is removed) on any failure. A path that
// names a device, FIFO or socket (after links: -o /dev/stdout, a link to
// /dev/full) is written in place, checked the same way, never replaced.
void write_file_atomically(const std::filesystem::path& path, std::string_view text);

// A buffered stream written in place, every operation checked.
class CheckedStream {
 public:
  // Throws InputError when the file cannot be created (a wrong --out is bad input).
  explicit CheckedStream(std::filesystem::path path, std::size_t buffer_bytes = 1 << 20);
  ~CheckedStream();  // closes without checking: close() is the checked way
  CheckedStream(const CheckedStream&) = delete;
  CheckedStream& operator=(const CheckedStream&) = delete;

  // Appends bytes; throws OutputError when the system refuses them.
  void write(const char* data, std::size_t n) {
    if (!f_ || std::fwrite(data, 1, n, f_) != n) fail("write failed");
    bytes_ += n;
  }
  void write(std::string_view s) { write(s.data(), s.size()); }
  // Hands the buffer to the system (checked).
  void flush();
  // Flushes, syncs to the device and closes (each checked). Idempotent.
  void close();

  const std::filesystem::path& path() const { return path_; }
  std::size_t bytes_written() const { return bytes_; }

 private:
  [[noreturn]] void fail(const char* what);

  std::filesystem::path path_;
  std::FILE* f_ = nullptr;
  std::vector<char> buffer_;
  std::size_t bytes_ = 0;  // accepted by write(), not necessarily on disk yet
  std::string failure_;    // the first failure, repeated by any later use
};

}  // namespace rigidae
