// GGL: the stabilized index-2 form of Gear, Gupta and Leimkuhler (1985).
//
// Force kind (Lagrange form):          Kinematic kind (Euler form):
//   q' = v - Phi_q^T mu                  q' = N v - Phi_q^T mu
//   M v' = f - G^T lambda                M v' = f
//   G v = 0                              Phi(q) = 0
//   Phi(q) = 0
// Both constraint levels hold to the Newton tolerance at every step; mu = 0
// on the exact solution. lambda and mu are index 2: they leave IDA's error
// test (IDASetSuppressAlg), as index-2 BDF theory requires.
#include "factories.hpp"
#include "jacobian_rows.hpp"
#include "scheme_rows.hpp"

namespace rigidae::schemes {

namespace {

class GglScheme final : public ConstraintScheme {
 public:
  std::string name() const override { return "ggl"; }
  UnknownLayout layout(const Representation& rep) const override {
    const bool force = rep.constraint_kind() == ConstraintKind::Force;
    return {rep.nq(), rep.nv(), force ? rep.nc() : 0, rep.nc()};
  }
  bool suppress_multiplier_error_test() const override { return true; }

  void residual(const StandardTerms& t, const UnknownLayout& lay, const ConstVecRef& y, const ConstVecRef& yp,
                VecRef F) const override {
    kinematic_rows(t, lay, y, yp, F);
    dynamic_rows(t, lay, y, yp, F);
    if (lay.n_lambda > 0)
      F.segment(lay.lambda_offset(), lay.n_lambda).noalias() = t.G * y.segment(lay.v_offset(), lay.nv);
    if (lay.n_mu > 0) F.segment(lay.mu_offset(), lay.n_mu) = t.phi;
  }

  void iteration_matrix(const JacobianInputs& in, IterationMatrixView& J) const override {
    add_kinematic_jacobian(in, J);
    add_dynamic_jacobian(in, J);
    if (in.lay.n_lambda > 0) add_velocity_level_jacobian(in, in.lay.lambda_offset(), 1.0, J);
    if (in.lay.n_mu > 0) add_position_level_jacobian(in, in.lay.mu_offset(), 1.0, J);
  }
};

}  // namespace

std::unique_ptr<ConstraintScheme> make_ggl(const SchemeSettings& /*settings*/) { return std::make_unique<GglScheme>(); }

}  // namespace rigidae::schemes
