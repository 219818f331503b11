// Dispatch on solver.integrator (see run_integrator.hpp).
#include "rigidae/app/run_integrator.hpp"

#include "rigidae/dae/single_body_ode.hpp"
#include "rigidae/solver/integrators.hpp"
#include "rigidae/solver/ode_driver.hpp"

namespace rigidae {

RunResult run_integrator(DaeSystem& dae, const Scene& scene, StepSink& sink) {
  const IntegratorInfo& info = find_integrator(scene.solver.integrator, scene.source);
  if (!info.is_ode) return integrate(dae, scene, sink);
  check_integrator_scheme(scene.solver.integrator, scene.formulation.scheme, scene.source);
  SingleBodyOde ode(dae, scene);
  return integrate_ode(ode, scene, {scene.solver.integrator, scene.solver.erk_method, dae.scheme().projection()},
                       sink);
}

}  // namespace rigidae
