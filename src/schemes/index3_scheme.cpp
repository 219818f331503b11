// Index 3: the position constraint as it is.
//
// Force kind (Lagrange form):  q' = v,  M v' = f - G^T lambda,  Phi(q) = 0.
// lambda is index 3 and v index 2. BDF converges on such systems only if
// both leave the error test (Brenan, Campbell & Petzold, ch. 3), and the
// iteration matrix has condition ~ 1/h^3, so Newton fails once h is small:
// at tight tolerances this scheme is expected to fail, and reports so.
// Kinematic kind (Euler form): the constraint enters through the
// kinematics, q' = N v - Phi_q^T mu, Phi(q) = 0: one differentiation fixes
// mu, so the system is index 2, with the same rows as ggl.
#include "factories.hpp"

namespace rigidae::schemes {

namespace {

class Index3Scheme final : public ConstraintScheme {
 public:
  std::string name() const override { return "index3"; }
  // Force: lambda rows Phi. Kinematic: mu rows Phi.
  SchemeRows rows() const override {
    return {{true, false, {1.0, 0.0, 0.0}, {}}, {false, true, {}, {1.0, 0.0, 0.0}}};
  }
  bool suppress_velocity_error_test(ConstraintKind kind) const override { return kind == ConstraintKind::Force; }
  std::string constrained_note(const Representation& rep) const override {
    if (rep.constraint_kind() == ConstraintKind::Kinematic)
      return "in the Euler form the position constraint acts through the kinematics (q' = N v - Phi_q^T mu): "
             "the system is index 2, with the same rows as ggl";
    return "index 3: v (index 2) and lambda (index 3) are left out of IDA's error test; the iteration matrix "
           "has condition ~1/h^3, so Newton may fail at small steps";
  }
};

}  // namespace

std::unique_ptr<ConstraintScheme> make_index3(const SchemeSettings& /*settings*/) { return std::make_unique<Index3Scheme>(); }

}  // namespace rigidae::schemes
