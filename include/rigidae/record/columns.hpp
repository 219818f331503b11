#pragma once
// The one table of output columns: name, units, the files that carry it, and
// how its value is computed from an Observation and the step. steps.csv and
// trajectory.csv (header, units line, rows), summary.json's final row, and the
// readers behind compare and study (trajectory_csv.cpp) all go through it:
// adding a column is one row in src/record/columns.cpp. A mechanism's
// files are a table of their own (src/record/mechanism_columns.cpp) written
// by the same functions.
#include <fmt/format.h>

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "rigidae/record/npy_file.hpp"
#include "rigidae/record/observation.hpp"

namespace rigidae::columns {

// Where a column appears (a bit set).
enum File : unsigned { kSteps = 1u, kTrajectory = 2u };

// What is known when a row is written.
struct Sample {
  double t = 0.0;
  double h = 0.0;       // the step just taken (steps.csv)
  int order = 0;        // its BDF order (steps.csv)
  const Observation* observation = nullptr;
  std::string_view chart;  // the current Euler-angle chart ("" without charts)
  std::span<const double> values;  // a Values column's numbers (a mechanism's per-part columns)
};

enum class Kind {
  Real,         // one number, `value`
  Integer,      // one whole number, `integer`
  Multipliers,  // one column per multiplier, named by the DAE ("lambda_*", "mu_*")
  Chart,        // the Euler-angle chart's name; only for representations with charts
  Values,       // one column per entry of Sample::values, named by the caller (as Multipliers)
};

struct Column {
  std::string_view name;   // header name (Multipliers: the DAE names them)
  std::string_view units;  // this column's part of the units line; "" for none
  unsigned files = kSteps | kTrajectory;
  Kind kind = Kind::Real;
  double (*value)(const Sample&) = nullptr;
  long (*integer)(const Sample&) = nullptr;
};

// How a table writes its numbers as text.
enum class Digits {
  ToChars,  // std::to_chars' shortest round trip: %f or %e, whichever is shorter (single body)
  Fmt,      // fmt's "{}": the same digits, %f from 1e-4 up to 1e16 (the multibody files' layout)
};

// A table of columns, in file order, and its layout of numbers.
struct Table {
  std::span<const Column> columns;
  Digits digits = Digits::ToChars;
};

// Every single-body column, in file order.
std::span<const Column> all();
// The single-body table (all(), written in to_chars' layout).
const Table& single_body();

// `multiplier_names` below names the columns of the table's one column of
// kind Multipliers or Values (a table has at most one of the two).

// The first line of the table's files: "# units: t s; h s; ...".
std::string units_line(const Table& table);
// The header line of `file` (without the newline).
std::string header(const Table& table, File file, const std::vector<std::string>& multiplier_names,
                   bool with_chart);
// Appends one row of `file` (with its newline) to b; allocates nothing.
void append_row(fmt::memory_buffer& b, const Table& table, File file, const Sample& s, bool with_chart);

// The binary step file (steps.npy): the fields of `file` in header order,
// Real and multiplier columns '<f8', Integer '<i8', the chart '|S8'.
inline constexpr std::size_t kChartBytes = 8;
std::vector<NpyField> npy_fields(const Table& table, File file, const std::vector<std::string>& multiplier_names,
                                 bool with_chart);
// Appends one such row (packed, little-endian) to b; allocates nothing.
void append_binary_row(fmt::memory_buffer& b, const Table& table, File file, const Sample& s, bool with_chart);

// The same for the single-body table.
inline std::string units_line() { return units_line(single_body()); }
inline std::string header(File file, const std::vector<std::string>& multiplier_names, bool with_chart) {
  return header(single_body(), file, multiplier_names, with_chart);
}
inline void append_row(fmt::memory_buffer& b, File file, const Sample& s, bool with_chart) {
  append_row(b, single_body(), file, s, with_chart);
}

// Appends one row of `file` to `row` as numbers (a run kept in memory):
// integer columns as numbers, the chart as its index in `charts` (added
// there when new).
void append_numbers(std::vector<double>& row, const Table& table, File file, const Sample& s, bool with_chart,
                    std::vector<std::string>& charts);

// Multiplier columns by their prefix: "lambda_" a force (J), "mu_" a kinematic one (1/s).
bool is_multiplier(std::string_view header_name);
bool is_force_multiplier(std::string_view header_name);

}  // namespace rigidae::columns
