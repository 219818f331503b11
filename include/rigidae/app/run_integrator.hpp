#pragma once
// Runs a scene's body with the integrator its settings name
// (solver.integrator): IDA on the DAE, or CVODE / ARKODE on the ODE form
// (dae/single_body_ode.hpp) of the same DaeSystem, whose layout the
// recorded states keep.
#include "rigidae/dae/dae_system.hpp"
#include "rigidae/model/scene.hpp"
#include "rigidae/solver/ida_driver.hpp"

namespace rigidae {

RunResult run_integrator(DaeSystem& dae, const Scene& scene, StepSink& sink);

}  // namespace rigidae
