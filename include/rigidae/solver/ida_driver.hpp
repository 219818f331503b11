#pragma once
// Integrates a DaeProblem with SUNDIALS IDA, one internal step at a time.
//
// The only module that includes SUNDIALS headers. It sees the narrow problem
// (solver/problem.hpp), the solver settings and the time grid: no scene, no
// physics. The loop reads like the method: start, advance one step, handle
// an event or what follows an accepted step (the problem's own actions:
// a chart change, a projection), and finish; every accepted step, every
// output-grid point and every event of the problem go to a sink.
#include <atomic>
#include <string>
#include <vector>

#include "rigidae/core/run_settings.hpp"
#include "rigidae/solver/problem.hpp"

namespace rigidae {

// IDA's counters, summed over restarts (IDAReInit resets IDA's own).
struct IdaCounters {
  long steps = 0;
  long residual_evals = 0;          // by the nonlinear solver
  long jacobian_evals = 0;
  long jacobian_residual_evals = 0;  // spent on difference-quotient Jacobians
  long nonlinear_iters = 0;
  long nonlinear_conv_fails = 0;
  long error_test_fails = 0;
  long linear_setups = 0;
  long root_evals = 0;
  long restarts = 0;     // IDAReInit calls (chart switches and projections)
  long projections = 0;  // states mapped back onto the constraint manifold
  double last_step = 0.0;
  int last_order = 0;
};

struct ChartSwitch {
  double t = 0.0;
  std::string from, to;
  double margin = 0.0;  // of the old chart where it was left
};

// A long run can switch charts without bound; only this many are held in memory.
constexpr std::size_t kSwitchesKept = 100;

enum class RunStatus { Success, Failed, Interrupted };
std::string to_string(RunStatus s);

struct RunResult {
  RunStatus status = RunStatus::Success;
  std::string message;     // why it stopped, if it did not succeed
  double t_reached = 0.0;  // s
  IdaCounters counters;
  long switch_count = 0;                // every chart switch (events.csv lists them all)
  std::vector<ChartSwitch> switches;    // the first kSwitchesKept of them
  double initial_residual = 0.0;  // max |F(t0, y0, y0')|: the consistency of the start
  std::string linear_solver;      // the one Newton used: "dense" or "klu" ("auto" resolved)
  long factor_nonzeros = 0;       // KLU: nonzeros of its last factors L + U (0: dense, or never factorised)
};

// Receives the run as it happens.
class StepSink {
 public:
  virtual ~StepSink() = default;
  // After each accepted internal step: step size and order used.
  virtual void on_step(double t, double h, int order, const Eigen::VectorXd& y) = 0;
  // At each point of the output grid (IDA's interpolation).
  virtual void on_output(double t, const Eigen::VectorXd& y) = 0;
  // False: the sink keeps only the last output point (a timed run that
  // records nothing), so the drivers interpolate and deliver only that one
  // (and the start); the steps taken are the same either way.
  virtual bool needs_every_output() const { return true; }
  // The problem's own events (chart switches, projections), as they happen.
  virtual void on_event(const EventNote& /*note*/) {}
};

// Set to true (e.g. from a SIGINT handler) to stop the run between steps.
extern std::atomic<bool> g_interrupt_requested;
// The signal that set it (SIGINT, SIGTERM), 0 when set otherwise (a test, an
// API call): the interrupted run's message names it.
extern std::atomic<int> g_interrupt_signal;
// "SIGTERM", "SIGINT (Ctrl-C)", or "a request to stop" for g_interrupt_signal.
std::string interrupt_cause();
// The message of a run stopped by g_interrupt_requested between steps.
std::string interrupt_message(double t, double last_step, long steps);
// The message of a run stopped by SolverSettings::wall_time_limit.
std::string timeout_message(double limit_s, double t, double t_end, double last_step, long steps);
// The step-size floor at t: settings.min_step_fraction * max(|end - start|, |t|).
double step_floor(const SolverSettings& settings, const TimeGrid& span, double t);
// The message of a run whose steps stayed below the floor for kStalledSteps
// steps: t, the step, the floor, the integrator and what the problem says.
std::string stall_message(const SolverSettings& settings, const TimeGrid& span, double t, double h, long steps,
                          const std::string& integrator, const std::string& problem_says);

// solver.linear_solver = "auto": KLU from this many unknowns on, dense LU
// below (measured on N-link chains: bench/chain.sh --solvers dense,klu and
// docs/benchmarks.md, "Dense or KLU"), and dense whenever KLU cannot run
// (IDA's difference quotients fill dense matrices only).
inline constexpr int kKluFromUnknowns = 120;
// "dense" or "klu": the linear solver a run of `problem` with `settings` uses.
std::string resolve_linear_solver(const SolverSettings& settings, const DaeProblem& problem);

// Runs the problem over the time grid. Never throws for solver trouble: the
// result says what happened. Throws InputError for an impossible start or
// settings IDA cannot combine.
RunResult integrate(DaeProblem& problem, const SolverSettings& settings, const TimeGrid& time, StepSink& sink);

// The output grid: start, start + k step, ..., and end exactly, computed
// point by point (a run of 1e8 output intervals must not hold them all); or,
// when the TimeGrid gives output_times, exactly those times.
class OutputGrid {
 public:
  explicit OutputGrid(const TimeGrid& grid);
  std::size_t size() const { return n_inner_ + 1; }
  double operator[](std::size_t k) const;

 private:
  TimeGrid grid_;
  std::size_t n_inner_ = 0;  // points before the end
};

// All points of OutputGrid as a vector.
std::vector<double> output_grid(const TimeGrid& grid);

}  // namespace rigidae
