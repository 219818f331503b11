// One run of a multibody scene: the MultibodyProblem through the IDA
// driver or its ODE form through CVODE/ARKODE, streamed by MultibodyRecorder behind the accuracy check
// (app/multibody_accuracy_check.hpp), and summary.json.
#include "solve_multibody.hpp"
#include "counters_json.hpp"
#include "summary_common.hpp"
#include "machine_record.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <optional>

#include "rigidae/app/multibody_accuracy_check.hpp"
#include "rigidae/io/checked_file.hpp"
#include "rigidae/core/error.hpp"
#include "rigidae/multibody/multibody_ode.hpp"
#include "rigidae/multibody/multibody_problem.hpp"
#include "rigidae/solver/integrators.hpp"
#include "rigidae/solver/ode_driver.hpp"
#include "rigidae/record/multibody_recorder.hpp"

namespace rigidae {

namespace {

nlohmann::json number_or_null(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); }

// Which bodies and joints have columns in the step file and trajectory.csv
// (model/recorded_parts.hpp), and why when the default left them out.
nlohmann::json recorded_parts_json(const multibody::MultibodyProblem& p, const MultibodyRecorder& r) {
  const auto names = [&](const RecordedParts& parts) {
    nlohmann::json b = nlohmann::json::array(), j = nlohmann::json::array();
    for (int i : parts.bodies) b.push_back(p.bodies()[i].name);
    for (int i : parts.joints) j.push_back(p.spec().joints[i].name);
    return nlohmann::json{{"bodies", b}, {"joints", j}};
  };
  const RecordedParts& s = r.step_parts();
  nlohmann::json out = {{"steps", names(s)},
                        {"trajectory", names(r.grid_parts())},
                        {"chosen_by_scene", {{"bodies", !s.bodies_by_default}, {"joints", !s.joints_by_default}}}};
  if (s.cut_by_size)
    out["note"] = fmt::format(
        "{} joints (more than {}): the step file holds only the global columns for the parts the scene does not "
        "name; choose them with [output] bodies = [...] and joints = [...] (or \"all\")",
        p.spec().joints.size(), kAllPartsUpToJoints);
  return out;
}

// Every step, output point and event to two sinks (the files, then `also`).
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
  bool needs_every_output() const override { return first_.needs_every_output() || second_.needs_every_output(); }

 private:
  StepSink &first_, &second_;
};

// What a run reports of its formulation before it starts.
SolveOutcome outcome_of(const multibody::MultibodyProblem& problem, const Scene& scene) {
  SolveOutcome o;
  o.representation = to_string(scene.formulation.coordinates) + "/" + to_string(scene.formulation.equations);
  o.scheme = problem.scheme().name;
  o.unknowns = problem.size();
  o.multipliers_error =
      multiplier_error_control(scene.solver.integrator, problem.suppress_algebraic_error_test(), o.scheme);
  return o;
}

// Singular poses passed (multibody/row_subset.cpp): the branch may have changed.
void add_singular_pose_warning(const multibody::MultibodyProblem& problem, SolveOutcome& o) {
  if (!problem.singular_poses().empty()) {
    const multibody::SingularPose& first = problem.singular_poses().front();
    AccuracyWarning w;
    w.quantity = "singular_pose";
    w.drift = first.condition;
    w.message = fmt::format(
        "the run passed {} singular pose(s) (first at t = {:.9g} s, joints {}), where the constraint rows nearly lose rank "
        "and assembly branches cross; the motion may have continued on another branch "
        "(rigidae has no general branch check: compare with a closed form or the mechanism's known branch; "
        "events.csv lists them as singular_pose)",
        problem.singular_poses().size(), first.t, first.joints);
    o.warnings.push_back(w);
  }

}

}  // namespace

SolveOutcome solve_multibody_with(const Scene& scene, const std::filesystem::path& out_dir,
                                  const MultibodySinkAttach& also) {
  return solve_multibody_scene(scene, out_dir, also);
}

SolveOutcome solve_multibody_in_memory(const Scene& scene, const MultibodySinkAttach& also) {
  check_multibody_integrator(scene);
  multibody::MultibodyProblem problem(scene);
  SolveOutcome o = outcome_of(problem, scene);
  StepSink* sink = also(problem);
  MultibodyInvariantMonitor monitor(problem, scene, sink);
  const auto t0 = std::chrono::steady_clock::now();
  try {
    o.run = run_multibody(problem, scene, monitor);
  } catch (const SolverError& e) {
    o.run.status = RunStatus::Failed;
    o.run.message = e.what();
  }
  o.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  o.drifts = monitor.drifts();
  o.warnings = monitor.warnings();
  add_singular_pose_warning(problem, o);
  o.start_warnings = problem.warnings();
  return o;
}

void check_multibody_integrator(const Scene& scene) {
  if (find_integrator(scene.solver.integrator, scene.source).is_ode)
    check_integrator_scheme(scene.solver.integrator, scene.formulation.scheme, scene.source);
}

RunResult run_multibody(multibody::MultibodyProblem& problem, const Scene& scene, StepSink& sink) {
  if (!find_integrator(scene.solver.integrator, scene.source).is_ode)
    return integrate(problem, scene.solver, scene.time, sink);
  // The KKT solve's LU: the DAE's rule (solver.linear_solver, "auto" by the DAE's size).
  const bool sparse = scene.solver.linear_solver == "klu" ||
                      (scene.solver.linear_solver == "auto" && problem.size() >= kKluFromUnknowns);
  multibody::MultibodyOde ode(problem, sparse, scene.source);
  const bool projection = problem.scheme().projection;
  RunResult r = integrate_ode(ode, scene.solver, scene.time,
                              {scene.solver.integrator, scene.solver.erk_method,
                               {projection, scene.formulation.projection.every_step, projection_threshold(scene)}},
                              sink);
  r.linear_solver = sparse ? "klu" : "dense";
  return r;
}

SolveOutcome solve_multibody_scene(const Scene& scene, const std::filesystem::path& out_dir,
                                   const MultibodySinkAttach& also) {
  check_multibody_integrator(scene);
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec) throw InputError(fmt::format("{}: cannot create output folder: {}", out_dir.string(), ec.message()));
  multibody::MultibodyProblem problem(scene);
  SolveOutcome o = outcome_of(problem, scene);
  o.out_dir = out_dir;
  o.note = fmt::format("{} bodies, {} joints, {} unknowns", problem.bodies().size(), scene.multibody->joints.size(),
                       problem.size());
  MultibodyRecorder recorder(problem, out_dir, scene.output, scene.time, scene.solver.integrator);
  StepSink* extra = also ? also(problem) : nullptr;
  std::optional<TeeSink> tee;
  if (extra) tee.emplace(recorder, *extra);
  MultibodyInvariantMonitor monitor(problem, scene, tee ? static_cast<StepSink*>(&*tee) : &recorder);
  const auto t0 = std::chrono::steady_clock::now();
  try {
    o.run = run_multibody(problem, scene, monitor);
  } catch (const SolverError& e) {
    o.run.status = RunStatus::Failed;
    o.run.message = e.what();
  } catch (const OutputError& e) {  // a step or grid file refused a write (a full disk): kept, and said
    o.output_lost = true;
    o.run.status = RunStatus::Failed;
    o.run.message = fmt::format("output lost: {}; the run stopped there, after {} steps recorded, and what was "
                                "written is kept",
                                e.what(), recorder.steps_recorded());
  }
  o.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  try {
    recorder.close();
  } catch (const OutputError& e) {
    if (!o.output_lost) o.run.message = fmt::format("output lost: {}; what was written is kept", e.what());
    o.output_lost = true;
    o.run.status = RunStatus::Failed;
  }
  o.extremes.steps_recorded = recorder.steps_recorded();
  o.extremes.max_drift_position = recorder.max_drift_position();
  o.extremes.max_drift_velocity = recorder.max_drift_velocity();
  o.extremes.max_abs_energy_error = recorder.max_abs_energy_rel_error();
  o.drifts = monitor.drifts();
  o.warnings = monitor.warnings();
  add_singular_pose_warning(problem, o);

  // The keys both summaries share (summary_common.hpp), then a mechanism's own.
  nlohmann::json j = common_summary_json(scene, o);
  j.update({
      // The run's settings under the keys single-body summaries use (tools/plot_compare.py reads them).
      {"configuration",
       {{"name", scene.name},
        {"scene", scene.source},
        {"formulation",
         {{"coordinates", to_string(scene.formulation.coordinates)},
          {"equations", to_string(scene.formulation.equations)},
          {"scheme", o.scheme}}},
        {"solver", {{"rtol", scene.solver.rtol}, {"atol", scene.solver.atol}, {"integrator", scene.solver.integrator}}},
        {"time", {{"start", scene.time.start}, {"end", scene.time.end}, {"output_step", scene.time.output_step}}}}},
      {"bodies", problem.bodies().size()},
      {"joints", scene.multibody->joints.size()},
      {"nonzeros", problem.sparsity().nnz()},
      {"start_warnings", problem.warnings()},
      {"recorded_parts", recorded_parts_json(problem, recorder)},
      {"accuracy_check",
       {{"tolerance", o.drifts.tolerance},
        {"energy", number_or_null(o.drifts.energy)},
        {"constraint_position", number_or_null(o.drifts.constraint_position)},
        {"constraint_velocity", number_or_null(o.drifts.constraint_velocity)},
        {"steps", monitor.steps()},
        {"definitions", "maxima over the steps; see include/rigidae/app/multibody_accuracy_check.hpp"}}},
      {"maxima",
       {{"drift_position", o.extremes.max_drift_position},
        {"drift_velocity", o.extremes.max_drift_velocity},
        {"abs_energy_rel_error", o.extremes.max_abs_energy_error}}},
      {"final",
       {{"t", o.run.t_reached},
        {"energy", recorder.last_energy()},
        {"energy_rel_error", (recorder.last_energy() - recorder.initial_energy()) /
                                 std::max(std::abs(recorder.initial_energy()), 1.0)},
        {"initial_energy", recorder.initial_energy()}}},
      {"columns_units", recorder.step_units()},
  });
  // Redundant constraints and mobility (multibody_problem.hpp, "Redundant
  // constraints"): one block, so that renames elsewhere merge cleanly.
  {
    const multibody::RedundancyReport& rr = problem.redundancy();
    nlohmann::json rows = nlohmann::json::array(), joints = nlohmann::json::array();
    for (int k = 0; k < static_cast<int>(rr.dropped.size()); ++k)
      rows.push_back({{"joint", scene.multibody->joints[rr.dropped[k].joint].name},
                      {"row", rr.dropped[k].row},
                      {"source", problem.dropped_row_source(k)}});
    for (int jt : rr.indeterminate_joints) joints.push_back(scene.multibody->joints[jt].name);
    const auto& expected = scene.multibody->expected_dof;
    j["mobility"] = {{"rank_dof", rr.rank_dof},
                     {"gruebler_dof", rr.gruebler_dof},
                     {"redundant_rows", rr.dropped.size()},
                     {"rank", rr.rank},
                     {"rows", rr.rows},
                     {"velocities", rr.velocities},
                     {"expected_dof", expected ? nlohmann::json(*expected) : nlohmann::json(nullptr)},
                     {"drivers", scene.multibody->drivers.size()},
                     {"singular_start", rr.singular_start}};
    j["redundant_rows"] = rows;
    j["reactions_determined"] = rr.indeterminate_joints.empty();
    j["reactions_indeterminate_joints"] = joints;
    // multibody/minimum_norm_reactions.cpp: what the force and torque columns hold.
    j["reactions_method"] =
        rr.indeterminate_joints.empty()
            ? "multipliers of the joints' rows (determined by the constraints)"
            : fmt::format("minimum-norm split over the rows of the joints in the dependency (kept and set aside), "
                          "torques weighed divided by L = {:.6g} m; determined joints: their multipliers; the lambda "
                          "columns of steps.csv are the kept rows' multipliers (a particular solution)",
                          rr.length_scale);
    // The subset during the run (multibody/row_subset.cpp).
    nlohmann::json now = nlohmann::json::array(), poses = nlohmann::json::array();
    for (const multibody::RedundantRow& d : problem.set_aside())
      now.push_back({{"joint", scene.multibody->joints[d.joint].name}, {"row", d.row}});
    for (const multibody::SingularPose& sp : problem.singular_poses())
      poses.push_back({{"t", sp.t}, {"joints", sp.joints}, {"condition", sp.condition}});
    j["row_subset"] = {{"changes", problem.subset_changes()},
                       {"largest_dependency", problem.largest_dependency()},
                       {"largest_amplification", problem.largest_amplification()},
                       {"set_aside_at_end", now},
                       {"singular_poses", poses}};
    if (!rr.mobility_warning.empty())
      j["warnings"].push_back({{"quantity", "mobility"}, {"message", rr.mobility_warning}});
    o.note += fmt::format("; mobility {} (rank), {} (Gruebler-Kutzbach)", rr.rank_dof, rr.gruebler_dof);
    if (!scene.multibody->drivers.empty())
      o.note += fmt::format(", {} driver{} counted as constraints", scene.multibody->drivers.size(),
                            scene.multibody->drivers.size() == 1 ? "" : "s");
    if (!rr.dropped.empty()) o.note += fmt::format(", {} redundant rows set aside", rr.dropped.size());
    j["note"] = o.note;
  }
  // An assembled start (multibody/assembly.hpp): what was held, the misses
  // before and after, and how far each other body was moved.
  if (const multibody::AssemblyReport& ar = problem.assembly(); ar.done) {
    nlohmann::json held = nlohmann::json::array(), moved = nlohmann::json::array();
    for (int b : ar.held) held.push_back(scene.multibody->bodies[b].name);
    for (const multibody::AssembledBody& a : ar.bodies)
      moved.push_back({{"body", scene.multibody->bodies[a.body].name},
                       {"moved_m", a.moved_m},
                       {"turned_rad", a.turned_rad},
                       {"velocity_change_m_s", a.velocity_change},
                       {"angular_velocity_change_rad_s", a.angular_velocity_change}});
    j["assembly"] = {{"held", held},
                     {"iterations", ar.iterations},
                     {"initial_miss", ar.initial_miss},
                     {"final_miss", ar.final_miss},
                     {"initial_velocity_miss", ar.initial_velocity_miss},
                     {"final_velocity_miss", ar.final_velocity_miss},
                     {"bodies", moved}};
    o.note += "; " + ar.note;
    j["note"] = o.note;
  }
  // URDF limits (model/multibody_spec.hpp, JointLimits): data, never enforced.
  {
    nlohmann::json limits = nlohmann::json::array();
    const auto opt = [](const std::optional<double>& x) { return x ? nlohmann::json(*x) : nlohmann::json(nullptr); };
    for (const JointSpec& js : scene.multibody->joints)
      if (js.limits)
        limits.push_back({{"joint", js.name},
                          {"lower", opt(js.limits->lower)},
                          {"upper", opt(js.limits->upper)},
                          {"effort", opt(js.limits->effort)},
                          {"velocity", opt(js.limits->velocity)}});
    if (!limits.empty())
      j["joint_limits"] = {{"enforced", false},
                           {"note", "kept as data from the URDF: rigidae has no joint stops, so joints may pass them"},
                           {"joints", limits}};
  }
  add_provenance(j);  // "build" and "run"
  o.start_warnings = problem.warnings();  // printed by the command (solve: each run; compare: once)
  try {
    write_file_atomically(out_dir / "summary.json", j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
  } catch (const OutputError& e) {
    if (o.output_lost)  // the file that failed first leads
      throw OutputError(fmt::format("{}; summary.json could not be written either: {}", o.run.message, e.what()));
    throw;
  }
  if (o.output_lost) throw OutputError(o.run.message);
  return o;
}

}  // namespace rigidae
