// Dispatch on solver.integrator (see run_integrator.hpp).
#include "rigidae/app/run_integrator.hpp"

#include "rigidae/dae/single_body_ode.hpp"
#include "rigidae/dae/single_body_problem.hpp"
#include "rigidae/solver/integrators.hpp"
#include "rigidae/solver/ode_driver.hpp"

namespace rigidae {

RunResult run_integrator(DaeSystem& dae, const Scene& scene, StepSink& sink) {
  const IntegratorInfo& info = find_integrator(scene.solver.integrator, scene.source);
  if (!info.is_ode) {
    SingleBodyProblem problem(dae, scene.formulation.euler, scene.R0_WB, scene.omega0_B, scene.source);
    return integrate(problem, scene.solver, scene.time, sink);
  }
  check_integrator_scheme(scene.solver.integrator, scene.formulation.scheme, scene.source);
  SingleBodyOde ode(dae, scene);
  return integrate_ode(ode, scene.solver, scene.time, {scene.solver.integrator, scene.solver.erk_method, dae.scheme().projection()},
                       sink);
}

}  // namespace rigidae
