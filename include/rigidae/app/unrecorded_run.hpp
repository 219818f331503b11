#pragma once
// A run that records nothing, for timing what users time (SciML's
// work-precision convention, save_everystep = false): the integrator writes
// no step or grid file and observes no step; only the state at the last
// output point is kept, from which the final error is taken.
#include "rigidae/app/reference.hpp"
#include "rigidae/model/scene.hpp"
#include "rigidae/solver/ida_driver.hpp"

namespace rigidae {

struct UnrecordedRun {
  RunResult run;
  double wall_seconds = 0.0;  // the integration alone (no setup, no files)
  // The last output point only (one row): the system's bodies (a one-body
  // scene's is named "body"); the layout of a mechanism's grid.
  BodyGrid last;
};

UnrecordedRun run_unrecorded(const Scene& scene);

// The final orientation error (rad; multibody: the worst body) of a run that
// reached the end, against the reference's last grid point; NaN otherwise.
double final_orientation_error(const UnrecordedRun& r, const ReferenceTrajectory& ref);

}  // namespace rigidae
