// Running a scene's system on its integrator (see run_system.hpp): the
// MultibodyProblem through the IDA driver, or its ODE form through CVODE or
// ARKODE.
#include "run_system.hpp"

#include "rigidae/multibody/multibody_ode.hpp"
#include "rigidae/solver/integrators.hpp"
#include "rigidae/solver/ode_driver.hpp"

namespace rigidae {

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
  r.linear_solver = ode.kkt_solver();
  return r;
}

}  // namespace rigidae
