#pragma once
// The keys every summary.json carries, one body or many, under one name
// each: what was run (scene, formulation, integrator and tolerances), how it
// ended, what it cost, and how far its multipliers can be trusted. The one
// summary writer (solve.cpp) starts from this object, adds the keys of every
// run and then those of its column set (record/run_columns.hpp); a key
// that does not apply is absent, never renamed
// (tests/unit/test_summary_schema.cpp checks both kinds of run).
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <Eigen/Core>

#include "counters_json.hpp"
#include "rigidae/app/solve.hpp"
#include "rigidae/model/scene.hpp"
#include "rigidae/solver/version.hpp"

namespace rigidae {

inline nlohmann::json common_summary_json(const Scene& scene, const SolveOutcome& o) {
  nlohmann::json j = {
      {"units", "SI: s, m, rad, rad/s, N, N m, J, kg m^2/s; quaternions scalar first, R_WB body to space"},
      {"scene", scene.name},
      {"source", scene.source},
      {"versions",
       {{"rigidae", RIGIDAE_VERSION},
        {"sundials", sundials_version()},
        {"eigen", fmt::format("{}.{}.{}", EIGEN_WORLD_VERSION, EIGEN_MAJOR_VERSION, EIGEN_MINOR_VERSION)}}},
      {"representation", o.representation},
      {"coordinates", to_string(scene.formulation.coordinates)},
      {"equations", to_string(scene.formulation.equations)},
      {"scheme", o.scheme},
      {"note", o.note},
      {"unknowns", o.unknowns},
      {"integrator", scene.solver.integrator},
      // "named" (scene file, command line, compare or study), why the default rule chose it, or "set in
      // code" for a Scene no loader resolved (settings/default_integrator.hpp).
      {"integrator_choice", scene.solver.integrator_choice.empty() ? "set in code" : scene.solver.integrator_choice},
      {"rtol", scene.solver.rtol},
      {"atol", scene.solver.atol},
      {"jacobian", scene.solver.jacobian},
      {"linear_solver", o.run.linear_solver.empty() ? "none" : o.run.linear_solver},  // the one Newton used
      {"linear_solver_setting", scene.solver.linear_solver},
      {"status", to_string(o.run.status)},
      {"message", o.run.message},
      {"t_reached", o.run.t_reached},
      {"wall_time_s", o.wall_seconds},
      {"initial_residual_max_abs", o.run.initial_residual},
      {"factor_nonzeros", o.run.factor_nonzeros},
      {"counters", counters_json(o.run.counters)},
      {"chart_switch_count", o.run.switch_count},
      {"warnings", warnings_json(o.warnings)},
      {"multipliers_error_controlled", o.multipliers_error.controlled},
      {"multipliers_error_note", o.multipliers_error.note},
  };
  // The scene file's schema_version, as its loader recorded it; absent for a
  // scene built in code, which came from no file.
  if (scene.schema_version > 0) j["schema_version"] = scene.schema_version;
  return j;
}

}  // namespace rigidae
