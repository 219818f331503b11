// One run of a multibody scene: the MultibodyProblem through the IDA
// driver, streamed by MultibodyRecorder behind the accuracy check
// (app/multibody_accuracy_check.hpp), and summary.json.
#include "solve_multibody.hpp"
#include "counters_json.hpp"
#include "machine_record.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <fstream>

#include "rigidae/app/multibody_accuracy_check.hpp"
#include "rigidae/io/checked_file.hpp"
#include "rigidae/core/error.hpp"
#include "rigidae/multibody/multibody_problem.hpp"
#include "rigidae/record/multibody_recorder.hpp"

namespace rigidae {

namespace {

nlohmann::json number_or_null(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); }

}  // namespace

void check_multibody_integrator(const Scene& scene) {
  if (scene.solver.integrator != "ida")
    throw InputError(fmt::format("{}: error: solver.integrator = \"{}\": a scene with bodies and joints "
                                 "(schema_version = 2) runs on ida only (valid: ida; the multibody ODE form for "
                                 "cvode-adams, cvode-bdf and arkode-erk is not built yet)",
                                 scene.source, scene.solver.integrator));
}

SolveOutcome solve_multibody_scene(const Scene& scene, const std::filesystem::path& out_dir) {
  check_multibody_integrator(scene);
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec) throw InputError(fmt::format("{}: cannot create output folder: {}", out_dir.string(), ec.message()));
  multibody::MultibodyProblem problem(scene);
  SolveOutcome o;
  o.out_dir = out_dir;
  o.representation = to_string(scene.formulation.coordinates) + "/" + to_string(scene.formulation.equations);
  o.scheme = problem.scheme().name;
  o.note = fmt::format("{} bodies, {} joints, {} unknowns", problem.bodies().size(), scene.multibody->joints.size(),
                       problem.size());
  MultibodyRecorder recorder(problem, out_dir, scene.output, scene.time);
  MultibodyInvariantMonitor monitor(problem, scene, &recorder);
  const auto t0 = std::chrono::steady_clock::now();
  try {
    o.run = integrate(problem, scene.solver, scene.time, monitor);
  } catch (const SolverError& e) {
    o.run.status = RunStatus::Failed;
    o.run.message = e.what();
  }
  o.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  recorder.close();
  o.extremes.steps_recorded = recorder.steps_recorded();
  o.extremes.max_drift_position = recorder.max_drift_position();
  o.extremes.max_drift_velocity = recorder.max_drift_velocity();
  o.extremes.max_abs_energy_error = recorder.max_abs_energy_rel_error();
  o.drifts = monitor.drifts();
  o.warnings = monitor.warnings();

  const IdaCounters& c = o.run.counters;
  nlohmann::json j = {
      {"scene", scene.name},
      {"source", scene.source},
      {"schema_version", 2},
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
      {"coordinates", to_string(scene.formulation.coordinates)},
      {"equations", to_string(scene.formulation.equations)},
      {"scheme", o.scheme},
      {"bodies", problem.bodies().size()},
      {"joints", scene.multibody->joints.size()},
      {"unknowns", problem.size()},
      {"nonzeros", problem.sparsity().nnz()},
      {"factor_nonzeros", o.run.factor_nonzeros},
      {"status", to_string(o.run.status)},
      {"message", o.run.message},
      {"t_reached", o.run.t_reached},
      {"wall_seconds", o.wall_seconds},
      {"rtol", scene.solver.rtol},
      {"atol", scene.solver.atol},
      {"jacobian", scene.solver.jacobian},
      {"linear_solver", o.run.linear_solver},  // the one used ("auto" resolved by size)
      {"linear_solver_setting", scene.solver.linear_solver},
      {"start_warnings", problem.warnings()},
      {"warnings", warnings_json(o.warnings)},
      {"accuracy_check",
       {{"tolerance", o.drifts.tolerance},
        {"energy", number_or_null(o.drifts.energy)},
        {"constraint_position", number_or_null(o.drifts.constraint_position)},
        {"constraint_velocity", number_or_null(o.drifts.constraint_velocity)},
        {"steps", monitor.steps()},
        {"definitions", "maxima over the steps; see include/rigidae/app/multibody_accuracy_check.hpp"}}},
      {"counters", counters_json(c)},
      {"maxima",
       {{"drift_position", o.extremes.max_drift_position},
        {"drift_velocity", o.extremes.max_drift_velocity},
        {"abs_energy_rel_error", o.extremes.max_abs_energy_error}}},
      {"final", {{"energy", recorder.last_energy()}, {"initial_energy", recorder.initial_energy()}}},
  };
  add_provenance(j);  // "build" and "run"
  o.start_warnings = problem.warnings();  // printed by the command (solve: each run; compare: once)
  write_file_atomically(out_dir / "summary.json", j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
  return o;
}

}  // namespace rigidae
