#pragma once
// The accuracy verdict of a run: its global error, from the closed form where
// the scene has one, else estimated by a companion run, and a warning when
// that error is far beyond the tolerance (docs/accuracy_check.md, "The
// verdict from an error estimate").
//
// Closed form (a single body: free body, symmetric Lagrange top): the error
// is the rotation angle of R_exact^T R on the output grid. It decides.
//
// Companion: the same scene and combination again at rtol/100 and atol/100
// (no tighter than the settings table allows), on the same output grid. With
// the global error of a tolerance-controlled run roughly proportional to the
// tolerance, the companion's error is ~1/100 of the run's, so
//   |run - companion| = |run - exact| (1 +- ~0.01)
// estimates the run's error where no closed form is. Compared per grid point:
//   orientation   the rotation angle between the two runs, the worst body (rad)
//   position      multibody: |x_run - x_companion| / L, the worst body's centre
//                 of mass, L the mechanism's size (app/multibody_accuracy_check.hpp:
//                 the largest distance between two of the bodies' centres of
//                 mass and the joints' ground points at the start, >= 1 mm)
// and the largest over the grid is the estimate.
//
// Verdict: with tol = max(rtol, atol) (orientations are O(1) and positions
// are divided by L, so both tolerances apply to them alike), an estimate above
//   limit = 300 tol
// gives a warning (quantity orientation_error or position_error). 300 lies
// between the "within 100 x rtol" and "more than 1000 x rtol off" classes
// that tools/accuracy_corpus.py measures (targets: at most 1 % of the first
// warned, at least 95 % of the second).
//
// Branch check: a run and its companion whose centres of mass differ by more
// than L are not on the same motion: one of them changed assembly branch at a
// singular pose (or the motion is chaotic). After a singular pose either run
// may have switched, so a difference past the limit there calls a third run,
// the arbiter: the same scene at the companion's tolerances in other
// coordinates (linear/euler/ggl on IDA, or quaternion/euler/ggl when the
// companion already is that; when it fails or changes branch by its own
// branch check, linear/euler/index2, then linear/euler/projection). Within
// the limit of the run, it sides with the
// run: the estimate is the run's difference to the arbiter (the companion was
// the one that switched); within the limit of the companion, two tighter runs
// agree against the run, whose warning then says so; else which run is right
// is not known and the warning says that. "Passed a singular pose" means a
// branch_switch or singular_pose warning of the run's own (its branch check,
// src/multibody/branch_check.cpp, found the velocity jump there, or could not
// check). The run's own branch_switch warning stays whatever the verdict: a
// run and its companion can change branch together (measured on problems/singular_linkage.toml:
// linear/lagrange/index2 at rtol 1e-5 ends 1.7 rad off the closed form, its
// companion 1.5e-3 rad from it).
//
// When the run's own combination fails at the tight tolerances (index3 at
// rtol 1e-11 can fail its first Newton iterations), the same motion in
// quaternion/euler/ggl on IDA is the companion instead: any well-posed
// formulation converges to the same solution; then linear/euler/index2 and
// linear/euler/projection on IDA (ggl's Newton iteration can fail at a
// singular pose, these pass it). If they all fail, or the
// companion stalls (its wall-time limit: max(30 s, 20 x the run's), each
// attempt), is interrupted or writes another grid, there is no verdict: the
// estimate is "not estimated" with the reason, never a pass.
#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "rigidae/app/accuracy_check.hpp"
#include "rigidae/app/solve.hpp"
#include "rigidae/model/scene.hpp"
#include "rigidae/record/trajectory_csv.hpp"

namespace rigidae {

// The verdict's limit, in units of max(rtol, atol).
inline constexpr double kVerdictFactor = 300.0;
// The companion's wall-time limit: max(kCompanionFloorS, kCompanionWallFactor x the run's wall time).
inline constexpr double kCompanionFloorS = 30.0;
inline constexpr double kCompanionWallFactor = 20.0;

struct OrientationError {
  double final = std::numeric_limits<double>::quiet_NaN();  // rad, at the last output time both runs reached
  double max = std::numeric_limits<double>::quiet_NaN();    // rad, over the output grid (every body)
  double t_final = std::numeric_limits<double>::quiet_NaN();
};

enum class EstimateSource { None, ClosedForm, Companion };
std::string to_string(EstimateSource s);

struct ErrorEstimate {
  EstimateSource source = EstimateSource::None;
  std::string not_estimated;  // why there is no verdict (source None)

  OrientationError orientation;  // |run - closed form| or |run - companion|, rad
  // Multibody and companion only: max over the grid of the worst body's |x - x_c| / L, and at the end.
  double position_rel_max = std::numeric_limits<double>::quiet_NaN();
  double position_rel_final = std::numeric_limits<double>::quiet_NaN();
  double length_scale_m = std::numeric_limits<double>::quiet_NaN();  // L (system_size in error_estimate.cpp), m

  // The companion run (source Companion, or a companion that failed).
  double rtol = 0.0, atol = 0.0;
  std::string tight_status;  // "success", or the companion's status and message
  double companion_wall_s = std::numeric_limits<double>::quiet_NaN();
  std::filesystem::path tight_dir;  // out_dir/error_estimate
  // Empty: the run's own combination. "quaternion/euler/ggl" when the run's own
  // failed at the tight tolerances (companion_note says how) and that one was run instead.
  std::string companion_combination, companion_note;

  double tolerance = 0.0;  // max(rtol, atol) of the run
  double limit = 0.0;      // kVerdictFactor x tolerance
  // The run and its companion differ by more than L, or differ past the limit
  // after one of them passed a singular pose (singular_pose_passed): then
  // either may have changed assembly branch, and the difference is no error
  // estimate of the run.
  bool branch_disagreement = false;
  bool singular_pose_passed = false;  // the run or its companion warned singular_pose or branch_switch
  // The arbiter after a singular pose (see above): "" (none run), "run" (it
  // sides with the run), "companion" (with the companion), "neither", or
  // "failed: ..." (it did not finish: the companion's estimate stands).
  std::string arbiter, arbiter_combination;
  std::vector<AccuracyWarning> warnings;  // the verdict's, past the limit

  // A companion's orientation estimate beside the closed form's error that
  // decides (solve --error-estimate on a scene with a closed form).
  std::optional<OrientationError> companion_orientation;

  bool estimated() const { return source != EstimateSource::None; }
};

// What a companion run may cost before it counts as stalled.
struct CompanionLimits {
  double floor_s = kCompanionFloorS;          // wall-time limit: max(floor_s, wall_factor x the run's)
  double wall_factor = kCompanionWallFactor;
  long max_steps = 0;  // 0: 10 x the scene's max_steps
};

// The tight tolerances for a run's: /100, no tighter than the settings table allows.
std::pair<double, double> tight_tolerances(const SolverSettings& run);

// The companion estimate: runs the scene at the tight tolerances into
// run.out_dir/error_estimate (record = grid) and compares the output grids;
// `run` is the first run's outcome, whose trajectory.csv must exist (record =
// steps or grid). Never throws for the companion's own failure: that is
// "not estimated" with the reason. Warnings are filled (judge).
ErrorEstimate estimate_global_error(const Scene& scene, const SolveOutcome& run, const CompanionLimits& limits = {});

// The verdict a run gets: the closed form's error when the scene has one;
// else the companion estimate when `companion` is true; else not estimated,
// the reason naming `how_to_enable` (e.g. "--error-estimate"). With a closed
// form and `companion`, the companion runs too and its estimate is kept
// beside (companion_orientation); the closed form decides.
ErrorEstimate accuracy_verdict(const Scene& scene, const SolveOutcome& run, bool companion,
                               const std::string& how_to_enable);

// The closed form's verdict on a run's output grid held in memory (the
// Python module's runs without an output folder); not estimated when the
// scene has no closed form.
ErrorEstimate closed_form_verdict(const Scene& scene, const BodyGrid& run_grid);

// The run's warnings with the verdict's appended (compare, study, solve).
void apply_verdict(SolveOutcome& run, const ErrorEstimate& e);

// Fills e.tolerance, e.limit, e.branch_disagreement and e.warnings from e's measures.
void judge(ErrorEstimate& e, const Scene& scene);

struct ReferenceTrajectory;  // app/reference.hpp

// A single-body run's orientation error against a reference on its output
// grid (read back from the run's trajectory.csv, which must exist): the
// closed form `solve` reports when the scene has one.
OrientationError error_against(const SolveOutcome& run, const ReferenceTrajectory& reference);

// Adds "closed_form_error" to the run's summary.json (rewritten atomically).
void add_closed_form_error_to_summary(const std::filesystem::path& summary, const OrientationError& e);

// The verdict as summary.json's "error_estimate" object.
nlohmann::json error_estimate_json(const ErrorEstimate& e);

// Adds "error_estimate" to the run's summary.json and the verdict's warnings
// to its "warnings" (rewritten atomically).
void add_error_estimate_to_summary(const std::filesystem::path& summary, const ErrorEstimate& e);
// The same on summary.json's text.
std::string with_error_estimate(const std::string& summary_text, const ErrorEstimate& e);

// One line for a person: "accuracy not estimated: WHY", or the estimate and its limit.
std::string describe(const ErrorEstimate& e);

}  // namespace rigidae
