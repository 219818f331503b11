// Index 2: the velocity-level constraint only.
//
// Force kind (Lagrange form):  q' = v,  M v' = f - G^T lambda,  G v = 0.
// Kinematic kind (Euler form): q' = N v - Phi_q^T mu,  M v' = f,
//                              Phi_q q' = 0  (d/dt Phi = 0; index 1 here).
// The position level Phi = 0 is not enforced: it drifts, in the Force kind
// about linearly in time (the integral of the velocity-level residual).
#include "factories.hpp"

namespace rigidae::schemes {

namespace {

class Index2Scheme final : public ConstraintScheme {
 public:
  std::string name() const override { return "index2"; }
  // Force: lambda rows G v. Kinematic: mu rows Phi_q q'.
  SchemeRows rows() const override {
    return {{true, false, {0.0, 1.0, 0.0}, {}}, {false, true, {}, {0.0, 1.0, 0.0}}};
  }
  std::string constrained_note(const Representation& rep) const override {
    if (rep.constraint_kind() == ConstraintKind::Kinematic)
      return "in the Euler form the velocity level is d/dt Phi = Phi_q q' = 0, which fixes mu algebraically "
             "(index 1 in this form)";
    return {};
  }
};

}  // namespace

std::unique_ptr<ConstraintScheme> make_index2(const SchemeSettings& /*settings*/) { return std::make_unique<Index2Scheme>(); }

}  // namespace rigidae::schemes
