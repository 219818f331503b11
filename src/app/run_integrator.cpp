// Dispatch on solver.integrator (see run_integrator.hpp).
#include "rigidae/app/run_integrator.hpp"

#include "rigidae/solver/integrators.hpp"
#include "rigidae/solver/ode_driver.hpp"

namespace rigidae {

IntegratorRun::IntegratorRun(const DaeSystem& dae, const Scene& scene) : dae_(dae), scene_(scene) {
  if (!find_integrator(scene.solver.integrator, scene.source).is_ode) {
    dae_problem_.emplace(dae, scene.formulation.euler, scene.R0_WB, scene.omega0_B, scene.source);
    return;
  }
  check_integrator_scheme(scene.solver.integrator, scene.formulation.scheme, scene.source);
  ode_.emplace(dae, scene);
}

const ChartState& IntegratorRun::chart_state() const {
  if (dae_problem_) return *dae_problem_;
  return *ode_;
}

RunResult IntegratorRun::run(StepSink& sink) {
  if (dae_problem_) return integrate(*dae_problem_, scene_.solver, scene_.time, sink);
  const ProjectionPolicy p = dae_.scheme().projection();
  return integrate_ode(*ode_, scene_.solver, scene_.time,
                       {scene_.solver.integrator, scene_.solver.erk_method, {p.enabled, p.every_step, p.threshold}},
                       sink);
}

}  // namespace rigidae
