#pragma once
// Accuracy studies: a grid of independent runs (scene x combination x
// tolerance), each timed over repeats and measured against a reference, then
// merged into one tidy table and work-precision figures.
//
// A study is a deterministic list of runs. Each run writes its own folder,
//   OUT/runs/SCENE/COORDINATES-EQUATIONS-SCHEME/rtol_R_atol_A/
// first under a temporary name, renamed when complete (run.json inside), so
// a run whose folder exists is never redone: an interrupted study resumes,
// and shards (--shard i/N, Slurm array tasks) or GNU parallel jobs can share
// one OUT. Tight references live in OUT/reference/SCENE/.
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "rigidae/app/compare.hpp"
#include "rigidae/model/scene.hpp"

namespace rigidae {

struct StudySpec {
  std::string source;  // the study file
  std::string name, description;
  std::vector<Scene> scenes;
  std::vector<std::string> only, skip;  // combination patterns, as for compare (integrator part default "*")
  // The integrators axis ([grid] integrators; default IDA only); each
  // scene runs the valid scheme pairs of each (multibody scenes too).
  std::vector<IntegratorChoice> integrators{IntegratorChoice{"ida", ""}};
  std::vector<double> rtols;
  // atol = atol_ratio * rtol when tied, else the fixed atol.
  bool atol_tied = true;
  double atol_ratio = 1.0;
  double atol = 0.0;
  int warmups = 1;  // untimed runs before the repeats
  int repeats = 3;  // timed runs: results report their minimum and median
  std::string reference;  // "auto", "exact", "tight"; empty: each scene's own choice
  std::optional<double> reference_rtol;  // default: default_reference_rtol(smallest rtol)
  std::vector<double> targets{1e-3, 1e-6, 1e-9};  // error targets of the best-per-target table, rad
};

// The reference kind a study uses for one of its scenes ("auto", "exact",
// "tight"), and the rtol of its tight references.
std::string study_reference_kind(const StudySpec& spec, const Scene& scene);
double study_reference_rtol(const StudySpec& spec);

// Parses and validates a study file (TOML; docs/studies.md). Scene paths are
// relative to the study file. Throws InputError "FILE:LINE:COL: error: ...".
StudySpec load_study(const std::string& path);

struct StudyRun {
  int index = 0;          // position in the plan
  std::size_t scene = 0;  // into StudySpec::scenes
  Combination combination;
  double rtol = 0.0, atol = 0.0;

  // "SCENE/COORDINATES-EQUATIONS-SCHEME/rtol_R_atol_A": the folder under OUT/runs.
  std::string id(const StudySpec& spec) const;
  // The scene as this run solves it.
  Scene scene_for(const StudySpec& spec) const;
};

// A scene's combinations in a study: its integrators axis, then the patterns.
std::vector<Combination> study_combinations(const StudySpec& spec, const Scene& scene);

// Every run, scene-major, then combination (integrator, then registry order), then rtol.
std::vector<StudyRun> plan_study(const StudySpec& spec);

// Slice `index` (0-based) of `count`: runs k with k % count == index, so each
// slice gets a mix of loose and tight tolerances.
struct Shard {
  int index = 0, count = 1;
};
std::vector<StudyRun> select_shard(const std::vector<StudyRun>& runs, Shard shard);
// "i/N" with 0 <= i < N; InputError otherwise.
Shard parse_shard(const std::string& text);
// From SLURM_ARRAY_TASK_ID (minus SLURM_ARRAY_TASK_MIN) and
// SLURM_ARRAY_TASK_COUNT; nullopt when not in a Slurm array job.
std::optional<Shard> shard_from_slurm();

std::filesystem::path run_folder(const std::filesystem::path& out, const StudySpec& spec, const StudyRun& run);
bool run_complete(const std::filesystem::path& out, const StudySpec& spec, const StudyRun& run);

struct StudyProgress {
  int done = 0, skipped = 0, failed = 0, total = 0;
  std::string last;  // the run just finished
};

struct StudyRunOptions {
  std::filesystem::path out;
  std::function<void(const StudyProgress&)> progress;  // after each run (may be empty)
  bool keep_steps = false;  // keep each run's steps.csv (nothing of a study reads them)
  std::function<void(const std::string&)> note;  // one-line notes (leftovers removed; may be empty)
  // Each run's verdict (app/error_estimate.hpp): a companion at rtol/100 for a
  // scene without a closed form; false: none (--no-error-estimate).
  bool error_estimate = true;
};

// Runs every incomplete run of `runs` (skipping complete ones). Returns false
// if interrupted (Ctrl-C / TERM): the run in progress leaves no folder.
bool run_study(const StudySpec& spec, const std::vector<StudyRun>& runs, const StudyRunOptions& opt);

// Merges the complete run folders into OUT/results.csv and writes the
// best-per-target table to OUT/best.txt and OUT/best.md (also returned).
// `missing` receives the ids of planned runs without a complete folder.
std::string collect_study(const StudySpec& spec, const std::filesystem::path& out, std::vector<std::string>* missing);

}  // namespace rigidae
