#pragma once
// The step-size floor's watch, shared by the IDA and the ODE drivers.
#include <algorithm>

#include "rigidae/core/run_settings.hpp"

namespace rigidae {

// Watches accepted steps for a collapsed step size: stalled after
// kStalledSteps steps in a row below the floor while the step is not
// climbing out (within 16x the smallest step of the streak: a start from a
// tiny first step doubles its step each step and is let through).
struct StallWatch {
  long steps = 0;      // in a row below the floor
  double min_h = 0.0;  // the smallest of them
  bool stalled(double h, double floor, bool at_end) {
    if (!(h < floor) || at_end) {
      steps = 0;
      return false;
    }
    min_h = steps == 0 ? h : std::min(min_h, h);
    ++steps;
    return steps >= kStalledSteps && h <= 16.0 * min_h;
  }
};

}  // namespace rigidae
