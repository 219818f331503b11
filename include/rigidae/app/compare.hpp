#pragma once
// One scene in every applicable coordinates x equations x scheme combination,
// side by side against one reference.
//
// Folder layout (out):
//   compare.csv, compare.txt, compare.md   the table
//   reference/, reference-check/          the reference and its cross-check
//   COORDINATES-EQUATIONS-SCHEME/         each combination's run folder, as `solve` writes it
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "rigidae/app/accuracy.hpp"
#include "rigidae/app/error_estimate.hpp"
#include "rigidae/app/reference.hpp"
#include "rigidae/app/solve.hpp"
#include "rigidae/model/scene.hpp"

namespace rigidae {

// A single body in coordinates without constraints (Euler angles) carries none, so every scheme gives
// it the same ODE: it appears once per equation form, with scheme "any". In a
// multibody scene the joints are constraints whatever the coordinates, so
// every coordinates x equations x scheme runs.
//
// The integrator is part of a combination (solver/integrators.hpp states
// which integrator runs which scheme): "ida" (the DAE, every scheme), or an
// ODE integrator ("cvode-adams", "cvode-bdf", "arkode-erk" with its Runge-
// Kutta table) on the ODE form, schemes index1 and projection only.
struct Combination {
  Coordinates coordinates = Coordinates::Quaternion;
  Equations equations = Equations::Euler;
  std::string scheme;  // registry name, or "any"
  std::string integrator = "ida";
  std::string erk_method;  // arkode-erk's table; empty otherwise

  // "quaternion/euler/ggl" on IDA (today's names), else with the integrator:
  // "quaternion/euler/projection@cvode-adams", "...@arkode-erk:fehlberg78".
  std::string name() const;
  // "quaternion-euler-ggl", "quaternion-euler-projection-cvode-adams", "...-arkode-erk-fehlberg78".
  std::string folder() const;
  // "ida", "cvode-adams", "arkode-erk:fehlberg78".
  std::string integrator_label() const;
  Scene applied_to(const Scene& scene) const;
};

// An entry of an integrators list: "ida", "cvode-adams", "cvode-bdf",
// "arkode-erk" (the scene's Runge-Kutta table) or "arkode-erk:METHOD".
struct IntegratorChoice {
  std::string integrator;
  std::string erk_method;  // arkode-erk only
  std::string label() const;
};
// InputError (prefixed by `where`) listing the valid entries for an unknown one.
IntegratorChoice parse_integrator_choice(const std::string& text, const std::string& default_erk_method,
                                         const std::string& where = "");
// Every integrator and Runge-Kutta table, e.g. for messages: "ida, cvode-adams, ..., arkode-erk:dopri5".
std::string integrator_choices_text();

// Every applicable single-body combination on IDA, coordinates then equations
// then schemes in registry order (today's compare table).
std::vector<Combination> all_combinations();
// The combinations of a scene on the given integrators: for each integrator,
// coordinates x equations x the schemes it runs. A multibody scene gives
// every scheme the integrator runs to every coordinates (its bodies'
// internal constraints and its joints need one even where a single body of
// those coordinates would not).
std::vector<Combination> combinations_for(const Scene& scene, const std::vector<IntegratorChoice>& integrators,
                                          const std::string& where = "");
// compare's default integrators: IDA, then the ODE integrators (arkode-erk
// with the scene's table), for single bodies and mechanisms alike.
std::vector<IntegratorChoice> default_integrators(const Scene& scene);

// A pattern is COMBINATION[@INTEGRATOR]. Its combination part with '/' is a
// glob over "coordinates/equations/scheme" ("quaternion/*/ggl"); without, it
// matches any single part ("ggl", "linear", "index*"). Its integrator part
// is a glob over the integrator ("cvode-*", "arkode-erk") or, with ':', over
// "integrator:method"; without '@' it is `default_integrator` (compare: "ida",
// so that today's patterns select today's rows; a study: "*", its integrators
// axis chooses). A bare integrator name ("cvode-adams") means "*@cvode-adams".
bool matches(const Combination& c, const std::string& pattern, const std::string& default_integrator = "ida");

struct CompareOptions {
  int repeat = 3;                     // wall time: median of this many runs
  std::vector<std::string> only, skip;
  std::filesystem::path out;
  std::optional<double> reference_rtol;  // default: default_reference_rtol(rtol)
  // "auto", "exact" or "tight" (see make_reference); empty: the scene's choice.
  std::string reference;
  // Keep each run's steps.csv (and the reference's); by default only the
  // summaries and output grids stay (a full compare wrote 152 MB of steps).
  bool keep_steps = false;
  // Wall-time limit of each combination's run in s (0: none); unset:
  // default_run_timeout of the reference's wall time.
  std::optional<double> run_timeout;
  // Run every combination even when the reference failed (otherwise
  // compare stops there: without a reference no error can be reported).
  bool keep_going = false;
  // The verdict of each row (app/error_estimate.hpp): the closed form decides
  // where the scene has one; otherwise a companion run at rtol/100 into the
  // row's folder (error_estimate/). false: no companion (--no-error-estimate).
  bool error_estimate = true;
};

// The default per-run limit: max(300 s, 10 x the reference's wall time). A
// combination at the scene's own tolerance runs 10-100x faster than the
// tight reference (docs/benchmarks.md), so 10x the reference only cuts runs
// that are far off their peers; 300 s keeps exact references (no run) and
// short scenes from timing out on a busy machine.
double default_run_timeout(double reference_wall_s);

struct CompareRow {
  Combination combination;
  SolveOutcome outcome;           // of the first run
  std::vector<double> wall_seconds;  // one per repeat
  double wall_median = 0.0;
  double error_final_rad = 0.0;   // NaN when the run did not reach the end or there is no reference
  double error_max_rad = 0.0;     // over the output grid points the run reached
  RunAccuracy accuracy;           // every error group
  ErrorEstimate verdict;          // its warnings are also in outcome.warnings
  double lambda_min = 0.0, lambda_max = 0.0;  // J, NaN without force multipliers
  double mu_abs_max = 0.0;                    // 1/s, NaN without kinematic multipliers
};

struct CompareReport {
  std::string scene_name, scene_source;
  double rtol = 0.0, atol = 0.0;
  // The grids record centre-of-mass positions (a mechanism's files): the
  // errors (app/accuracy.hpp, the worst body's) add the position's, and the
  // integrators are ranked by it.
  bool positions = false;
  ReferenceTrajectory reference;
  std::vector<CompareRow> rows;
  double run_timeout_s = 0.0;  // the per-run limit used (0: none)
  bool run_timeout_default = true;  // run_timeout_s is default_run_timeout(reference_wall_s), not --run-timeout
  double reference_wall_s = 0.0;    // the reference's wall time (s), which the default limit scales
  // Why compare stopped before running every combination ("" if it did
  // not): a signal, or a failed reference without keep_going.
  std::string stopped;
  bool interrupted = false;  // by a signal (Ctrl-C, TERM)
};

// Which integrator is cheapest for the accuracy (issue 23 item 4), read off
// the rows: at each error level (the powers of ten from the one at or above
// the largest row error down to the one at or above the smallest), each
// integrator's fastest successful row (wall median) whose error is at most
// the level. The error is the largest on the output grid: the worst body's
// centre-of-mass distance in m for a mechanism, the rotation angle in rad
// for a single body. Rows without an error (failed, or no reference) take
// no part.
struct FastestToError {
  double level = 0.0;
  std::vector<int> row;  // per IntegratorRanking::integrators: index into CompareReport::rows, -1 none
  int fastest = -1;      // index into IntegratorRanking::integrators, -1 when no row reaches the level
};
struct IntegratorRanking {
  std::string unit;                      // "m" or "rad"
  std::vector<std::string> integrators;  // labels ("ida", "arkode-erk:fehlberg78"), in the rows' order
  std::vector<FastestToError> levels;    // largest level first
};
IntegratorRanking rank_integrators(const CompareReport& r);
// The ranking as compare.txt prints it under the rows ("" with fewer than
// two integrators or no errors).
std::string format_integrator_ranking(const CompareReport& r);

// Runs everything; one combination's failure is a row, not an exception.
// progress receives one line per finished run (may be empty).
CompareReport compare_scene(const Scene& scene, const CompareOptions& opt,
                            const std::function<void(const std::string&)>& progress);

// The fixed-width table `rigidae compare` prints.
std::string format_compare_table(const CompareReport& r);
// compare.csv, compare.txt and compare.md into opt.out.
void write_compare_outputs(const CompareReport& r, const std::filesystem::path& out);

}  // namespace rigidae
