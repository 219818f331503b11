#include "memory_recorder.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rigidae::python {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The observation columns of steps.csv and trajectory.csv, in the order
// RunRecorder writes them (tests/python compares them with the CLI's headers).
std::vector<std::string> observation_columns(const std::vector<std::string>& multipliers) {
  std::vector<std::string> c{"qw", "qx", "qy", "qz", "omega_x", "omega_y", "omega_z", "drift_position",
                             "drift_velocity"};
  c.insert(c.end(), multipliers.begin(), multipliers.end());
  for (const char* s : {"energy", "energy_rel_error", "vertical_momentum", "vertical_momentum_rel_error"})
    c.emplace_back(s);
  return c;
}

}  // namespace

MemoryRecorder::MemoryRecorder(const DaeSystem& dae, const Scene& scene, bool keep_steps, bool keep_grid)
    : dae_(dae),
      keep_steps_(keep_steps),
      keep_grid_(keep_grid),
      with_chart_(dae.representation().has_charts()),
      step_observer_(dae, scene),
      grid_observer_(dae, scene) {
  const std::vector<std::string> names = dae.multiplier_names();
  const std::vector<std::string> obs = observation_columns(names);
  step_columns_ = {"t", "h", "order"};
  step_columns_.insert(step_columns_.end(), obs.begin(), obs.end());
  grid_columns_ = {"t"};
  grid_columns_.insert(grid_columns_.end(), obs.begin(), obs.end());
  if (with_chart_) {
    step_columns_.emplace_back("chart");
    grid_columns_.emplace_back("chart");
  }
  const int nm = static_cast<int>(names.size());
  extremes_.multiplier_min = Eigen::VectorXd::Constant(nm, std::numeric_limits<double>::infinity());
  extremes_.multiplier_max = Eigen::VectorXd::Constant(nm, -std::numeric_limits<double>::infinity());
}

void MemoryRecorder::append_observation(std::vector<double>& rows, const Observation& o) {
  rows.insert(rows.end(), o.q_WB.data(), o.q_WB.data() + 4);
  rows.insert(rows.end(), o.omega_B.data(), o.omega_B.data() + 3);
  rows.push_back(o.drift.position);
  rows.push_back(o.drift.velocity);
  for (int i = 0; i < o.multipliers.size(); ++i) rows.push_back(o.multipliers(i));
  rows.push_back(o.energy);
  rows.push_back(o.energy_error);
  rows.push_back(o.vertical_momentum);
  rows.push_back(o.vertical_momentum_error);
  if (with_chart_) {
    const std::string chart = dae_.representation().chart_name();
    auto it = std::find(chart_names_.begin(), chart_names_.end(), chart);
    if (it == chart_names_.end()) it = chart_names_.insert(chart_names_.end(), chart);
    rows.push_back(static_cast<double>(it - chart_names_.begin()));
  }
}

void MemoryRecorder::on_step(double t, double h, int order, const Eigen::VectorXd& y) {
  const Observation o = step_observer_.observe(t, y);
  if (keep_steps_) {
    steps_.push_back(t);
    steps_.push_back(h);
    steps_.push_back(order);
    append_observation(steps_, o);
  }
  // As RunRecorder::on_step.
  RunExtremes& e = extremes_;
  ++e.steps_recorded;
  e.max_drift_position = std::max(e.max_drift_position, o.drift.position);
  e.max_drift_velocity = std::max(e.max_drift_velocity, o.drift.velocity);
  e.max_abs_energy_error = std::max(e.max_abs_energy_error, std::abs(o.energy_error));
  e.max_abs_vertical_momentum_error = std::max(e.max_abs_vertical_momentum_error, std::abs(o.vertical_momentum_error));
  e.multiplier_min = e.multiplier_min.cwiseMin(o.multipliers);
  e.multiplier_max = e.multiplier_max.cwiseMax(o.multipliers);
  e.last = o;
}

void MemoryRecorder::on_output(double t, const Eigen::VectorXd& y) {
  const Observation o = grid_observer_.observe(t, y);
  if (keep_grid_) {
    grid_.push_back(t);
    append_observation(grid_, o);
  }
  if (extremes_.steps_recorded == 0) extremes_.last = o;
}

void MemoryRecorder::on_event(const EventNote& e) {
  // The fields events.csv fills for each kind; the others NaN (empty there).
  if (e.what == "chart_switch")
    events_.push_back({e.t, e.what, e.from, e.to, e.margin, kNaN, kNaN});
  else if (e.what == "projection")
    events_.push_back({e.t, e.what, "", "", kNaN, e.drift_position, e.drift_velocity});
}

}  // namespace rigidae::python
