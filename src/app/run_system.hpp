#pragma once
// Running a scene's system on its integrator (internal header of app/).
#include "rigidae/app/solve.hpp"
#include "rigidae/multibody/multibody_problem.hpp"
#include "rigidae/solver/ida_driver.hpp"

namespace rigidae {

// The integrator a scene may name: ida (the DAE) with any scheme,
// or cvode-adams, cvode-bdf, arkode-erk (the ODE form, multibody_ode.hpp)
// with the schemes they run (index1, projection). InputError naming the file
// and the valid values otherwise.
void check_multibody_integrator(const Scene& scene);

// Runs `problem` (assembled from `scene`) on the scene's integrator: IDA on
// the DAE, or CVODE/ARKODE on its ODE form; every accepted step and output
// point to `sink` in the DAE layout. SolverError is the caller's.
RunResult run_multibody(multibody::MultibodyProblem& problem, const Scene& scene, StepSink& sink);

}  // namespace rigidae
