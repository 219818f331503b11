#pragma once
// IDA's counters and the accuracy check's warnings as summary.json writes
// them, for every kind of run (one body or many), so the two summaries cannot
// drift apart.
#include <nlohmann/json.hpp>

#include <vector>

#include "rigidae/app/accuracy_check.hpp"
#include "rigidae/solver/ida_driver.hpp"

namespace rigidae {

inline nlohmann::json counters_json(const IdaCounters& c) {
  return {{"steps", c.steps},
          {"residual_evals", c.residual_evals},
          {"jacobian_evals", c.jacobian_evals},
          {"jacobian_residual_evals", c.jacobian_residual_evals},
          {"nonlinear_iters", c.nonlinear_iters},
          {"nonlinear_conv_fails", c.nonlinear_conv_fails},
          {"error_test_fails", c.error_test_fails},
          {"linear_setups", c.linear_setups},
          {"root_evals", c.root_evals},
          {"restarts", c.restarts},
          {"projections", c.projections},
          {"last_step", c.last_step},
          {"last_order", c.last_order}};
}

inline nlohmann::json warnings_json(const std::vector<AccuracyWarning>& warnings) {
  nlohmann::json a = nlohmann::json::array();
  for (const AccuracyWarning& w : warnings)
    a.push_back({{"quantity", w.quantity},
                 {"drift", w.drift},
                 {"limit", w.limit},
                 {"factor", w.factor},
                 {"tolerance", w.tolerance},
                 {"message", w.message}});
  return a;
}

}  // namespace rigidae
