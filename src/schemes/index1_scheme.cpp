// Index 1: the constraints differentiated down to index one.
//
// Force kind (Lagrange form): the acceleration level
//   q' = v,  M v' = f - G^T lambda,  G v' = gamma(q, v).
// Neither Phi nor G v is enforced: G v drifts about linearly in time and
// Phi about quadratically.
// Kinematic kind (Euler form): the kinematics already keep the constraint
// (Phi_q N = 0 on the manifold), so the index-1 form is the underlying ODE
//   q' = N v,  M v' = f
// with no multiplier at all; Phi drifts with the integration error only.
#include "factories.hpp"

namespace rigidae::schemes {

namespace {

class Index1Scheme final : public ConstraintScheme {
 public:
  std::string name() const override { return "index1"; }
  // Force: lambda rows G v' - gamma. Kinematic: no rows (the ODE).
  SchemeRows rows() const override { return {{true, false, {0.0, 0.0, 1.0}, {}}, {}}; }
  std::string constrained_note(const Representation& rep) const override {
    if (rep.constraint_kind() == ConstraintKind::Kinematic)
      return "in the Euler form the kinematics keep the constraint: index 1 is the ODE q' = N v, M v' = f, "
             "with no multiplier";
    return {};
  }
};

}  // namespace

std::unique_ptr<ConstraintScheme> make_index1(const SchemeSettings& /*settings*/) { return std::make_unique<Index1Scheme>(); }

}  // namespace rigidae::schemes
