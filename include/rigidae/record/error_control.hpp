#pragma once
// Whether a run's multipliers (and the joint reactions made of them) are
// held to rtol/atol by the integrator's error test, and why not. IDA leaves
// the algebraic unknowns out of its local error test when the problem asks
// (DaeProblem::suppress_algebraic_error_test: every scheme does, since the
// multipliers of index-2 and index-3 formulations are not smooth enough for
// it); they are then as accurate as each step's Newton solve, with no error
// estimate (a first correction is accepted without a second iteration only
// within about 30 x the Newton tolerance in their weighted norm,
// src/solver/ida_newton_test.hpp). The ODE integrators carry no multipliers: they are solved from
// the state after each step, so their error follows the state's, unmeasured.
// summary.json (multipliers_error_controlled, multipliers_error_note) and the
// units line of a mechanism's step file state it.
#include <fmt/format.h>

#include <string>
#include <string_view>

namespace rigidae {

struct MultiplierErrorControl {
  bool controlled = false;
  std::string note;  // why not ("" when controlled)
};

inline MultiplierErrorControl multiplier_error_control(std::string_view integrator, bool algebraic_test_suppressed,
                                                       std::string_view scheme) {
  if (integrator != "ida")
    return {false, fmt::format("{} integrates the state only; multipliers and reactions are solved from it after "
                               "each step, without an error estimate of their own",
                               integrator)};
  if (!algebraic_test_suppressed) return {true, ""};
  return {false, fmt::format("scheme {}: IDA's error test leaves out the multipliers (algebraic unknowns); they "
                             "and the reactions made of them are as accurate as each step's Newton solve, not "
                             "held to rtol/atol",
                             scheme)};
}

}  // namespace rigidae
