// One run of a multibody scene: the MultibodyProblem through the IDA
// driver, streamed by MultibodyRecorder, and summary.json.
#include "solve_multibody.hpp"
#include "counters_json.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <fstream>

#include "rigidae/io/checked_file.hpp"
#include "rigidae/core/error.hpp"
#include "rigidae/multibody/multibody_problem.hpp"
#include "rigidae/record/multibody_recorder.hpp"

namespace rigidae {

SolveOutcome solve_multibody_scene(const Scene& scene, const std::filesystem::path& out_dir) {
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
  const auto t0 = std::chrono::steady_clock::now();
  try {
    o.run = integrate(problem, scene.solver, scene.time, recorder);
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

  const IdaCounters& c = o.run.counters;
  nlohmann::json j = {
      {"scene", scene.name},
      {"source", scene.source},
      {"schema_version", 2},
      {"coordinates", to_string(scene.formulation.coordinates)},
      {"equations", to_string(scene.formulation.equations)},
      {"scheme", o.scheme},
      {"bodies", problem.bodies().size()},
      {"joints", scene.multibody->joints.size()},
      {"unknowns", problem.size()},
      {"nonzeros", problem.sparsity().nnz()},
      {"status", to_string(o.run.status)},
      {"message", o.run.message},
      {"t_reached", o.run.t_reached},
      {"wall_seconds", o.wall_seconds},
      {"rtol", scene.solver.rtol},
      {"atol", scene.solver.atol},
      {"jacobian", scene.solver.jacobian},
      {"linear_solver", o.run.linear_solver},  // the one used ("auto" resolved by size)
      {"linear_solver_setting", scene.solver.linear_solver},
      {"warnings", problem.warnings()},
      {"counters", counters_json(c)},
      {"maxima",
       {{"drift_position", o.extremes.max_drift_position},
        {"drift_velocity", o.extremes.max_drift_velocity},
        {"abs_energy_rel_error", o.extremes.max_abs_energy_error}}},
      {"final", {{"energy", recorder.last_energy()}, {"initial_energy", recorder.initial_energy()}}},
  };
  for (const std::string& w : problem.warnings()) fmt::print(stderr, "rigidae: warning: {}\n", w);
  write_file_atomically(out_dir / "summary.json", j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
  return o;
}

}  // namespace rigidae
