// The stop time both drivers (IDA, the ODE integrators) give their
// integrator after an accepted step: the problem's hint (short of a
// mechanism's singular pose, stop_time_hint()) when it lies ahead of t and
// inside the run, else the run's end.
#pragma once

namespace rigidae {

inline double next_stop_time(double hint, double t, double end) { return hint > t && hint < end ? hint : end; }

}  // namespace rigidae
