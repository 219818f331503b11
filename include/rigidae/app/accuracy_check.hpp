#pragma once
// The accuracy check every run gets: the quantities the scene conserves,
// measured at every step, against what the tolerance allows.
//
// A run can meet IDA's local error test at every step and still be wrong by
// pi rad at the end (a body near its intermediate axis, where a small error
// in energy or momentum moves every flip). Nothing in the run knows the true
// solution, but the invariants are known: for a single rigid body under
// gravity the energy E is conserved, so is the angular momentum L_W when no
// torque acts (a free body about its centre of mass, or a top with g = 0 or
// its centre of mass at the pivot), and else its component along gravity;
// the constraints Phi(q) = 0 and d/dt Phi = 0 hold on the exact solution.
//
// Measures (all dimensionless, maxima over the accepted steps):
//   energy                 |E - E0| / E_s,     E_s = T0 + m |g| |c|
//   angular_momentum       |L_W - L_W0| / L_s, L_s = sqrt(2 J_max E_s)
//   vertical_angular_momentum  |Lz - Lz0| / L_s   (when only Lz is conserved)
//   constraint_position    |Phi(q)|            (Phi is dimensionless here)
//   constraint_velocity    |dPhi/dt| / w_s,    w_s = sqrt(2 E_s / J_min)
// E_s is the largest energy the motion can exchange between kinetic and
// potential form (so a potential's arbitrary zero does not matter), L_s the
// largest momentum that energy allows, w_s the largest angular speed.
// The tolerance a measure is compared with is
//   tau = rtol + atol / min(1, w_s),
// the relative accuracy IDA's error test asks of the least well scaled
// differential unknown (coordinates are O(1), angular velocities O(w_s)).
// A measure above its limit gives a warning; the run's status is untouched.
// Limits, for N accepted steps (accuracy_check.cpp says why):
//   energy and momenta     2 tau sqrt(N)   (a random walk of per-step errors)
//   constraints            10 tau N        (10 tau of drift per step)
// Scenes with several bodies (schema 2) get the same check with their own
// measures and scales: app/multibody_accuracy_check.hpp.
#include <memory>
#include <string>
#include <vector>

#include "rigidae/multibody/one_body_view.hpp"
#include "rigidae/model/scene.hpp"
#include "rigidae/record/recorder.hpp"
#include "rigidae/solver/ida_driver.hpp"

namespace rigidae {

struct AccuracyWarning {
  std::string quantity;  // one of the measure names above
  double drift = 0.0;    // the measure's maximum
  double limit = 0.0;    // the limit it passed (factor x tolerance)
  double factor = 0.0;   // limit / tolerance (2 sqrt(N) or 10 N)
  double tolerance = 0.0;
  std::string message;   // one line for a person
};

// The largest drifts of a run, by measure; NaN for a measure not checked.
struct InvariantDrifts {
  double energy, angular_momentum, vertical_angular_momentum, constraint_position, constraint_velocity;
  double tolerance;
};

// The accuracy check of a run: a StepSink in front of the run's sinks (the
// recorder first) that forwards everything and measures each accepted step.
class RunMonitor : public StepSink {
 public:
  virtual const InvariantDrifts& drifts() const = 0;
  virtual std::vector<AccuracyWarning> warnings() const = 0;
  virtual long steps() const = 0;
  // Where the measures are defined (summary.json's accuracy_check.definitions).
  virtual std::string definitions() const = 0;
};

// The check of the run of `system` whose records `recorder` keeps: a single
// body's (below) when the records read the system as one body, else a
// mechanism's (app/multibody_accuracy_check.hpp). `next` gets everything
// (the recorder, or a sink in front of it).
std::unique_ptr<RunMonitor> make_run_monitor(multibody::MultibodyProblem& system, const Scene& scene,
                                             const RunRecorder& recorder, StepSink& next);

// A single body's check: reads each step's observation back from the
// recorder (no second evaluation).
class InvariantMonitor final : public RunMonitor {
 public:
  InvariantMonitor(const OneBodyView& problem, const Scene& scene, const RunRecorder& recorder, StepSink& next);

  void on_step(double t, double h, int order, const Eigen::VectorXd& y) override;
  void on_output(double t, const Eigen::VectorXd& y) override { next_.on_output(t, y); }
  void on_event(const EventNote& note) override { next_.on_event(note); }

  const InvariantDrifts& drifts() const override { return d_; }
  std::vector<AccuracyWarning> warnings() const override;
  long steps() const override { return steps_; }
  std::string definitions() const override {
    return "maxima over the steps; see include/rigidae/app/accuracy_check.hpp";
  }

 private:
  const RunRecorder& recorder_;
  StepSink& next_;
  const RigidBodyModel& body_;
  bool full_momentum_, constrained_;
  double e0_, e_scale_, l_scale_, w_scale_;
  Vec3 L0_W_;
  double lz0_;
  InvariantDrifts d_;
  long steps_ = 0;
};

// What each measure is, in words, for the warning messages.
struct DriftMeanings {
  std::string energy, angular_momentum, vertical_angular_momentum, constraint_position, constraint_velocity;
};
// The warnings for the drifts of N accepted steps against the limits above
// (2 tau sqrt(N) for invariants, 10 tau N for constraints); a NaN measure is not checked.
std::vector<AccuracyWarning> drift_warnings(const InvariantDrifts& d, long steps, const DriftMeanings& what);

// The warnings as one short text for a table cell ("energy 3.1e+03 tau;
// angular_momentum ..."), empty when there are none.
std::string warnings_cell(const std::vector<AccuracyWarning>& w);

}  // namespace rigidae
