#include "rigidae/record/multibody_recorder.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <iterator>
#include <cmath>

#include "rigidae/record/columns.hpp"
#include "rigidae/record/error_control.hpp"

namespace rigidae {

namespace {

std::string join(const std::vector<std::string>& v, const char* sep) {
  std::string s;
  for (std::size_t i = 0; i < v.size(); ++i) s += (i ? sep : "") + v[i];
  return s;
}

std::string units_comment(const multibody::MultibodyProblem& p, const RecordedParts& parts,
                          const std::string& not_controlled) {
  const std::vector<std::string> names = p.output_names(parts), units = p.output_units(parts);
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
             "body b (on a when b is the ground) at its joint point, space frame; residual_position |Phi| (m for "
             "point rows, 1 for angular rows), residual_velocity |G v|; JOINT.angle* (rad, unwrapped: whole turns "
             "counted) and JOINT.displacement (m) the joint's coordinates, *_rate their rates" + (parts.joints.empty() ? std::string() : not_controlled);
}

// The units of the step file's per-part columns (after the table's own).
std::string step_part_units(const RecordedParts& parts, bool any_column, const std::string& not_controlled) {
  if (!any_column) return "";
  std::string s;
  if (!parts.bodies.empty())
    s += "; BODY.lambda_* J, BODY.mu_* 1/s (multipliers of a body's own constraints, e.g. the quaternion norm)";
  if (!parts.joints.empty())
    s += "; JOINT.lambda_* N (point rows) or N m (angular rows), JOINT.mu_* m/s or 1/s (multipliers of the joint's "
         "rows, named by row); JOINT.force_* N, JOINT.torque_* N m the reaction on body b (on a when b is the "
         "ground) at its joint point, space frame; JOINT.residual_position |Phi| m or 1, JOINT.residual_velocity |G v| m/s or "
         "1/s; JOINT.angle* rad (unwrapped), JOINT.displacement m, *_rate rad/s or m/s: the joint's coordinates";
  return s + not_controlled;
}

std::string not_controlled_note(const multibody::MultibodyProblem& p, const std::string& integrator) {
  const MultiplierErrorControl c =
      multiplier_error_control(integrator, p.suppress_algebraic_error_test(), p.scheme().name);
  return c.controlled ? std::string() : "; multipliers and reactions NOT error-controlled: " + c.note;
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
    {"energy_rel_error", "energy_rel_error (H - H0 - W)/max(|H0|, 1 J), W the work of drivers and loads", columns::kSteps, columns::Kind::Real,
     [](const columns::Sample& s) { return obs(s).energy_error; }, nullptr},
    // The recorded parts' multipliers, reactions and drift (MultibodyProblem::step_part_names).
    {"parts", "", columns::kSteps, columns::Kind::Values, nullptr, nullptr},
};

// Numbers in fmt's layout, as in trajectory.csv (and as multibody steps.csv
// always had them: the files stay byte for byte what earlier runs wrote).
const columns::Table kStepTable{kStepColumns, columns::Digits::Fmt};

}  // namespace

MultibodyRecorder::MultibodyRecorder(multibody::MultibodyProblem& problem, const std::filesystem::path& out_dir,
                                     const OutputSettings& output, const TimeGrid& time,
                                     const std::string& integrator)
    : problem_(problem),
      step_parts_(recorded_parts(problem.spec())),
      grid_parts_(recorded_parts(problem.spec(), false)),
      step_part_names_(problem.step_part_names(step_parts_)),
      step_units_more_(step_part_units(step_parts_, !step_part_names_.empty(), not_controlled_note(problem, integrator))),
      step_values_(step_part_names_.size()),
      events_(out_dir / "events.csv",
              "# units: t s; margin |det B| of the chart left (chart_switch), 1; drift_position and "
              "drift_velocity just before a projection; row_subset: body the joints whose rows moved, from/to "
              "the rows set aside before/after, margin the largest dependency coefficient; singular_pose: body "
              "the joints whose rows nearly lose rank, margin their conditioning relative to the start",
              "t,event,body,from,to,margin,drift_position,drift_velocity"),
      steps_(kStepTable, step_part_names_, false, output, out_dir, step_units_more_),
      trajectory_(open_csv_if(output.record != RecordMode::None, out_dir / "trajectory.csv",
                              units_comment(problem, grid_parts_, not_controlled_note(problem, integrator)),
                              "t," + join(problem.output_names(grid_parts_), ","))) {
  start_is_output_ = time.output_times.empty() || time.output_times.front() == time.start;
  const std::vector<std::string> names = problem.output_names(grid_parts_);
  row_.resize(names.size());
  energy_column_ = static_cast<int>(std::find(names.begin(), names.end(), "energy") - names.begin());
  has_work_ = problem.has_work();
}

void MultibodyRecorder::on_step(double t, double h, int order, const Eigen::VectorXd& y) {
  const auto [pos, vel] = problem_.drift(t, y.data());
  const double H = problem_.kinetic_energy(y.data()) + problem_.potential_energy(y.data());
  if (!have_H0_) H0_ = H, have_H0_ = true;
  if (has_work_) work_.add(t, problem_.work_rate(t, y.data()));
  const double err = (H - H0_ - work_.value()) / std::max(std::abs(H0_), 1.0);
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
    if (!step_values_.empty()) problem_.step_part_row(t, y.data(), step_parts_, step_values_.data());
    steps_.write({t, h, order, &o, {}, step_values_});
  }
}

void MultibodyRecorder::on_output(double t, const Eigen::VectorXd& y) {
  const bool row = trajectory_ && (seen_start_ || start_is_output_);
  seen_start_ = true;
  if (!row && have_H0_) return;
  problem_.output_row(t, y.data(), grid_parts_, row_.data());
  if (!have_H0_) {
    H0_ = row_[energy_column_], have_H0_ = true;
    if (has_work_) work_.add(t, problem_.work_rate(t, y.data()));
  }
  if (!row) return;
  fmt::memory_buffer line;
  fmt::format_to(std::back_inserter(line), "{}", t);
  for (double v : row_) fmt::format_to(std::back_inserter(line), ",{}", v);
  line.push_back('\n');
  trajectory_->file().write(line.data(), line.size());
}

std::string MultibodyRecorder::step_units() const {
  return columns::units_line(kStepTable).substr(2) + step_units_more_;
}

std::vector<std::string> MultibodyRecorder::step_columns() const {
  std::vector<std::string> c;
  for (const columns::Column& col : kStepColumns)
    if (col.kind != columns::Kind::Values) c.emplace_back(col.name);
  c.insert(c.end(), step_part_names_.begin(), step_part_names_.end());
  return c;
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
