#pragma once
// The narrow view an explicit or multistep ODE integrator (CVODE, ARKODE)
// has of an assembled system: x' = f(t, x).
//
// Beside the right-hand side it offers what problem.hpp's DaeProblem offers
// (events, what to do at an event or after a step) and, when the ODE carries
// invariants (|q| = 1, R^T R = I, G v = 0 of an index-1 form), a projection
// onto them:
//   position level  q <- the nearest point of {Phi(q) = 0}
//   velocity level  v <- v - M^-1 G^T (G M^-1 G^T)^-1 G v   (mass metric)
// and its linearisation for an error vector (what CVODE asks so that its
// error estimate lives in the tangent space).
//
// What is recorded is the system's full state in the DAE layout
// (q | v | lambda | mu): observe() fills it, with the multipliers of the KKT
// solve, so the recorders of the DAE runs read ODE runs unchanged.
//
// Conventions: plain arrays of size() (x) or observed_size() (y).
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "rigidae/solver/problem.hpp"

namespace rigidae {

// Constraint residuals before a projection: |Phi| and |G v| (or |dPhi/dt|).
struct OdeDrift {
  double position = 0.0;
  double velocity = 0.0;
};

class OdeProblem {
 public:
  virtual ~OdeProblem() = default;

  virtual int size() const = 0;
  // The start x(t0) on the invariants.
  virtual void initial_state(double t0, Eigen::VectorXd& x) = 0;
  // Per-entry absolute tolerances from the user's (rtol, atol) and x0.
  virtual void absolute_tolerances(double rtol, double atol, const Eigen::VectorXd& x0,
                                   Eigen::Ref<Eigen::VectorXd> out) const = 0;

  // The hot path. Allocates nothing. Returns false when f is not finite
  // (the integrator retries with a smaller step).
  virtual bool rhs(double t, const double* x, double* xdot) = 0;

  // Invariants. has_invariants() false: the other three are never called.
  virtual bool has_invariants() const { return false; }
  virtual OdeDrift drift(double /*t*/, const double* /*x*/) const { return {}; }
  // Moves x onto the invariants (in place). Allocates nothing.
  virtual void project(double /*t*/, double* /*x*/) {}
  // Projects an error vector e at x onto the invariants' tangent space.
  virtual void project_error(double /*t*/, const double* /*x*/, double* /*e*/) {}

  // The state as recorded (the DAE layout), from x at t.
  virtual int observed_size() const = 0;
  virtual void observe(double t, const double* x, Eigen::VectorXd& y) = 0;

  // Root functions and what to do at a root (x may be changed: a restart).
  virtual int event_count() const { return 0; }
  virtual void event_functions(double /*t*/, const double* /*x*/, double* /*g*/) {}
  virtual StepAction on_event(double /*t*/, Eigen::VectorXd& /*x*/) { return {}; }
  // After every accepted step, at the step's end (before any projection):
  // bookkeeping that follows the motion (a mechanism's torsion angles); x is not changed.
  virtual void after_step(double /*t*/, const double* /*x*/) {}
  // The bridge across a mechanism's singular pose (DaeProblem's
  // stop_time_hint and after_step's bridge): a time the next step must not
  // pass (+inf: none); after an accepted step (recorded), bridge() may move x
  // from t to the landing time it returns (0: no bridge), and
  // bridged_observation() gives the recorded row inside (t, landing].
  virtual double stop_time_hint() const { return std::numeric_limits<double>::infinity(); }
  virtual double bridge(double /*t*/, Eigen::VectorXd& /*x*/) { return 0.0; }
  virtual void bridged_observation(double /*t*/, Eigen::VectorXd& /*y*/) {}
  // Events that happened since the last call (chart switches), oldest first.
  virtual std::vector<EventNote> take_events() { return {}; }
  // As DaeProblem::describe_stall: why the step size collapsed at (t, x), or "".
  virtual std::string describe_stall(double /*t*/, const double* /*x*/) { return ""; }
};

}  // namespace rigidae
