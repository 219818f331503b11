#pragma once
// How a run is integrated: the solver's settings and the time grid.
//
// Plain data shared by the scene (which holds them), the command line and
// study files (which override them) and the integrator (which reads them and
// nothing else of the scene). Units are SI.
#include <string>
#include <vector>

namespace rigidae {

// The smallest relative tolerance accepted: below it round-off in double
// precision exceeds the tolerance and IDA's step size collapses without a
// failure (heavy top at 1e-15: 545,792 steps in 60 s reached t = 4.5e-8 s).
inline constexpr double kMinRelativeTolerance = 1e-14;
// The smallest absolute tolerance accepted: IDA's weighted norms square
// 1/atol and overflow near 1e-154 (at 1e-160 IDA rejects the input).
inline constexpr double kMinAbsoluteTolerance = 1e-100;

struct SolverSettings {
  double rtol = 1e-8;            // in [kMinRelativeTolerance, 1)
  double atol = 1e-8;            // in [kMinAbsoluteTolerance, 1), absolute tolerance of coordinates and velocities
  long max_steps = 10'000'000;   // internal IDA steps over the whole run
  int max_order = 5;             // BDF order limit, 1..5
  double initial_step = 0.0;     // 0: estimated from the start's second derivative
  // Iteration matrix: "exact" (derived by hand per representation and
  // scheme), "central" (rigidae's differences, accurate to ~1e-11) or
  // "ida_dq" (IDA's own forward difference quotients). Same steps, far fewer
  // residual evaluations with "exact" (docs/ida_settings.md).
  std::string jacobian = "exact";
  // Linear solver for Newton's systems: "dense" (SUNDIALS' dense LU),
  // "klu" (sparse LU on the iteration matrix's structural pattern; not with
  // "ida_dq") or "auto" (KLU from kKluFromUnknowns unknowns on, a measured
  // size: solver/ida_driver.hpp; single bodies have <= 30 and stay dense).
  std::string linear_solver = "auto";
  // Integrator and explicit Runge-Kutta table (solver/integrators.hpp
  // lists the valid values and which schemes each integrator runs).
  std::string integrator = "ida";
  std::string erk_method = "dopri87";
  // Whether a scene file, the command line or a study named the integrator;
  // if not, settings::resolve_integrator chooses it by the default rule
  // (settings/default_integrator.hpp) and says why in integrator_choice
  // ("named" when it was named), which summary.json reports.
  bool integrator_named = false;
  std::string integrator_choice;
  // The step-size floor, relative to the scene's time scale: a run whose
  // accepted steps stay below min_step_fraction * max(|end - start|, |t|)
  // for kStalledSteps steps in a row fails as stalled (at that size the rest
  // of the span would take over 1e12 steps). 0: no floor.
  double min_step_fraction = 1e-12;
  // Wall-clock limit of one run in s (compare --run-timeout); 0: none. A run
  // past it fails with a message saying so, its steps kept.
  double wall_time_limit = 0.0;
};

// Accepted steps in a row below the floor before a run counts as stalled:
// a step that lands on an output or stop time, or the first steps after a
// restart, may be tiny once; IDA grows its step at most 2x per step, so a
// run recovering from a transient is back above the floor well within this.
inline constexpr long kStalledSteps = 20;

// Limits of the time grid: |start|, |end| (about 32 years; beyond, t + h
// loses the digits of small steps) and the number of output intervals.
inline constexpr double kMaxTimeMagnitude = 1e9;  // s
inline constexpr double kMaxOutputIntervals = 1e8;

struct TimeGrid {
  TimeGrid() = default;
  // The even grid (the usual case; `{start, end, step}` reads as before output_times existed).
  TimeGrid(double start_s, double end_s, double output_step_s)
      : start(start_s), end(end_s), output_step(output_step_s) {}

  double start = 0.0;          // s
  double end = 1.0;            // s, > start
  double output_step = 0.01;   // s, > 0; grid = start, start + k step, ..., end (end always included)
  // Output at these times instead of the even grid (scene key output.times):
  // strictly increasing, inside [start, end]. Empty: the even grid.
  std::vector<double> output_times;
};

// What a run writes besides summary.json (always written):
//   Steps  every accepted step (steps.csv or steps.npy) and the output grid (trajectory.csv)
//   Grid   the output grid only
//   None   neither (events.csv, a few rows, stays)
enum class RecordMode { Steps, Grid, None };
// The step file's format: text (steps.csv) or NumPy's binary .npy (steps.npy,
// a structured array whose field names are the CSV's header).
enum class StepFormat { Csv, Npy };

struct OutputSettings {
  RecordMode record = RecordMode::Steps;
  StepFormat step_format = StepFormat::Csv;
};

}  // namespace rigidae
