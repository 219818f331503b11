#pragma once
// Runs a scene's body with the integrator its settings name
// (solver.integrator): IDA on the DAE (dae/single_body_problem.hpp), or
// CVODE / ARKODE on the ODE form (dae/single_body_ode.hpp) of the same
// DaeSystem, whose layout the recorded states keep. Built before the run so
// that a recorder can follow the chart the state is written in.
#include <optional>

#include "rigidae/dae/chart_state.hpp"
#include "rigidae/dae/dae_system.hpp"
#include "rigidae/dae/single_body_ode.hpp"
#include "rigidae/dae/single_body_problem.hpp"
#include "rigidae/model/scene.hpp"
#include "rigidae/solver/ida_driver.hpp"

namespace rigidae {

class IntegratorRun {
 public:
  // InputError for an integrator/scheme pair the table does not run.
  IntegratorRun(const DaeSystem& dae, const Scene& scene);
  IntegratorRun(const IntegratorRun&) = delete;
  IntegratorRun& operator=(const IntegratorRun&) = delete;

  const ChartState& chart_state() const;
  RunResult run(StepSink& sink);

 private:
  const DaeSystem& dae_;
  const Scene& scene_;
  std::optional<SingleBodyProblem> dae_problem_;
  std::optional<SingleBodyOde> ode_;
};

}  // namespace rigidae
