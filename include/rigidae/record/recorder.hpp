#pragma once
// The one recorder of every run: streams it to disk (and/or to memory) as it
// happens and keeps its extremes. What a row holds is the system's column
// set (record/run_columns.hpp); the recorder is the same for one body and
// for a mechanism.
//
// Files in the output folder (scene.output says which):
//   steps.csv       one row per accepted step (record = steps, step_format = csv)
//   steps.npy       the same rows in NumPy's binary format (step_format = npy)
//   trajectory.csv  one row per output-grid point (record = steps or grid)
//   events.csv      one row per event (chart switch, projection, ...; always)
// Rows go through a large write buffer (no history is held in memory), and
// the files are flushed when the run ends, however it ends. Every step is
// observed whatever is recorded: the extremes (summary.json, the accuracy
// check) need each one.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "rigidae/io/checked_file.hpp"
#include "rigidae/record/columns.hpp"
#include "rigidae/record/npy_file.hpp"
#include "rigidae/record/observation.hpp"
#include "rigidae/record/run_columns.hpp"
#include "rigidae/solver/ida_driver.hpp"

namespace rigidae {

struct RunExtremes {
  long steps_recorded = 0;
  double max_drift_position = 0.0;
  double max_drift_velocity = 0.0;
  double max_abs_energy_error = 0.0;
  double max_abs_vertical_momentum_error = 0.0;
  Eigen::VectorXd multiplier_min, multiplier_max;
  Observation last;  // at the last recorded step (or the start)

  // Takes in one accepted step's observation (every recorder keeps the same maxima).
  void add_step(const Observation& o) {
    ++steps_recorded;
    max_drift_position = std::max(max_drift_position, o.drift.position);
    max_drift_velocity = std::max(max_drift_velocity, o.drift.velocity);
    max_abs_energy_error = std::max(max_abs_energy_error, std::abs(o.energy_error));
    max_abs_vertical_momentum_error = std::max(max_abs_vertical_momentum_error, std::abs(o.vertical_momentum_error));
    if (multiplier_min.size() != o.multipliers.size()) {  // the first step
      multiplier_min = o.multipliers;
      multiplier_max = o.multipliers;
    } else {
      multiplier_min = multiplier_min.cwiseMin(o.multipliers);
      multiplier_max = multiplier_max.cwiseMax(o.multipliers);
    }
    last = o;
  }
};

// A CSV file: units comment, header, then rows; every write checked
// (io/checked_file.hpp), so a full disk ends the run with OutputError.
class CsvStream {
 public:
  CsvStream(const std::filesystem::path& path, const std::string& units_comment, const std::string& header);
  CheckedStream& file() { return stream_; }
  void close() { stream_.close(); }

 private:
  CheckedStream stream_;
};

// Opens `path` as a CsvStream when wanted; else removes a previous run's file
// there (a stale file would pass for this run's) and returns null.
std::unique_ptr<CsvStream> open_csv_if(bool wanted, const std::filesystem::path& path,
                                       const std::string& units_comment, const std::string& header);

// A run's step file, steps.csv or steps.npy as output.record and
// output.step_format say (or none; a previous run's are removed), written a
// row per accepted step from a table of columns (record/columns.hpp): the one
// step writer of RunRecorder, for either column set.
class StepFile {
 public:
  // `table` outlives the file (the tables are static); `units` is the file's first line.
  StepFile(const columns::Table& table, const std::vector<std::string>& multiplier_names, bool with_chart,
           const OutputSettings& output, const std::filesystem::path& out_dir, const std::string& units);
  // Whether a step file is written.
  explicit operator bool() const { return csv_ || npy_; }
  // One row (allocates nothing once the row buffer has grown to a row's
  // length: it is kept from row to row, and a mechanism's row can be wide).
  void write(const columns::Sample& s) {
    fmt::memory_buffer& b = row_;
    b.clear();
    if (csv_) {
      columns::append_row(b, table_, columns::kSteps, s, with_chart_);
      csv_->file().write(b.data(), b.size());
    } else if (npy_) {
      columns::append_binary_row(b, table_, columns::kSteps, s, with_chart_);
      npy_->write_row(b.data());
    }
  }
  // Closes the file; throws OutputError when that fails.
  void close() {
    if (csv_) csv_->close();
    if (npy_) npy_->close();
  }

 private:
  const columns::Table& table_;
  bool with_chart_;
  std::unique_ptr<CsvStream> csv_;  // at most one of the two
  std::unique_ptr<NpyFile> npy_;
  fmt::memory_buffer row_;
};

// Closes a recorder's files one after another, each even when one before
// failed, and throws an OutputError naming the first failure at the end.
class CloseEach {
 public:
  template <typename Close>
  CloseEach& operator()(Close&& close_one) {
    try {
      close_one();
    } catch (const OutputError& e) {
      if (first_.empty()) first_ = e.what();
    }
    return *this;
  }
  void rethrow_first() const {
    if (!first_.empty()) throw OutputError(first_);
  }

 private:
  std::string first_;
};

// A run held in memory (the Python module): the rows of the step file and of
// trajectory.csv as numbers, row-major, integer columns as numbers and the
// chart as an index into `charts`; every event.
struct MemoryRows {
  bool keep_steps = false, keep_grid = false;
  std::vector<std::string> step_columns, grid_columns, integer_columns;  // set by the recorder
  std::vector<double> steps, grid;
  std::vector<std::string> charts;
  std::vector<EventNote> events;
};

class RunRecorder final : public StepSink {
 public:
  // Writes into out_dir what `output` asks for (and removes a previous run's
  // files it does not write); with an empty out_dir, no file. Keeps the rows
  // `memory` asks for there when given. `time`: the run's grid (the start is
  // reported first, always, and is a row only when it is an output time).
  RunRecorder(RunColumns& columns, const OutputSettings& output, const TimeGrid& time,
              const std::filesystem::path& out_dir, MemoryRows* memory = nullptr);

  void on_step(double t, double h, int order, const Eigen::VectorXd& y) override;
  void on_output(double t, const Eigen::VectorXd& y) override;
  void on_event(const EventNote& note) override;
  // Flushes, syncs and closes the files (the .npy header gets its row count);
  // throws OutputError naming the first that fails (the others are still closed).
  void close();

  const RunExtremes& extremes() const { return extremes_; }
  const RunColumns& columns() const { return columns_; }

 private:
  RunColumns& columns_;
  MemoryRows* memory_;
  bool with_chart_;
  std::unique_ptr<CsvStream> events_;  // created first, then the step file and trajectory.csv
  StepFile steps_;
  std::unique_ptr<CsvStream> trajectory_;
  bool step_values_wanted_ = false;
  std::vector<double> step_values_, grid_values_;  // the Values columns of one row, reused
  fmt::memory_buffer row_;
  Observation step_observation_;
  RunExtremes extremes_;
  bool start_is_output_ = true, seen_start_ = false;
};

}  // namespace rigidae
