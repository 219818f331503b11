#include "rigidae/record/multibody_recorder.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <iterator>
#include <cmath>

#include "rigidae/record/columns.hpp"

namespace rigidae {

namespace {

std::string join(const std::vector<std::string>& v, const char* sep) {
  std::string s;
  for (std::size_t i = 0; i < v.size(); ++i) s += (i ? sep : "") + v[i];
  return s;
}

std::string units_comment(const multibody::MultibodyProblem& p) {
  const std::vector<std::string> names = p.output_names(), units = p.output_units();
  std::string s = "# units: t s";
  // One entry per kind of column (the body and joint names vary).
  std::vector<std::string> seen;
  for (std::size_t i = 0; i < names.size(); ++i) {
    const std::size_t dot = names[i].rfind('.');
    const std::string kind = dot == std::string::npos ? names[i] : "*." + names[i].substr(dot + 1);
    if (std::find(seen.begin(), seen.end(), kind) != seen.end()) continue;
    seen.push_back(kind);
    s += "; " + kind + " " + units[i];
  }
  return s + "; q* unit quaternion of R_WB (scalar first); w* space angular velocity; JOINT.force/torque on "
             "body b (on a when b is the ground) at its joint point, space frame; phi |Phi| (m for point rows, 1 "
             "for angular rows), phi_dot |G v|";
}

// steps.csv / steps.npy: a row per accepted step. Drift is the largest over
// the constraint rows; energy the total H with its error against the start.
const Observation& obs(const columns::Sample& s) { return *s.observation; }

const columns::Column kStepColumns[] = {
    {"t", "t s", columns::kSteps, columns::Kind::Real, [](const columns::Sample& s) { return s.t; }, nullptr},
    {"h", "h s", columns::kSteps, columns::Kind::Real, [](const columns::Sample& s) { return s.h; }, nullptr},
    {"order", "", columns::kSteps, columns::Kind::Integer, nullptr,
     [](const columns::Sample& s) { return static_cast<long>(s.order); }},
    {"drift_position", "drift_position max |Phi| (m or 1)", columns::kSteps, columns::Kind::Real,
     [](const columns::Sample& s) { return obs(s).drift.position; }, nullptr},
    {"drift_velocity", "drift_velocity max |G v|", columns::kSteps, columns::Kind::Real,
     [](const columns::Sample& s) { return obs(s).drift.velocity; }, nullptr},
    {"energy", "energy J", columns::kSteps, columns::Kind::Real, [](const columns::Sample& s) { return obs(s).energy; },
     nullptr},
    {"energy_rel_error", "energy_rel_error (H - H0)/max(|H0|, 1 J)", columns::kSteps, columns::Kind::Real,
     [](const columns::Sample& s) { return obs(s).energy_error; }, nullptr},
};

// Numbers in fmt's layout, as in trajectory.csv (and as multibody steps.csv
// always had them: the files stay byte for byte what earlier runs wrote).
const columns::Table kStepTable{kStepColumns, columns::Digits::Fmt};

}  // namespace

MultibodyRecorder::MultibodyRecorder(multibody::MultibodyProblem& problem, const std::filesystem::path& out_dir,
                                     const OutputSettings& output, const TimeGrid& time)
    : problem_(problem),
      events_(out_dir / "events.csv",
              "# units: t s; margin |det B| of the chart left (chart_switch), 1; drift_position and "
              "drift_velocity just before a projection",
              "t,event,body,from,to,margin,drift_position,drift_velocity"),
      steps_(kStepTable, {}, false, output, out_dir),
      trajectory_(open_csv_if(output.record != RecordMode::None, out_dir / "trajectory.csv", units_comment(problem),
                              "t," + join(problem.output_names(), ","))) {
  start_is_output_ = time.output_times.empty() || time.output_times.front() == time.start;
  row_.resize(problem.output_names().size());
  const std::vector<std::string> names = problem.output_names();
  energy_column_ = static_cast<int>(std::find(names.begin(), names.end(), "energy") - names.begin());
}

void MultibodyRecorder::on_step(double t, double h, int order, const Eigen::VectorXd& y) {
  const auto [pos, vel] = problem_.drift(t, y.data());
  const double H = problem_.kinetic_energy(y.data()) + problem_.potential_energy(y.data());
  if (!have_H0_) H0_ = H, have_H0_ = true;
  const double err = (H - H0_) / std::max(std::abs(H0_), 1.0);
  ++steps_recorded_;
  max_drift_position_ = std::max(max_drift_position_, pos);
  max_drift_velocity_ = std::max(max_drift_velocity_, vel);
  max_energy_error_ = std::max(max_energy_error_, std::abs(err));
  last_energy_ = H;
  if (steps_) {
    Observation o;
    o.drift = {pos, vel};
    o.energy = H;
    o.energy_error = err;
    steps_.write({t, h, order, &o, {}});
  }
}

void MultibodyRecorder::on_output(double t, const Eigen::VectorXd& y) {
  const bool row = trajectory_ && (seen_start_ || start_is_output_);
  seen_start_ = true;
  if (!row && have_H0_) return;
  problem_.output_row(y.data(), row_.data());
  if (!have_H0_) H0_ = row_[energy_column_], have_H0_ = true;
  if (!row) return;
  fmt::memory_buffer line;
  fmt::format_to(std::back_inserter(line), "{}", t);
  for (double v : row_) fmt::format_to(std::back_inserter(line), ",{}", v);
  line.push_back('\n');
  trajectory_->file().write(line.data(), line.size());
}

void MultibodyRecorder::on_event(const EventNote& n) {
  events_.file().write(fmt::format("{},{},{},{},{},{},{},{}\n", n.t, n.what, n.body, n.from, n.to, n.margin,
             n.drift_position, n.drift_velocity));
}

void MultibodyRecorder::flush() {
  steps_.flush();
  if (trajectory_) trajectory_->flush();
  events_.flush();
}

void MultibodyRecorder::close() {
  CloseEach each;
  each([&] { steps_.close(); });
  if (trajectory_) each([&] { trajectory_->close(); });
  each([&] { events_.close(); }).rethrow_first();
}

}  // namespace rigidae
