#pragma once
// Streams a run to disk as it happens and keeps its extremes.
//
// Files in the output folder (scene.output says which):
//   steps.csv       one row per accepted step (record = steps, step_format = csv)
//   steps.npy       the same rows in NumPy's binary format (step_format = npy)
//   trajectory.csv  one row per output-grid point (record = steps or grid)
//   events.csv      one row per Euler-angle chart switch or projection (always)
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
#include "rigidae/multibody/one_body_view.hpp"
#include "rigidae/record/observation.hpp"
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
    multiplier_min = multiplier_min.cwiseMin(o.multipliers);
    multiplier_max = multiplier_max.cwiseMax(o.multipliers);
    last = o;
  }
};

// A CSV file: units comment, header, then rows; every write checked
// (io/checked_file.hpp), so a full disk ends the run with OutputError.
class CsvStream {
 public:
  CsvStream(const std::filesystem::path& path, const std::string& units_comment, const std::string& header);
  CheckedStream& file() { return stream_; }
  void flush() { stream_.flush(); }
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
// step writer of RunRecorder and MultibodyRecorder.
class StepFile {
 public:
  // `table` outlives the file (the tables are static).
  // `units_more` is appended to the table's units line (a mechanism's per-part columns).
  StepFile(const columns::Table& table, const std::vector<std::string>& multiplier_names, bool with_chart,
           const OutputSettings& output, const std::filesystem::path& out_dir, const std::string& units_more = {});
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
  void flush() {
    if (csv_) csv_->flush();
    if (npy_) npy_->flush();
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

// A sink that keeps the run's extremes as it goes (RunRecorder on disk; the
// Python module's in-memory recorder): what InvariantMonitor sits in front of.
class RecordingSink : public StepSink {
 public:
  virtual const RunExtremes& extremes() const = 0;
};

class RunRecorder final : public RecordingSink {
 public:
  // Observes the problem's states in its current chart; writes what
  // scene.output asks for (and removes a previous run's files it does not write).
  RunRecorder(const OneBodyView& problem, const Scene& scene, const std::filesystem::path& out_dir);

  void on_step(double t, double h, int order, const Eigen::VectorXd& y) override;
  void on_output(double t, const Eigen::VectorXd& y) override;
  void on_event(const EventNote& note) override;
  void flush();
  // Flushes, syncs and closes the files; throws OutputError naming the
  // first that fails (the others are still closed).
  void close();

  const RunExtremes& extremes() const override { return extremes_; }
  const std::vector<std::string>& multiplier_names() const { return multiplier_names_; }

 private:
  // One row of `file` from the table of columns (record/columns.hpp).
  void write_row(CheckedStream& f, columns::File file, const columns::Sample& sample);

  const OneBodyView& problem_;
  std::vector<std::string> multiplier_names_;
  bool with_chart_;
  Observer step_observer_, grid_observer_;
  StepFile steps_;
  std::unique_ptr<CsvStream> trajectory_;
  CsvStream events_;
  RunExtremes extremes_;
  // The integrators report the start first, always; it is a row of
  // trajectory.csv only when it is an output time (output.times may leave it out).
  bool start_is_output_ = true, seen_start_ = false;
};

}  // namespace rigidae
