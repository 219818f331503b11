#pragma once
// The accuracy check of app/accuracy_check.hpp for a multibody run (schema 2):
// what the mechanism conserves, measured at every accepted step, against
// what the tolerance allows, with the same limits (2 tau sqrt(N) for an
// invariant, 10 tau N for a constraint).
//
// Measures (dimensionless, maxima over the accepted steps):
//   energy               |H - H0 - W| / E_s,  when the scene's energy balance
//                        is known: no spring damping, no torsional damping
//                        (gravity, undamped springs, undamped torsional springs
//                        and constant space-frame forces have a potential;
//                        ideal joints do no work). W(t) is the work done by
//                        the drivers and by the loads without a potential
//                        (torques, body-frame and time-dependent loads): the
//                        integral of their power P = sum_d tau_d theta_d' +
//                        sum_loads Q . v, by the quadrature below.
// The work's quadrature: multibody/work_integral.hpp (the polynomial through
// the last six values of P at the accepted steps).
//   constraint_position  max |Phi| / L    (the joints' and the bodies' own
//                        position rows; point rows are in m, angular rows in
//                        rad: dividing these by L too is conservative for L < 1 m)
//   constraint_velocity  max |G v| / v_s
// Scales, from the start:
//   L    the mechanism's size: the largest distance between two of the
//        bodies' centres of mass and the joints' ground points (at least 1 mm)
//   E_s  T0 + V_s0 + |g| L sum_i m_i  (kinetic energy, the springs' and
//        torsional springs' energy V_s0, plus the largest potential energy
//        gravity can exchange over the mechanism's size)
//   v_s  sqrt(2 E_s / sum_i m_i), the largest speed that energy allows
//   tau  rtol + atol / min(1, L, v_s), the relative accuracy IDA's error test
//        asks of the least well scaled differential unknown (positions O(L),
//        velocities O(v_s))
// Momenta are not checked (the ground's joints exert forces and torques).
#include <vector>

#include "rigidae/app/accuracy_check.hpp"
#include "rigidae/model/scene.hpp"
#include "rigidae/multibody/multibody_problem.hpp"
#include "rigidae/multibody/work_integral.hpp"
#include "rigidae/solver/ida_driver.hpp"

namespace rigidae {

// L above, m: the mechanism's length scale (also that of the verdict's
// position error, app/error_estimate.hpp).
double mechanism_size(const MultibodySpec& spec);

// A StepSink in front of the recorder (or of nothing, for a run that records
// nothing): forwards everything and measures each accepted step.
class MultibodyInvariantMonitor final : public RunMonitor {
 public:
  MultibodyInvariantMonitor(multibody::MultibodyProblem& problem, const Scene& scene, StepSink* next);

  void on_step(double t, double h, int order, const Eigen::VectorXd& y) override;
  void on_output(double t, const Eigen::VectorXd& y) override;
  void on_event(const EventNote& note) override {
    if (next_) next_->on_event(note);
  }

  const InvariantDrifts& drifts() const override { return d_; }
  std::vector<AccuracyWarning> warnings() const override;
  long steps() const override { return steps_; }
  std::string definitions() const override {
    return "maxima over the steps; see include/rigidae/app/multibody_accuracy_check.hpp";
  }

 private:
  multibody::MultibodyProblem& problem_;
  StepSink* next_;
  const Scene& scene_;
  bool conservative_, started_ = false;
  double size_ = 1.0, mass_ = 0.0, h0_ = 0.0, e_scale_ = 1.0, v_scale_ = 1.0;
  // The work W of the drivers and of the loads without a potential, and the
  // last values of their power (t, P), oldest first, for its quadrature.
  bool has_work_ = false;
  bool work_from_efforts_ = false;  // W sums the drivers' multipliers (a DAE run): see warnings()
  multibody::WorkIntegral work_;
  InvariantDrifts d_;
  long steps_ = 0;
};

}  // namespace rigidae
