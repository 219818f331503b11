// Baumgarte (1972): index 1 with feedback on the drift.
//
// Force kind (Lagrange form): the acceleration level with the constraint's
// own error fed back,
//   q' = v,  M v' = f - G^T lambda,  G v' = gamma - 2 a G v - b^2 Phi,
// so that Phi'' + 2 a Phi' + b^2 Phi = 0: drift decays instead of growing.
// Kinematic kind (Euler form): the constraint is first order in time here
// (its velocity level is kept by the kinematics), so the feedback is
//   q' = N v - Phi_q^T mu,  M v' = f,  Phi_q q' = -a Phi,
// i.e. Phi' + a Phi = 0, the decay rate of the critically damped law above.
#include <fmt/format.h>

#include "factories.hpp"
#include "jacobian_rows.hpp"
#include "scheme_rows.hpp"

namespace rigidae::schemes {

namespace {

class BaumgarteScheme final : public ConstraintScheme {
 public:
  BaumgarteScheme(double a, double b) : a_(a), b_(b) {}

  std::string name() const override { return "baumgarte"; }
  UnknownLayout layout(const Representation& rep) const override { return single_level_layout(rep); }
  bool suppress_multiplier_error_test() const override { return true; }
  std::vector<SchemeParameter> parameters() const override { return {{"a", a_}, {"b", b_}}; }
  std::string constrained_note(const Representation& rep) const override {
    if (rep.constraint_kind() == ConstraintKind::Kinematic)
      return fmt::format("first-order feedback Phi' + a Phi = 0 with a = {:g} 1/s (b is not used in the Euler form)",
                         a_);
    return fmt::format("feedback Phi'' + 2 a Phi' + b^2 Phi = 0 with a = {:g} 1/s, b = {:g} 1/s", a_, b_);
  }

  void residual(const StandardTerms& t, const UnknownLayout& lay, const ConstVecRef& y, const ConstVecRef& yp,
                VecRef F) const override {
    kinematic_rows(t, lay, y, yp, F);
    dynamic_rows(t, lay, y, yp, F);
    if (lay.n_lambda > 0) {
      auto rows = F.segment(lay.lambda_offset(), lay.n_lambda);
      acceleration_level_rows(t, lay, yp, rows);
      rows.noalias() += (2.0 * a_) * (t.G * y.segment(lay.v_offset(), lay.nv));
      rows += (b_ * b_) * t.phi;
    } else if (lay.n_mu > 0) {
      auto rows = F.segment(lay.mu_offset(), lay.n_mu);
      velocity_level_rows(t, lay, y, yp, rows);
      rows += a_ * t.phi;
    }
  }

  void iteration_matrix(const JacobianInputs& in, IterationMatrixView& J) const override {
    add_kinematic_jacobian(in, J);
    add_dynamic_jacobian(in, J);
    if (in.lay.n_lambda > 0) {
      const int row = in.lay.lambda_offset();
      add_acceleration_level_jacobian(in, row, J);
      add_velocity_level_jacobian(in, row, 2.0 * a_, J);
      add_position_level_jacobian(in, row, b_ * b_, J);
    } else if (in.lay.n_mu > 0) {
      const int row = in.lay.mu_offset();
      add_velocity_level_jacobian(in, row, 1.0, J);
      add_position_level_jacobian(in, row, a_, J);
    }
  }

 protected:
  VecC acceleration_target(const StandardTerms& t, const ConstVecRef& v) const override {
    return t.gamma - (2.0 * a_) * (t.G * v) - (b_ * b_) * t.phi;
  }
  VecC rate_target(const StandardTerms& t) const override { return -a_ * t.phi; }

 private:
  double a_, b_;
};

}  // namespace

std::unique_ptr<ConstraintScheme> make_baumgarte(const SchemeSettings& settings) {
  return std::make_unique<BaumgarteScheme>(settings.baumgarte_a, settings.baumgarte_b);
}

}  // namespace rigidae::schemes
