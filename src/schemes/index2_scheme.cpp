// Index 2: the velocity-level constraint only.
//
// Force kind (Lagrange form):  q' = v,  M v' = f - G^T lambda,  G v = 0.
// Kinematic kind (Euler form): q' = N v - Phi_q^T mu,  M v' = f,
//                              Phi_q q' = 0  (d/dt Phi = 0; index 1 here).
// The position level Phi = 0 is not enforced: it drifts, in the Force kind
// about linearly in time (the integral of the velocity-level residual).
#include "factories.hpp"
#include "jacobian_rows.hpp"
#include "scheme_rows.hpp"

namespace rigidae::schemes {

namespace {

class Index2Scheme final : public ConstraintScheme {
 public:
  std::string name() const override { return "index2"; }
  UnknownLayout layout(const Representation& rep) const override { return single_level_layout(rep); }
  bool suppress_multiplier_error_test() const override { return true; }
  std::string constrained_note(const Representation& rep) const override {
    if (rep.constraint_kind() == ConstraintKind::Kinematic)
      return "in the Euler form the velocity level is d/dt Phi = Phi_q q' = 0, which fixes mu algebraically "
             "(index 1 in this form)";
    return {};
  }

  void residual(const StandardTerms& t, const UnknownLayout& lay, const ConstVecRef& y, const ConstVecRef& yp,
                VecRef F) const override {
    kinematic_rows(t, lay, y, yp, F);
    dynamic_rows(t, lay, y, yp, F);
    if (lay.n_lambda + lay.n_mu > 0) velocity_level_rows(t, lay, y, yp, constraint_rows(lay, F));
  }

  void iteration_matrix(const JacobianInputs& in, IterationMatrixView& J) const override {
    add_kinematic_jacobian(in, J);
    add_dynamic_jacobian(in, J);
    if (in.lay.n_lambda + in.lay.n_mu > 0) add_velocity_level_jacobian(in, constraint_row(in.lay), 1.0, J);
  }
};

}  // namespace

std::unique_ptr<ConstraintScheme> make_index2(const SchemeSettings& /*settings*/) { return std::make_unique<Index2Scheme>(); }

}  // namespace rigidae::schemes
