#pragma once
// One run of one scene, start to finish: assemble the DAE, integrate it with
// IDA while streaming every step to disk, and write summary.json.
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "rigidae/app/accuracy_check.hpp"
#include "rigidae/multibody/one_body_view.hpp"
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
  std::vector<std::string> multiplier_names;
  InvariantDrifts drifts;                 // the accuracy check's measures (app/accuracy_check.hpp)
  std::vector<AccuracyWarning> warnings;  // those past their limits
  std::vector<std::string> start_warnings;  // multibody: the start's notes (projected misses, unmodelled parts)
  std::vector<SchemeParameter> scheme_parameters;  // as the scheme used them
  MultiplierErrorControl multipliers_error;  // record/error_control.hpp
  bool output_lost = false;               // a record could not be written (run.message says which)
};

// Writes steps.csv, trajectory.csv, events.csv and summary.json into
// out_dir (created if needed). A failed run keeps every step and has
// status "failed" in its summary; it does not throw.
SolveOutcome solve_scene(const Scene& scene, const std::filesystem::path& out_dir);

// The recording side of a run, for solve_with: the sink that sees it, and
// `close`, called when the run has ended however it ended (it may throw
// OutputError for a record that could not be completed).
struct RunSink {
  RecordingSink* sink = nullptr;
  std::function<void()> close;
};

// solve_scene without its files, for callers that record the run themselves
// (the Python module keeps it in memory): `attach` receives the assembled problem
// and returns the recording. out_dir stays empty; nothing is written.
SolveOutcome solve_with(const Scene& scene, const std::function<RunSink(const OneBodyView&)>& attach);

// solve_scene for a scene of bodies and joints (schema 2, URDF) with a second
// sink beside its files: `also` receives the assembled problem and returns a
// sink that sees every step, output point and event as the recorder does
// (the Python module's memory), or null.
using MultibodySinkAttach = std::function<StepSink*(multibody::MultibodyProblem&)>;
SolveOutcome solve_multibody_with(const Scene& scene, const std::filesystem::path& out_dir,
                                  const MultibodySinkAttach& also);

// The same run with no files (the Python module without `out`): the
// integrator the scene names, the accuracy check and its warnings; `also`
// is the only sink.
SolveOutcome solve_multibody_in_memory(const Scene& scene, const MultibodySinkAttach& also);

// The text of summary.json for an outcome (what solve_scene writes).
std::string summary_json(const Scene& scene, const SolveOutcome& o);
void write_summary(const std::filesystem::path& path, const Scene& scene, const SolveOutcome& o);

// A folder name for a formulation, e.g. "heavy_top-quaternion-euler-ggl".
std::string default_run_name(const Scene& scene);

}  // namespace rigidae
