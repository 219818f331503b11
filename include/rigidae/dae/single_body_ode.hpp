#pragma once
// The single rigid body as an ODE x' = f(t, x), x = (q, v), for CVODE and
// ARKODE, built on a DaeSystem's public API (its representation).
//
//   q' = N(q) v
//   Euler form (and Euler angles): M v' = f          (the index-1 rows
//       without multipliers: the kinematics keeps |q| = 1, R^T R = I only
//       up to the integration error, which the projection removes)
//   Lagrange form with constraints: (v', lambda) from
//       [M  G^T] [v'    ]   [f    ]
//       [G  0  ] [lambda] = [gamma]
//     at every evaluation (Schur complement: M is positive definite).
//
// Invariants (when the representation has constraints): Phi(q) = 0, and in
// the Lagrange form also G v = 0. Projection: q to the nearest point of
// Phi = 0 (the representation's own: the normalised quaternion, the
// orthogonal polar factor of R), then v to G v = 0 in the metric of M.
// The recorded state is the DaeSystem's layout (q | v | lambda), lambda from
// the KKT solve at the recorded x. Euler-angle charts are events: at a root
// of margin - threshold the state is re-expressed in the most regular chart.
// The arithmetic of the right-hand side, the projection and its
// linearisation is schemes::BodyOde (schemes/body_ode.hpp), shared with the
// multibody ODE form's decoupled bodies.
#include <vector>

#include "rigidae/dae/chart_state.hpp"
#include "rigidae/dae/dae_system.hpp"
#include "rigidae/schemes/body_ode.hpp"
#include "rigidae/solver/ode_problem.hpp"

namespace rigidae {

class SingleBodyOde final : public OdeProblem, public ChartState {
 public:
  // dae: the scene's body with an acceleration-level scheme (index1 or
  // projection); it must outlive this object.
  SingleBodyOde(const DaeSystem& dae, const Scene& scene);

  // The chart the state is written in now (Euler angles), as in SingleBodyProblem.
  int chart() const override { return chart_; }
  const DaeSystem& system() const override { return dae_; }

  int size() const override { return nq_ + nv_; }
  void initial_state(double t0, Eigen::VectorXd& x) override;
  void absolute_tolerances(double rtol, double atol, const Eigen::VectorXd& x0,
                           Eigen::Ref<Eigen::VectorXd> out) const override;
  bool rhs(double t, const double* x, double* xdot) override;

  bool has_invariants() const override { return nc_ > 0; }
  OdeDrift drift(double t, const double* x) const override;
  void project(double t, double* x) override;
  void project_error(double t, const double* x, double* e) override;

  int observed_size() const override { return dae_.size(); }
  void observe(double t, const double* x, Eigen::VectorXd& y) override;

  int event_count() const override;
  void event_functions(double t, const double* x, double* g) override;
  StepAction on_event(double t, Eigen::VectorXd& x) override;
  std::vector<EventNote> take_events() override;
  // The formulation that stalled, for the step-size floor's message.
  std::string describe_stall(double /*t*/, const double* /*y*/) override {
    return "Formulation: " + representation().name() + " with scheme " + dae_.scheme().name() + ".";
  }

 private:
  const Representation& rep() const { return representation(); }
  // Re-expresses x at t in the most regular chart; notes the switch. False if the chart stayed.
  bool change_chart(double t, Eigen::VectorXd& x);

  const DaeSystem& dae_;
  int chart_;  // the run's state besides x: the current chart
  const Scene& scene_;
  int nq_ = 0, nv_ = 0, nc_ = 0;
  bool force_ = false;
  schemes::BodyOde body_;  // the one-body arithmetic (rhs, projection)
  std::vector<EventNote> notes_;
};

}  // namespace rigidae
