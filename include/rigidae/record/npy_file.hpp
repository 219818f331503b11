#pragma once
// A NumPy .npy file (format version 1.0) holding a 1-D structured array,
// written row by row as a run goes: numpy.load returns a record array whose
// field names are the columns (pandas.DataFrame takes it as it is).
//
// Layout (numpy.lib.format): the magic "\x93NUMPY", version bytes 1 0, the
// header length as little-endian uint16, then an ASCII Python dict
//   {'descr': [('t', '<f8'), ('order', '<i8'), ('chart', '|S8'), ...],
//    'fortran_order': False, 'shape': (ROWS,), }
// padded with spaces and ended by '\n' so that the data starts at a multiple
// of 64 bytes; then ROWS rows of packed little-endian fields.
//
// ROWS is unknown while the run goes: the header is written with room for any
// count and rewritten by close() with the rows wholly on disk (a write that
// failed midway leaves the rows before it valid, and the file is cut after
// the last whole row). A process killed before close() leaves ROWS = 0.
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "rigidae/io/checked_file.hpp"

namespace rigidae {

struct NpyField {
  std::string name;
  std::string type;   // NumPy's type string: "<f8", "<i8", "|S8"
  std::size_t bytes;  // its size
};

class NpyFile {
 public:
  // Throws InputError when the file cannot be created.
  NpyFile(const std::filesystem::path& path, std::vector<NpyField> fields);

  std::size_t row_bytes() const { return row_bytes_; }
  // Appends one row of row_bytes() bytes, the fields packed in order.
  void write_row(const char* row) { stream_.write(row, row_bytes_); }
  // Flushes and closes the rows, then writes their count into the header
  // (each step checked). Throws OutputError naming the first failure; the
  // header is rewritten even after a failed write. Idempotent.
  void close();

 private:
  std::string header(std::size_t rows) const;

  std::filesystem::path path_;
  std::vector<NpyField> fields_;
  std::size_t row_bytes_ = 0, header_bytes_ = 0;
  CheckedStream stream_;
  bool closed_ = false;
};

}  // namespace rigidae
