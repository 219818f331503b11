#pragma once
// A run kept in memory instead of on disk: the rows of steps.csv and
// trajectory.csv, computed through the same table of columns
// (record/columns.hpp), as flat row-major buffers of doubles (integer
// columns as numbers, the chart as an index into chart_names), the events,
// and the run's extremes computed exactly as RunRecorder computes them, so
// that a run from Python and the CLI's summary.json agree.
#include <string>
#include <vector>

#include "rigidae/record/columns.hpp"
#include "rigidae/record/observation.hpp"
#include "rigidae/record/recorder.hpp"
#include "rigidae/solver/ida_driver.hpp"

namespace rigidae::python {

struct EventRow {
  double t = 0.0;
  std::string event, from, to;
  double margin, drift_position, drift_velocity;  // NaN where events.csv leaves the field empty
};

class MemoryRecorder final : public RecordingSink {
 public:
  // keep_steps / keep_grid: hold those rows (the extremes are kept either way).
  MemoryRecorder(const OneBodyView& problem, const Scene& scene, bool keep_steps, bool keep_grid);

  void on_step(double t, double h, int order, const Eigen::VectorXd& y) override;
  void on_output(double t, const Eigen::VectorXd& y) override;
  void on_event(const EventNote& note) override;
  const RunExtremes& extremes() const override { return extremes_; }

  // Column names in the CSV files' order, and those holding whole numbers.
  const std::vector<std::string>& step_columns() const { return step_columns_; }
  const std::vector<std::string>& grid_columns() const { return grid_columns_; }
  std::vector<std::string> integer_columns() const;
  const std::vector<double>& steps() const { return steps_; }  // step_columns().size() per row
  const std::vector<double>& grid() const { return grid_; }
  const std::vector<std::string>& chart_names() const { return chart_names_; }
  const std::vector<EventRow>& events() const { return events_; }

 private:
  void append(std::vector<double>& rows, columns::File file, const columns::Sample& s);

  const OneBodyView& problem_;
  bool keep_steps_, keep_grid_, with_chart_;
  Observer step_observer_, grid_observer_;
  std::vector<std::string> step_columns_, grid_columns_, chart_names_;
  std::vector<double> steps_, grid_;
  std::vector<EventRow> events_;
  RunExtremes extremes_;
};

// Passes the run to the files and to memory; the monitor in front reads the
// extremes of the memory side (the same values).
class TeeSink final : public RecordingSink {
 public:
  TeeSink(StepSink& files, MemoryRecorder& memory) : files_(files), memory_(memory) {}
  void on_step(double t, double h, int order, const Eigen::VectorXd& y) override {
    files_.on_step(t, h, order, y);
    memory_.on_step(t, h, order, y);
  }
  void on_output(double t, const Eigen::VectorXd& y) override {
    files_.on_output(t, y);
    memory_.on_output(t, y);
  }
  void on_event(const EventNote& note) override {
    files_.on_event(note);
    memory_.on_event(note);
  }
  const RunExtremes& extremes() const override { return memory_.extremes(); }

 private:
  StepSink& files_;
  MemoryRecorder& memory_;
};

}  // namespace rigidae::python
