#pragma once
// A run kept in memory instead of on disk: the rows of steps.csv and
// trajectory.csv as flat row-major buffers of doubles (order and chart as
// numbers, the chart an index into chart_names), the events, and the run's
// extremes computed exactly as RunRecorder computes them, so that a run from
// Python and the CLI's summary.json agree.
#include <string>
#include <vector>

#include "rigidae/record/observation.hpp"
#include "rigidae/record/recorder.hpp"
#include "rigidae/solver/ida_driver.hpp"

namespace rigidae::python {

struct EventRow {
  double t = 0.0;
  std::string event, from, to;
  double margin, drift_position, drift_velocity;  // NaN where the CSV leaves the field empty
};

class MemoryRecorder final : public StepSink {
 public:
  // keep_steps / keep_grid: hold those rows (the extremes are kept either way).
  MemoryRecorder(const DaeSystem& dae, const Scene& scene, bool keep_steps, bool keep_grid);

  void on_step(double t, double h, int order, const Eigen::VectorXd& y) override;
  void on_output(double t, const Eigen::VectorXd& y) override;
  void on_event(const EventNote& note) override;

  const RunExtremes& extremes() const { return extremes_; }
  // Column names in the CSV files' order.
  const std::vector<std::string>& step_columns() const { return step_columns_; }
  const std::vector<std::string>& grid_columns() const { return grid_columns_; }
  const std::vector<double>& steps() const { return steps_; }  // step_columns().size() per row
  const std::vector<double>& grid() const { return grid_; }
  const std::vector<std::string>& chart_names() const { return chart_names_; }
  const std::vector<EventRow>& events() const { return events_; }

 private:
  void append_observation(std::vector<double>& rows, const Observation& o);

  const DaeSystem& dae_;
  bool keep_steps_, keep_grid_, with_chart_;
  Observer step_observer_, grid_observer_;
  std::vector<std::string> step_columns_, grid_columns_, chart_names_;
  std::vector<double> steps_, grid_;
  std::vector<EventRow> events_;
  RunExtremes extremes_;
};

// Passes the run to two sinks (files and memory).
class TeeSink final : public StepSink {
 public:
  TeeSink(StepSink& a, StepSink& b) : a_(a), b_(b) {}
  void on_step(double t, double h, int order, const Eigen::VectorXd& y) override {
    a_.on_step(t, h, order, y);
    b_.on_step(t, h, order, y);
  }
  void on_output(double t, const Eigen::VectorXd& y) override {
    a_.on_output(t, y);
    b_.on_output(t, y);
  }
  void on_event(const EventNote& note) override {
    a_.on_event(note);
    b_.on_event(note);
  }

 private:
  StepSink &a_, &b_;
};

}  // namespace rigidae::python
