#include "rigidae/app/solve.hpp"

#include "run_system.hpp"
#include "counters_json.hpp"
#include "summary_common.hpp"
#include "machine_record.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <algorithm>
#include <variant>
#include <optional>
#include <nlohmann/json.hpp>

#include "rigidae/core/error.hpp"
#include "rigidae/model/one_body_system.hpp"
#include "rigidae/multibody/multibody_problem.hpp"
#include "rigidae/multibody/one_body_view.hpp"
#include "rigidae/io/checked_file.hpp"
#include "rigidae/record/columns.hpp"
#include "rigidae/record/run_columns.hpp"
#include "rigidae/settings/settings.hpp"
#include "rigidae/so3/rotation.hpp"
#include "rigidae/solver/version.hpp"

namespace rigidae {

namespace {

// A parameter as the scheme used it; a scheme that does not use it leaves
// the scene's setting (null when unset: the default is resolved by the
// scheme that uses it).
nlohmann::json used_or_set(const std::vector<SchemeParameter>& used, const std::string& name,
                           const std::optional<double>& set) {
  for (const auto& p : used)
    if (p.name == name) return p.value;
  return set ? nlohmann::json(*set) : nlohmann::json(nullptr);
}

// Every run setting of the table (rigidae/settings) at its dotted key, and
// the scheme's parameters as the scheme used them.
nlohmann::json configuration_json(const Scene& s, const std::vector<SchemeParameter>& used) {
  nlohmann::json j = {{"scene", s.source}, {"name", s.name}};
  for (const settings::Setting& setting : settings::all()) {
    if (setting.scene_key.empty() || !setting.get) continue;
    nlohmann::json value;
    std::visit([&](const auto& v) { value = v; }, setting.get(s));
    std::string pointer = "/" + std::string(setting.scene_key);
    std::replace(pointer.begin(), pointer.end(), '.', '/');
    j[nlohmann::json::json_pointer(pointer)] = value;
  }
  if (!s.time.output_times.empty()) j["output"]["times"] = s.time.output_times;
  j["formulation"]["baumgarte"]["a"] = used_or_set(used, "a", s.formulation.baumgarte.a);
  j["formulation"]["baumgarte"]["b"] = used_or_set(used, "b", s.formulation.baumgarte.b);
  j["formulation"]["projection"]["threshold"] = used_or_set(used, "threshold", s.formulation.projection.threshold);
  return j;
}

// JSON has no NaN: a measure not checked is null.
nlohmann::json number_or_null(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); }

nlohmann::json accuracy_check_json(const SolveOutcome& o, const RunMonitor& monitor) {
  const InvariantDrifts& d = o.drifts;
  return {{"tolerance", d.tolerance},
          {"energy", number_or_null(d.energy)},
          {"angular_momentum", number_or_null(d.angular_momentum)},
          {"vertical_angular_momentum", number_or_null(d.vertical_angular_momentum)},
          {"constraint_position", number_or_null(d.constraint_position)},
          {"constraint_velocity", number_or_null(d.constraint_velocity)},
          {"steps", monitor.steps()},
          {"definitions", monitor.definitions()}};
}

// summary.json: the keys every run shares (summary_common.hpp), then those
// its column set adds (record/run_columns.hpp).
nlohmann::json summary(const Scene& scene, const SolveOutcome& o, const RunColumns& columns, const RunMonitor& monitor) {
  const RunExtremes& x = o.extremes;
  const Observation& f = x.last;
  nlohmann::json switches = nlohmann::json::array();
  for (const auto& s : o.run.switches) switches.push_back({{"t", s.t}, {"from", s.from}, {"to", s.to}, {"margin", s.margin}});
  nlohmann::json j = common_summary_json(scene, o);
  j.update({
      {"configuration", configuration_json(scene, o.scheme_parameters)},
      {"chart_switches", switches},  // the first kSwitchesKept; events.csv has them all
      {"maxima",
       {{"drift_position", x.max_drift_position},
        {"drift_velocity", x.max_drift_velocity},
        {"abs_energy_rel_error", x.max_abs_energy_error}}},
      {"accuracy_check", accuracy_check_json(o, monitor)},
      {"final",
       {{"t", x.steps_recorded > 0 ? f.t : o.run.t_reached},
        {"drift_position", f.drift.position},
        {"drift_velocity", f.drift.velocity},
        {"energy", f.energy},
        {"energy_rel_error", f.energy_error},
        {"initial_energy", columns.initial_energy()}}},
      {"columns_units", columns.units_line(columns::kSteps).substr(2)},
  });
  columns.add_summary(j, x);
  add_provenance(j);  // "build" and "run"
  return j;
}

}  // namespace

std::string default_run_name(const Scene& scene) {
  return fmt::format("{}-{}-{}-{}", scene.name.empty() ? "scene" : scene.name,
                     to_string(scene.formulation.coordinates), to_string(scene.formulation.equations),
                     scene.formulation.scheme);
}

SolveOutcome solve_scene(const Scene& scene, const std::filesystem::path& out_dir) {
  return run_scene(scene, out_dir);
}

namespace {

// Singular poses passed (multibody/row_subset.cpp) and what the branch check
// (multibody/branch_check.cpp) saw there: a pose where the velocity jumped is
// a branch switch (warning branch_switch); a pose it could not check (the run
// ended inside its neighbourhood) keeps the warning that the branch may have
// changed; a pose passed with a continuous velocity is no warning (it stays
// in summary.json's row_subset.singular_poses and events.csv).
void add_singular_pose_warning(const multibody::MultibodyProblem& problem, SolveOutcome& o) {
  const multibody::SingularPose* switched = nullptr;
  const multibody::SingularPose* unchecked = nullptr;
  int n_switched = 0;
  for (const multibody::SingularPose& sp : problem.singular_poses()) {
    if (sp.branch_switch) {
      ++n_switched;
      if (!switched) switched = &sp;
    } else if (std::isnan(sp.velocity_jump) && !unchecked) {
      unchecked = &sp;
    }
  }
  if (switched) {
    AccuracyWarning w;
    w.quantity = "branch_switch";
    w.drift = switched->velocity_jump;
    w.limit = multibody::kBranchJump;
    w.message = fmt::format(
        "the run changed assembly branch at {} singular pose(s) (first at t = {:.9g} s, joints {}): its velocity "
        "jumped by {:.3g} of its size across the pose (limit {}), an impulse no applied force explains, so the "
        "motion after it follows another branch than the one it arrived on (events.csv: branch_switch); the "
        "bridge across singular poses ([mechanism] singular_poses = \"bridge\", the default, on IDA) keeps the "
        "branch, and so may a tighter tolerance or an index-3 scheme",
        n_switched, switched->t, switched->joints, switched->velocity_jump, multibody::kBranchJump);
    o.warnings.push_back(w);
  }
  if (unchecked) {
    AccuracyWarning w;
    w.quantity = "singular_pose";
    w.drift = unchecked->condition;
    w.message = fmt::format(
        "the run reached a singular pose at t = {:.9g} s (joints {}), where the constraint rows nearly lose rank "
        "and assembly branches cross, and did not leave its neighbourhood: the branch check (the velocity's "
        "continuity across the pose) could not be made, so the motion may have continued on another branch "
        "(events.csv lists it as singular_pose)",
        unchecked->t, unchecked->joints);
    o.warnings.push_back(w);
  }
}

// Every step, output point and event to two sinks (the recorder, then `second`).
class TeeSink final : public StepSink {
 public:
  TeeSink(StepSink& first, StepSink& second) : first_(first), second_(second) {}
  void on_step(double t, double h, int order, const Eigen::VectorXd& y) override {
    first_.on_step(t, h, order, y);
    second_.on_step(t, h, order, y);
  }
  void on_output(double t, const Eigen::VectorXd& y) override {
    first_.on_output(t, y);
    second_.on_output(t, y);
  }
  void on_event(const EventNote& note) override {
    first_.on_event(note);
    second_.on_event(note);
  }

 private:
  StepSink &first_, &second_;
};

}  // namespace

SolveOutcome run_scene(const Scene& scene, const std::filesystem::path& out_dir, MemoryRows* memory,
                       const std::function<StepSink*(const multibody::MultibodyProblem&)>& also) {
  // Every scene runs as a system of bodies (model/one_body_system.hpp for a
  // one-body scene): one model, one recorder, one accuracy check, one summary.
  const Scene system_scene = as_system(scene);
  check_multibody_integrator(system_scene);
  if (!out_dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(out_dir, ec);
    if (ec) throw InputError(fmt::format("{}: cannot create output folder: {}", out_dir.string(), ec.message()));
  }
  multibody::MultibodyProblem system(system_scene);
  const std::unique_ptr<RunColumns> columns = make_run_columns(system, system_scene);
  // What the scheme says of itself on the first body's representation (its
  // note, the parameters it used): the registry's scheme, which writes the rows.
  const std::unique_ptr<ConstraintScheme> scheme =
      make_scheme(system_scene.formulation.scheme, scheme_settings(system_scene));
  SolveOutcome o;
  o.out_dir = out_dir;
  o.representation = columns->one_body() ? columns->one_body()->representation().name()
                                         : to_string(scene.formulation.coordinates) + "/" + to_string(scene.formulation.equations);
  o.scheme = scheme->name();
  o.note = columns->note(scheme->note(*system.bodies().front().rep));
  if (const OneBodyView* one = columns->one_body()) o.multiplier_names = one->multiplier_names();
  o.unknowns = system.size();
  // Drift is measured on every constraint: the rows the DAE carries and the
  // coordinates' own (an Euler-form quaternion on an ODE integrator keeps
  // |q| = 1 by projection, with no row in the system).
  o.constrained = std::any_of(system.blocks().begin(), system.blocks().end(),
                              [](const multibody::ConstraintBlock& b) { return b.nr > 0; }) ||
                  std::any_of(system.bodies().begin(), system.bodies().end(), [](const multibody::BodyModel& b) {
                    return b.rep != nullptr && !b.rep->constraint_names().empty();
                  });
  o.scheme_parameters = scheme->parameters();
  o.multipliers_error =
      multiplier_error_control(scene.solver.integrator, system.suppress_algebraic_error_test(), o.scheme);

  RunRecorder recorder(*columns, scene.output, scene.time, out_dir, memory);
  StepSink* extra = also ? also(system) : nullptr;
  std::optional<TeeSink> tee;
  if (extra) tee.emplace(recorder, *extra);
  const std::unique_ptr<RunMonitor> monitor =
      make_run_monitor(system, system_scene, recorder, tee ? static_cast<StepSink&>(*tee) : recorder);
  const auto t0 = std::chrono::steady_clock::now();
  std::string lost;  // the first output file that could not be written completely
  try {
    o.run = run_multibody(system, system_scene, *monitor);
  } catch (const SolverError& e) {
    o.run.status = RunStatus::Failed;
    o.run.message = e.what();
  } catch (const OutputError& e) {  // a step or grid file refused a write (a full disk): kept, and said
    lost = e.what();
  }
  o.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  try {
    recorder.close();
  } catch (const OutputError& e) {
    if (lost.empty()) lost = e.what();
  }
  o.extremes = recorder.extremes();
  o.drifts = monitor->drifts();
  o.warnings = monitor->warnings();
  add_singular_pose_warning(system, o);
  o.start_warnings = system.warnings();  // printed by the command (solve: each run; compare: once)
  o.final_report = columns->final_report(o.extremes, o.run.t_reached);
  if (!lost.empty()) {
    // Results that did not reach the disk are no success, however the solver fared.
    o.output_lost = true;
    o.run.status = RunStatus::Failed;
    o.run.t_reached = o.extremes.last.t;
    o.run.message = fmt::format("output lost: {}; the run stopped there (last recorded t = {:.9g} s, {} steps "
                                "recorded) and what was written is kept",
                                lost, o.extremes.last.t, o.extremes.steps_recorded);
  }
  // A path from the command line need not be UTF-8; JSON must be: invalid bytes become U+FFFD.
  o.summary = summary(scene, o, *columns, *monitor).dump(2, ' ', false, nlohmann::json::error_handler_t::replace);
  if (!out_dir.empty()) {
    try {
      write_file_atomically(out_dir / "summary.json", o.summary + '\n');
    } catch (const OutputError& e) {
      // On a full disk the summary fails after the step file did: the file that
      // failed first (the CSV) is the cause and is named first.
      if (o.output_lost) throw OutputError(fmt::format("{}; summary.json could not be written either: {}",
                                                       o.run.message, e.what()));
      throw;
    }
  }
  if (o.output_lost) throw OutputError(o.run.message);
  return o;
}

}  // namespace rigidae
