// Linear coordinates (the 9 entries of R, row by row), Lagrange form.
//
// Placement x = R X, so T = 1/2 sum_i row_i'^T E row_i': a constant mass
// matrix M = blockdiag(E, E, E). The potential -m g^T R c is linear in r:
// the generalized gravity force is constant, block i = m g_i c. No velocity
// terms. Six constraints c_j . c_k = delta_jk (columns of R, j <= k), held by
// six force multipliers; G = Phi_q, gamma = -2 (R'^T R')_jk.
// Unknowns: r (9), v = r' (9).
#include "coordinate_maps.hpp"
#include "factories.hpp"

namespace rigidae::coords {

namespace {

class LinearLagrange final : public Representation {
 public:
  explicit LinearLagrange(const RigidBodyModel& body) : body_(body) {
    M_.setZero(9, 9);
    f_.resize(9);
    for (int i = 0; i < 3; ++i) {
      M_.block<3, 3>(3 * i, 3 * i) = body.E_B;
      f_.segment<3>(3 * i) = body.mass * body.gravity_W(i) * body.c_B;
    }
  }

  std::string name() const override { return "linear/lagrange"; }
  int nq() const override { return 9; }
  int nv() const override { return 9; }
  int nc() const override { return 6; }
  ConstraintKind constraint_kind() const override { return ConstraintKind::Force; }
  std::vector<std::string> constraint_names() const override { return {"c11", "c12", "c13", "c22", "c23", "c33"}; }

  void evaluate(double /*t*/, const VecQ& q, const VecV& v, StandardTerms& out) const override {
    out.qdot = v;
    out.M = M_;
    out.f = f_;
    orthonormality_constraints(rows_to_matrix(q), out.phi, out.phi_q);
    out.G = out.phi_q;
    orthonormality_gamma(rows_to_matrix(v), out.gamma);
  }

  // Constant M and f; only gamma = -2 (V^T V)_jk depends on the state:
  // it is -2 times the constraints' quadratic form at V, so gamma_v = -2 Phi_q(V).
  void differentiate(double /*t*/, const VecQ& /*q*/, const VecV& v, const VecV& /*a*/,
                     TermDerivatives& out) const override {
    out.qdot_q.setZero(9, 9);
    out.N.setIdentity(9, 9);
    out.Ma_q.setZero(9, 9);
    out.f_q.setZero(9, 9);
    out.f_v.setZero(9, 9);
    out.gamma_q.setZero(6, 9);
    VecC phi_unused;
    orthonormality_constraints(rows_to_matrix(v), phi_unused, out.gamma_v);
    out.gamma_v *= -2.0;
  }
  void constraint_hessian_weighted(const VecQ& /*q*/, const VecC& m, MatQQ& out) const override {
    orthonormality_hessian_weighted(m, out);
  }
  void constraint_hessian_applied(const VecQ& /*q*/, const VecQ& w, MatCQ& out) const override {
    orthonormality_hessian_applied(w, out);
  }

  void from_physical(const Mat3& R_WB, const Vec3& omega_B, VecQ& q, VecV& v) const override {
    matrix_to_rows(R_WB, q);
    matrix_to_rows(R_WB * so3::hat(omega_B), v);
  }
  Vec4 orientation(const VecQ& q) const override {
    return so3::matrix_to_quaternion(so3::nearest_rotation(rows_to_matrix(q)));
  }
  Mat3 placement(const VecQ& q) const override { return rows_to_matrix(q); }
  Vec3 body_angular_velocity(const VecQ& q, const VecV& v) const override {
    // R^T R' = hat(omega_B) on the manifold; off it, take the skew part.
    const Mat3 A = rows_to_matrix(q).transpose() * rows_to_matrix(v);
    return so3::vee(A);
  }
  void project_coordinates(VecQ& q) const override { matrix_to_rows(so3::nearest_rotation(rows_to_matrix(q)), q); }

 private:
  RigidBodyModel body_;
  MatVV M_;  // constant
  VecV f_;   // constant
};

}  // namespace

std::unique_ptr<Representation> make_linear_lagrange(const RigidBodyModel& body, const so3::EulerSequence& /*start_chart*/) {
  return std::make_unique<LinearLagrange>(body);
}

}  // namespace rigidae::coords
