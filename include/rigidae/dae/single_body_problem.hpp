#pragma once
// One rigid body's DAE as the integrator sees it (solver/problem.hpp).
//
// Adds to DaeSystem what a run needs beyond the equations: the start from a
// physical state, the Euler-angle charts (the start-of-run choice, the root
// function that watches the chart's margin, the switch at that root or the
// failure when switching is off) and the projection after a step that the
// scheme asks for. Events (chart switches, projections) are kept as notes
// for the driver to forward.
#include <string>
#include <vector>

#include "rigidae/dae/chart_state.hpp"
#include "rigidae/dae/dae_system.hpp"
#include "rigidae/solver/problem.hpp"

namespace rigidae {

class SingleBodyProblem final : public DaeProblem, public ChartState {
 public:
  // `source` names the scene in messages (its file, or "" when built in code).
  SingleBodyProblem(const DaeSystem& dae, const EulerChartSpec& charts, const Mat3& R0_WB, const Vec3& omega0_B,
                    std::string source);

  // The chart the state is written in now, and the representation in it.
  int chart() const override { return chart_; }
  const DaeSystem& system() const override { return dae_; }
  using ChartState::representation;

  int size() const override { return dae_.size(); }
  int state_size() const override { return dae_.layout().nq + dae_.layout().nv; }
  void initial_state(double t0, Eigen::VectorXd& y, Eigen::VectorXd& yp) override;
  void make_consistent(double t, Eigen::VectorXd& y, Eigen::VectorXd& yp) override {
    dae_.make_consistent(chart_, t, y, yp);
  }
  void differential_id(Eigen::Ref<Eigen::VectorXd> id) const override { id = dae_.differential_id(); }
  bool suppress_algebraic_error_test() const override { return dae_.scheme().suppress_multiplier_error_test(); }
  void absolute_tolerances(double rtol, double atol, const Eigen::VectorXd& y0,
                           Eigen::Ref<Eigen::VectorXd> out) const override;

  bool residual(double t, const double* y, const double* yp, double* F) override;
  void iteration_matrix_dense(double t, double cj, const double* y, const double* yp, double* J) override {
    dae_.iteration_matrix(chart_, t, cj, y, yp, J);
  }
  const SparsityPattern& sparsity() const override { return dae_.sparsity(); }
  void iteration_matrix_sparse(double t, double cj, const double* y, const double* yp, double* values) override {
    dae_.iteration_matrix_sparse(chart_, t, cj, y, yp, values);
  }

  // One root function where the representation has charts: margin - threshold.
  int event_count() const override { return dae_.representation().has_charts() ? 1 : 0; }
  void event_functions(double t, const double* y, double* g) override;
  StepAction on_event(double t, double h, Eigen::VectorXd& y, Eigen::VectorXd& yp) override;
  StepAction after_step(double t, double h, Eigen::VectorXd& y, Eigen::VectorXd& yp) override;
  std::vector<EventNote> take_events() override;
  // The formulation that stalled, for the step-size floor's message.
  std::string describe_stall(double /*t*/, const double* /*y*/) override {
    return "Formulation: " + representation().name() + " with scheme " + dae_.scheme().name() + ".";
  }

 private:
  // Re-expresses (y, y') at t in the most regular chart and makes it
  // consistent; notes the switch. False if the chart stayed.
  bool change_chart(double t, Eigen::VectorXd& y, Eigen::VectorXd& yp);

  const DaeSystem& dae_;
  int chart_;  // the run's state besides y: the current chart
  EulerChartSpec charts_;
  Mat3 R0_WB_;
  Vec3 omega0_B_;
  std::string source_;
  ProjectionPolicy projection_;
  std::vector<EventNote> events_;  // since the last take_events()
};

}  // namespace rigidae
