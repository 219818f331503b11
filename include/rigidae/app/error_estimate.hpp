#pragma once
// An estimate of a run's global error (solve --error-estimate): the same
// scene run again at tighter tolerances, rtol/100 and atol/100 (no tighter
// than the settings table allows), and the orientation of every body compared
// on the output grid. With BDF's error roughly proportional to the tolerance,
// the tight run's own error is ~1/100 of the first run's, so
//   |run - tight| = |run - exact| (1 +- ~0.01)
// is an estimate of the first run's error, available where no closed form
// is. Where the scene has a closed form (a free body, a symmetric Lagrange
// top), the true error is reported beside it.
#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <utility>

#include "rigidae/app/solve.hpp"
#include "rigidae/model/scene.hpp"

namespace rigidae {

struct OrientationError {
  double final = std::numeric_limits<double>::quiet_NaN();  // rad, at the last output time both runs reached
  double max = std::numeric_limits<double>::quiet_NaN();    // rad, over the output grid (every body)
  double t_final = std::numeric_limits<double>::quiet_NaN();
};

struct ErrorEstimate {
  double rtol = 0.0, atol = 0.0;  // of the tight run
  std::string tight_status;       // "success", or why the estimate is missing
  OrientationError estimate;      // |run - tight run|
  std::optional<OrientationError> closed_form;  // |run - closed form|, when the scene has one
  std::filesystem::path tight_dir;  // the tight run's files (out_dir/error_estimate)
};

// The tight tolerances for a run's: /100, no tighter than the settings table allows.
std::pair<double, double> tight_tolerances(const SolverSettings& run);

// Runs the tight run into run.out_dir/error_estimate (record = grid) and
// compares the output grids; `run` is the first run's outcome, whose
// trajectory.csv must exist (record = steps or grid).
ErrorEstimate estimate_global_error(const Scene& scene, const SolveOutcome& run);

struct ReferenceTrajectory;  // app/reference.hpp

// A single-body run's orientation error against a reference on its output
// grid (read back from the run's trajectory.csv, which must exist): the
// closed form `solve` reports when the scene has one.
OrientationError error_against(const SolveOutcome& run, const ReferenceTrajectory& reference);

// Adds "closed_form_error" to the run's summary.json (rewritten atomically).
void add_closed_form_error_to_summary(const std::filesystem::path& summary, const OrientationError& e);

// Adds "error_estimate" to the run's summary.json (rewritten atomically).
void add_error_estimate_to_summary(const std::filesystem::path& summary, const ErrorEstimate& e);

}  // namespace rigidae
