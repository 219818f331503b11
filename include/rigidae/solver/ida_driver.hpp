#pragma once
// Integrates an assembled DAE with SUNDIALS IDA, one internal step at a time.
//
// The only module that includes SUNDIALS headers. The loop reads like the
// method: advance one step; on a chart event re-express the state and
// restart; hand every accepted step and every output-grid point to a sink.
#include <atomic>
#include <string>
#include <vector>

#include "rigidae/dae/dae_system.hpp"
#include "rigidae/model/scene.hpp"

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
};

// Receives the run as it happens.
class StepSink {
 public:
  virtual ~StepSink() = default;
  // After each accepted internal step: step size and order used.
  virtual void on_step(double t, double h, int order, const Eigen::VectorXd& y) = 0;
  // At each point of the output grid (IDA's interpolation).
  virtual void on_output(double t, const Eigen::VectorXd& y) = 0;
  virtual void on_chart_switch(const ChartSwitch& s) = 0;
  // After a step whose state was projected onto the manifold (drift before it).
  virtual void on_projection(double t, const ConstraintDrift& before) = 0;
};

// Set to true (e.g. from a SIGINT handler) to stop the run between steps.
extern std::atomic<bool> g_interrupt_requested;

// Runs the scene's time span. Never throws for solver trouble: the result
// says what happened. Throws InputError for an impossible start.
RunResult integrate(DaeSystem& dae, const Scene& scene, StepSink& sink);

// The output grid: start, start + k step, ..., and end exactly, computed
// point by point (a run of 1e8 output intervals must not hold them all).
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
