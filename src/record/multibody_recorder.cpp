#include "rigidae/record/multibody_recorder.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <iterator>
#include <cmath>

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

}  // namespace

MultibodyRecorder::MultibodyRecorder(multibody::MultibodyProblem& problem, const std::filesystem::path& out_dir)
    : problem_(problem),
      steps_(out_dir / "steps.csv",
             "# units: t s; h s; drift_position max |Phi| (m or 1); drift_velocity max |G v|; energy J; "
             "energy_rel_error (H - H0)/max(|H0|, 1 J)",
             "t,h,order,drift_position,drift_velocity,energy,energy_rel_error"),
      trajectory_(out_dir / "trajectory.csv", units_comment(problem), "t," + join(problem.output_names(), ",")),
      events_(out_dir / "events.csv",
              "# units: t s; margin |det B| of the chart left (chart_switch), 1; drift_position and "
              "drift_velocity just before a projection",
              "t,event,body,from,to,margin,drift_position,drift_velocity") {
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
  steps_.file().write(fmt::format("{},{},{},{},{},{},{}\n", t, h, order, pos, vel, H, err));
}

void MultibodyRecorder::on_output(double t, const Eigen::VectorXd& y) {
  problem_.output_row(y.data(), row_.data());
  if (!have_H0_) H0_ = row_[energy_column_], have_H0_ = true;
  fmt::memory_buffer line;
  fmt::format_to(std::back_inserter(line), "{}", t);
  for (double v : row_) fmt::format_to(std::back_inserter(line), ",{}", v);
  line.push_back('\n');
  trajectory_.file().write(line.data(), line.size());
}

void MultibodyRecorder::on_event(const EventNote& n) {
  events_.file().write(fmt::format("{},{},{},{},{},{},{},{}\n", n.t, n.what, n.body, n.from, n.to, n.margin,
             n.drift_position, n.drift_velocity));
}

void MultibodyRecorder::flush() {
  steps_.flush();
  trajectory_.flush();
  events_.flush();
}

}  // namespace rigidae
