#pragma once
// The narrow view an integrator has of an assembled system.
//
// A DaeProblem is F(t, y, y') = 0 with everything an implicit integrator
// (IDA) needs and nothing else: its size, a consistent start, which unknowns
// are differential, per-unknown absolute tolerances, the residual, the exact
// iteration matrix dF/dy + cj dF/dy' (dense or on a fixed sparse pattern),
// root functions (events) and what to do at an event or after an accepted
// step (project, change a chart, or stop). It never exposes the scene or the
// physics: the single rigid body (dae/) and the multibody assembler
// (multibody/) both implement it, and the driver (solver/) sees only this.
//
// An OdeProblem is x' = f(t, x) for the explicit and Adams integrators
// (CVODE, ARKODE), with the same events and after-step actions and an
// optional projection onto the invariants.
//
// Conventions: vectors are plain arrays of size(); dense matrices are
// column-major size() x size(); sparse patterns are compressed sparse columns
// with 64-bit indices (SUNDIALS' sunindextype on Debian), rows ascending
// within each column, built once.
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

namespace rigidae {

// Compressed sparse columns of an n x n matrix: column c holds the entries
// rows[col_start[c]] .. rows[col_start[c+1]-1].
struct SparsityPattern {
  std::vector<std::int64_t> col_start;  // n + 1
  std::vector<std::int64_t> rows;       // nnz
  std::int64_t nnz() const { return static_cast<std::int64_t>(rows.size()); }
};

// What a problem asks of the integrator at an event or after a step.
struct StepAction {
  enum class Kind {
    Continue,  // nothing changed
    Restart,   // y (and y') were changed at t: reinitialise the integrator there
    Fail,      // stop the run as failed, with message
  };
  Kind kind = Kind::Continue;
  double restart_step = 0.0;  // first step after a restart; 0 = the integrator's own estimate
  std::string message;        // for Fail: why, in the user's words
  bool projected = false;     // the restart is a projection onto the constraints (counted)
  // A bridge (a mechanism's singular pose): > t when the problem has moved
  // the state from the accepted step at t to bridge_to without the
  // integrator (y, y' are at bridge_to); the driver emits the output grid
  // inside from bridged_state(), records the landing as a step of order 0
  // and restarts there.
  double bridge_to = 0.0;

  static StepAction proceed() { return {}; }
  // After a projection at a step of size h: IDA keeps no memory across the
  // restart, so the step size is carried over; the order and the history are lost.
  static StepAction restart_after_projection(double h) {
    StepAction a;
    a.kind = Kind::Restart;
    a.restart_step = h;
    a.projected = true;
    return a;
  }
};

// Receives the problem's own events as they happen (chart switches,
// projections), so a recorder can write them; the driver only forwards.
struct EventNote {
  double t = 0.0;
  std::string what;   // "chart_switch" or "projection"
  std::string body;   // the body concerned, "" for a single body
  std::string from, to;
  double margin = 0.0;            // chart margin where it was left
  double drift_position = 0.0;    // before a projection
  double drift_velocity = 0.0;

  // A projection at t, with the drift just before it.
  static EventNote projection(double t, double drift_position, double drift_velocity) {
    EventNote e;
    e.t = t;
    e.what = "projection";
    e.drift_position = drift_position;
    e.drift_velocity = drift_velocity;
    return e;
  }
  // A mechanism event at t (singular_pose, branch_switch) at the joints named.
  static EventNote at_joints(double t, std::string what, std::string joints, double margin) {
    EventNote e;
    e.t = t;
    e.what = std::move(what);
    e.body = std::move(joints);
    e.margin = margin;
    return e;
  }
};

class DaeProblem {
 public:
  virtual ~DaeProblem() = default;

  virtual int size() const = 0;
  // Unknowns [0, state_size()) are the state (positions and velocities:
  // differential in the mathematics, even where differential_id() marks
  // some 0 to leave them out of the error test); the rest are multipliers.
  // The driver's first-step estimate measures y'' on the state only.
  virtual int state_size() const = 0;

  // A consistent (y, y') at t0 (the residual vanishes to round-off). May
  // record events (a chart chosen at the start) through take_events().
  virtual void initial_state(double t0, Eigen::VectorXd& y, Eigen::VectorXd& yp) = 0;
  // Keeps the differential part of y and recomputes the algebraic part and
  // y' consistently at t (used for the first-step estimate).
  virtual void make_consistent(double t, Eigen::VectorXd& y, Eigen::VectorXd& yp) = 0;

  // 1 for differential unknowns, 0 for algebraic ones (size()).
  virtual void differential_id(Eigen::Ref<Eigen::VectorXd> id) const = 0;
  // Whether id-0 unknowns leave the error test (index 2 and above).
  virtual bool suppress_algebraic_error_test() const = 0;
  // Per-unknown absolute tolerances from the user's (rtol, atol) and the start y0.
  virtual void absolute_tolerances(double rtol, double atol, const Eigen::VectorXd& y0,
                                   Eigen::Ref<Eigen::VectorXd> out) const = 0;
  // How many unknowns the residual holds at a fixed value (a mechanism's
  // multipliers of rows set aside, lambda_r = 0). IDA's norms are root mean
  // squares over all size() unknowns: the driver scales its weights by
  // sqrt(size() / (size() - held)) so that these do not loosen its tests.
  virtual int held_unknowns() const { return 0; }

  // The hot path. Allocates nothing. Returns false when F is not finite
  // (the integrator then retries with a smaller step).
  virtual bool residual(double t, const double* y, const double* yp, double* F) = 0;
  // Exact dF/dy + cj dF/dy', dense column-major into J (zeroed by the callee).
  // (Difference-quotient matrices are the driver's: it differences residual().)
  virtual void iteration_matrix_dense(double t, double cj, const double* y, const double* yp, double* J) = 0;
  // The iteration matrix's structural pattern (fixed for the run).
  virtual const SparsityPattern& sparsity() const = 0;
  // The same matrix's values in sparsity()'s order.
  virtual void iteration_matrix_sparse(double t, double cj, const double* y, const double* yp, double* values) = 0;

  // Root functions: the integrator stops where one crosses zero.
  virtual int event_count() const { return 0; }
  virtual void event_functions(double /*t*/, const double* /*y*/, double* /*g*/) {}
  // At a root found by the integrator, with (y, y') there; h is the size
  // of the last step taken (for messages).
  virtual StepAction on_event(double /*t*/, double /*h*/, Eigen::VectorXd& /*y*/, Eigen::VectorXd& /*yp*/) {
    return {};
  }
  // After every accepted step of size h (projection, chart checks). Not
  // called at the end time. A restart that keeps the step size returns
  // restart_step = h.
  virtual StepAction after_step(double /*t*/, double /*h*/, Eigen::VectorXd& /*y*/, Eigen::VectorXd& /*yp*/) {
    return {};
  }

  // A time the next step must not pass (the approach to a mechanism's
  // singular pose, which after_step then bridges); +inf: none. Read after
  // every accepted step.
  virtual double stop_time_hint() const { return std::numeric_limits<double>::infinity(); }
  // Inside the last bridge (t, bridge_to]: the state at t (size()), for the
  // output grid.
  virtual void bridged_state(double /*t*/, Eigen::VectorXd& /*y*/) {}

  // Events that happened since the last call (chart switches, projections), oldest first.
  virtual std::vector<EventNote> take_events() { return {}; }

  // Residual evaluations the problem spent itself (difference Jacobians).
  virtual long own_residual_evaluations() const { return 0; }

  // When the step size has collapsed below the floor (SolverSettings::
  // min_step_fraction) at (t, y): what the problem knows about why, in the
  // user's words (its formulation; for a mechanism the joints whose rows
  // lost rank), appended to the failure message. "" says nothing.
  virtual std::string describe_stall(double /*t*/, const double* /*y*/) { return ""; }
};

}  // namespace rigidae
