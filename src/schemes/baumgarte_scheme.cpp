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

namespace rigidae::schemes {

namespace {

class BaumgarteScheme final : public ConstraintScheme {
 public:
  BaumgarteScheme(double a, double b) : a_(a), b_(b) {}

  std::string name() const override { return "baumgarte"; }
  // Force: lambda rows (G v' - gamma) + 2a G v + b^2 Phi. Kinematic: mu rows Phi_q q' + a Phi.
  SchemeRows rows() const override {
    return {{true, false, {b_ * b_, 2.0 * a_, 1.0}, {}}, {false, true, {}, {a_, 1.0, 0.0}}};
  }
  std::vector<SchemeParameter> parameters() const override { return {{"a", a_}, {"b", b_}}; }
  std::string constrained_note(const Representation& rep) const override {
    if (rep.constraint_kind() == ConstraintKind::Kinematic)
      return fmt::format("first-order feedback Phi' + a Phi = 0 with a = {:g} 1/s (b is not used in the Euler form)",
                         a_);
    return fmt::format("feedback Phi'' + 2 a Phi' + b^2 Phi = 0 with a = {:g} 1/s, b = {:g} 1/s", a_, b_);
  }

 private:
  double a_, b_;
};

}  // namespace

std::unique_ptr<ConstraintScheme> make_baumgarte(const SchemeSettings& settings) {
  return std::make_unique<BaumgarteScheme>(settings.baumgarte_a, settings.baumgarte_b);
}

}  // namespace rigidae::schemes
