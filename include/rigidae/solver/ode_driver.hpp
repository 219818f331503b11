#pragma once
// Integrates an OdeProblem with SUNDIALS' CVODE (Adams-Moulton orders 1-12
// with fixed-point iteration, or BDF orders 1-5 with Newton and rigidae's
// dense LU) or ARKODE's explicit Runge-Kutta (ERKStep), one internal step at
// a time, with the IDA driver's recording: every accepted step and every
// output-grid point go to the same StepSink, chart switches and projections
// too, and the counters come back in the same RunResult.
//
// Projection (ProjectionPolicy, the projection scheme's): CVODE-BDF through
// CVodeSetProjFn (after each step's nonlinear solve, with the error
// estimate projected too); ARKODE after each accepted step
// (ERKStepSetPostprocessStepFn); CVODE-Adams only by a restart
// (CVodeReInit), because CVODE 6.4 supports CVodeSetProjFn with BDF only and
// a restart drops Adams to order 1: it projects only when the drift passes
// the threshold, never every step.
#include <string>

#include "rigidae/solver/ida_driver.hpp"
#include "rigidae/solver/ode_problem.hpp"

namespace rigidae {

// When to project (the projection scheme's ProjectionPolicy, copied by the
// caller: solver/ sees no scheme).
struct OdeProjection {
  bool enabled = false;
  bool every_step = false;  // after every accepted step, or only when the drift passes threshold
  double threshold = 0.0;   // on the position and velocity drifts
};

struct OdeMethod {
  std::string integrator;  // "cvode-adams", "cvode-bdf" or "arkode-erk" (integrators.hpp)
  std::string erk_method;  // for arkode-erk (integrators.hpp)
  OdeProjection projection;
};

RunResult integrate_ode(OdeProblem& problem, const SolverSettings& settings, const TimeGrid& time, const OdeMethod& method,
                        StepSink& sink);

}  // namespace rigidae
