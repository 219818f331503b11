// Index 1: the constraints differentiated down to index one.
//
// Force kind (Lagrange form): the acceleration level
//   q' = v,  M v' = f - G^T lambda,  G v' = gamma(q, v).
// Neither Phi nor G v is
// enforced: both drift, the position level about quadratically in time.
// Kinematic kind (Euler form): the constraint is already kept by the
// kinematics at the velocity level, so index 1 means d/dt Phi = 0:
//   q' = N v - Phi_q^T mu,  M v' = f,  Phi_q q' = 0,
// which fixes mu (zero on the manifold) and lets Phi drift with the
// integration error only.
#include "factories.hpp"
#include "scheme_rows.hpp"

namespace rigidae::schemes {

namespace {

class Index1Scheme final : public ConstraintScheme {
 public:
  std::string name() const override { return "index1"; }
  UnknownLayout layout(const Representation& rep) const override {
    const bool force = rep.constraint_kind() == ConstraintKind::Force;
    return {rep.nq(), rep.nv(), force ? rep.nc() : 0, force ? 0 : rep.nc()};
  }
  bool suppress_multiplier_error_test() const override { return true; }

  void residual(const StandardTerms& t, const UnknownLayout& lay, const ConstVecRef& y, const ConstVecRef& yp,
                VecRef F) const override {
    kinematic_rows(t, lay, y, yp, F);
    dynamic_rows(t, lay, y, yp, F);
    if (lay.n_lambda > 0) {
      F.segment(lay.lambda_offset(), lay.n_lambda).noalias() = t.G * yp.segment(lay.v_offset(), lay.nv);
      F.segment(lay.lambda_offset(), lay.n_lambda) -= t.gamma;
    }
    if (lay.n_mu > 0)
      F.segment(lay.mu_offset(), lay.n_mu).noalias() = t.phi_q * yp.segment(lay.q_offset(), lay.nq);
  }
};

}  // namespace

std::unique_ptr<ConstraintScheme> make_index1(const Scene& /*scene*/) { return std::make_unique<Index1Scheme>(); }

}  // namespace rigidae::schemes
