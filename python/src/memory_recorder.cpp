#include "memory_recorder.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace rigidae::python {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::vector<std::string> split(const std::string& header) {
  std::vector<std::string> names;
  std::stringstream ss(header);
  std::string name;
  while (std::getline(ss, name, ',')) names.push_back(name);
  return names;
}

}  // namespace

MemoryRecorder::MemoryRecorder(const OneBodyView& problem, const Scene& scene, bool keep_steps, bool keep_grid)
    : problem_(problem),
      keep_steps_(keep_steps),
      keep_grid_(keep_grid),
      with_chart_(problem.representation().has_charts()),
      step_observer_(problem, scene),
      grid_observer_(problem, scene) {
  const std::vector<std::string> names = problem.multiplier_names();
  step_columns_ = split(columns::header(columns::kSteps, names, with_chart_));
  grid_columns_ = split(columns::header(columns::kTrajectory, names, with_chart_));
  const int nm = static_cast<int>(names.size());
  extremes_.multiplier_min = Eigen::VectorXd::Constant(nm, std::numeric_limits<double>::infinity());
  extremes_.multiplier_max = Eigen::VectorXd::Constant(nm, -std::numeric_limits<double>::infinity());
}

std::vector<std::string> MemoryRecorder::integer_columns() const {
  std::vector<std::string> names;
  for (const columns::Column& c : columns::all())
    if (c.kind == columns::Kind::Integer) names.emplace_back(c.name);
  return names;
}

void MemoryRecorder::append(std::vector<double>& rows, columns::File file, const columns::Sample& s) {
  for (const columns::Column& c : columns::all()) {
    if (!(c.files & file)) continue;
    switch (c.kind) {
      case columns::Kind::Real: rows.push_back(c.value(s)); break;
      case columns::Kind::Integer: rows.push_back(static_cast<double>(c.integer(s))); break;
      case columns::Kind::Multipliers: {
        const auto& m = s.observation->multipliers;
        for (int i = 0; i < m.size(); ++i) rows.push_back(m(i));
        break;
      }
      case columns::Kind::Values: rows.insert(rows.end(), s.values.begin(), s.values.end()); break;
      case columns::Kind::Chart: {
        if (!with_chart_) break;
        auto it = std::find(chart_names_.begin(), chart_names_.end(), s.chart);
        if (it == chart_names_.end()) it = chart_names_.insert(chart_names_.end(), std::string(s.chart));
        rows.push_back(static_cast<double>(it - chart_names_.begin()));
        break;
      }
    }
  }
}

void MemoryRecorder::on_step(double t, double h, int order, const Eigen::VectorXd& y) {
  const Observation o = step_observer_.observe(t, y);
  if (keep_steps_) {
    const std::string chart = with_chart_ ? problem_.representation().chart_name() : std::string();
    append(steps_, columns::kSteps, columns::Sample{t, h, order, &o, chart, {}});
  }
  extremes_.add_step(o);
}

void MemoryRecorder::on_output(double t, const Eigen::VectorXd& y) {
  const Observation o = grid_observer_.observe(t, y);
  if (keep_grid_) {
    const std::string chart = with_chart_ ? problem_.representation().chart_name() : std::string();
    append(grid_, columns::kTrajectory, columns::Sample{t, 0.0, 0, &o, chart, {}});
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
