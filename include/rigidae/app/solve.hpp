#pragma once
// One run of one scene, start to finish: the scene as a system of bodies
// (one body or a mechanism alike), integrated by the integrator it names
// while the one recorder streams every step (record/recorder.hpp) behind the
// accuracy check, then summary.json.
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "rigidae/app/accuracy_check.hpp"
#include "rigidae/multibody/multibody_problem.hpp"
#include "rigidae/model/scene.hpp"
#include "rigidae/record/error_control.hpp"
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
  int unknowns = 0;  // of the system IDA integrates (the DAE's y)
  bool constrained = false;  // the system has constraint rows (a body's own or joints'): drift is measured
  std::vector<std::string> multiplier_names;
  InvariantDrifts drifts;                 // the accuracy check's measures (app/accuracy_check.hpp)
  std::vector<AccuracyWarning> warnings;  // those past their limits
  std::vector<std::string> start_warnings;  // multibody: the start's notes (projected misses, unmodelled parts)
  std::vector<SchemeParameter> scheme_parameters;  // as the scheme used them
  MultiplierErrorControl multipliers_error;  // record/error_control.hpp
  bool output_lost = false;               // a record could not be written (run.message says which)
  std::string final_report;  // solve's report lines on the final state (RunColumns::final_report)
  std::string summary;       // summary.json's text
};

// Writes steps.csv, trajectory.csv, events.csv and summary.json into
// out_dir (created if needed). A failed run keeps every step and has
// status "failed" in its summary; it does not throw.
SolveOutcome solve_scene(const Scene& scene, const std::filesystem::path& out_dir);

// solve_scene with the choice of outputs: files into out_dir when it is not
// empty, the rows `memory` asks for (the Python module), and `also`, which
// receives the assembled system and may return a sink that sees every step,
// output point and event after the recorder (or null).
SolveOutcome run_scene(const Scene& scene, const std::filesystem::path& out_dir, MemoryRows* memory = nullptr,
                       const std::function<StepSink*(const multibody::MultibodyProblem&)>& also = {});

// A folder name for a formulation, e.g. "heavy_top-quaternion-euler-ggl".
std::string default_run_name(const Scene& scene);

}  // namespace rigidae
