#pragma once
// One run of one scene, start to finish: assemble the DAE, integrate it with
// IDA while streaming every step to disk, and write summary.json.
#include <filesystem>
#include <string>
#include <vector>

#include "rigidae/app/accuracy_check.hpp"
#include "rigidae/model/scene.hpp"
#include "rigidae/record/recorder.hpp"
#include "rigidae/schemes/scheme.hpp"
#include "rigidae/solver/ida_driver.hpp"

namespace rigidae {

struct SolveOutcome {
  RunResult run;
  RunExtremes extremes;
  double wall_seconds = 0.0;  // integration and recording, not setup
  std::filesystem::path out_dir;
  std::string representation, scheme, note;
  std::vector<std::string> multiplier_names;
  InvariantDrifts drifts;                 // the accuracy check's measures (app/accuracy_check.hpp)
  std::vector<AccuracyWarning> warnings;  // those past their limits
  std::vector<SchemeParameter> scheme_parameters;  // as the scheme used them
};

// Writes steps.csv, trajectory.csv, events.csv and summary.json into
// out_dir (created if needed). A failed run keeps every step and has
// status "failed" in its summary; it does not throw.
SolveOutcome solve_scene(const Scene& scene, const std::filesystem::path& out_dir);

// A folder name for a formulation, e.g. "heavy_top-quaternion-euler-ggl".
std::string default_run_name(const Scene& scene);

}  // namespace rigidae
