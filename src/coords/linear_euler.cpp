// Linear coordinates (the 9 entries of R, row by row), Euler form.
//
//   R' = R hat(omega_B),   J omega_B' = tau(R) - omega_B x J omega_B.
// The six orthonormality conditions are kept by the kinematics on the
// manifold (d/dt R^T R = hat(w)^T R^T R + R^T R hat(w) = 0 when R^T R = I), so
// they take no force multiplier; a scheme adds -Phi_q^T mu to the kinematic
// rows instead. Unknowns: r (9), omega_B (3).
#include "coordinate_maps.hpp"
#include "euler_form_rate.hpp"
#include "factories.hpp"
#include "rigid_body_derivatives.hpp"

namespace rigidae::coords {

namespace {

// R' = R hat(w): row i of R' is r_i x w. R^T g = sum_i g_i r_i.
struct LinearKinematics {
  static constexpr int kNq = 9;
  static void rate(const double* r, const Vec3& w, double* rdot) {
    for (int i = 0; i < 3; ++i) Eigen::Map<Vec3>(rdot + 3 * i) = Eigen::Map<const Vec3>(r + 3 * i).cross(w);
  }
  static Vec3 gravity_in_body(const double* r, const Vec3& g) {
    return g(0) * Eigen::Map<const Vec3>(r) + g(1) * Eigen::Map<const Vec3>(r + 3) + g(2) * Eigen::Map<const Vec3>(r + 6);
  }
};

class LinearEuler final : public Representation {
 public:
  explicit LinearEuler(const RigidBodyModel& body) : body_(body), rate_(body) {}

  std::string name() const override { return "linear/euler"; }
  int nq() const override { return 9; }
  int nv() const override { return 3; }
  int nc() const override { return 6; }
  ConstraintKind constraint_kind() const override { return ConstraintKind::Kinematic; }
  std::vector<std::string> constraint_names() const override { return {"c11", "c12", "c13", "c22", "c23", "c33"}; }

  void evaluate(double /*t*/, const VecQ& q, const VecV& v, StandardTerms& out) const override {
    const Mat3 R = rows_to_matrix(q);
    const Vec3 w = v.head<3>();
    matrix_to_rows(R * so3::hat(w), out.qdot);
    out.M = body_.J_B;
    out.f = body_.gravity_torque_B(R) - w.cross(body_.J_B * w);
    orthonormality_constraints(R, out.phi, out.phi_q);
  }

  // Row i of R' = R hat(w) is r_i^T hat(w), i.e. -hat(w) r_i = hat(r_i) w as a column.
  // tau = c x (m R^T g) with R^T g = sum_i g_i r_i: d tau/dr_i = m g_i hat(c).
  void differentiate(double /*t*/, const VecQ& q, const VecV& v, const VecV& /*a*/,
                     TermDerivatives& out) const override {
    const Vec3 w = v.head<3>();
    const Mat3 hat_w = so3::hat(w);
    const Mat3 hat_c = so3::hat(body_.c_B);
    out.qdot_q.setZero(9, 9);
    out.N.resize(9, 3);
    out.f_q.resize(3, 9);
    for (int i = 0; i < 3; ++i) {
      out.qdot_q.block<3, 3>(3 * i, 3 * i) = -hat_w;
      out.N.block<3, 3>(3 * i, 0) = so3::hat(q.segment<3>(3 * i));
      out.f_q.block<3, 3>(0, 3 * i) = (body_.mass * body_.gravity_W(i)) * hat_c;
    }
    out.Ma_q.setZero(3, 9);  // M = J
    out.f_v = gyroscopic_derivative(body_, w);
    out.gamma_q.resize(0, 9);
    out.gamma_v.resize(0, 3);
  }
  void constraint_hessian_weighted(const VecQ& /*q*/, const VecC& m, MatQQ& out) const override {
    orthonormality_hessian_weighted(m, out);
  }
  void constraint_hessian_applied(const VecQ& /*q*/, const VecQ& w, MatCQ& out) const override {
    orthonormality_hessian_applied(w, out);
  }

  void from_physical(const Mat3& R_WB, const Vec3& omega_B, VecQ& q, VecV& v) const override {
    matrix_to_rows(R_WB, q);
    v = omega_B;
  }
  Vec4 orientation(const VecQ& q) const override {
    return so3::matrix_to_quaternion(so3::nearest_rotation(rows_to_matrix(q)));
  }
  Mat3 placement(const VecQ& q) const override { return rows_to_matrix(q); }
  Vec3 body_angular_velocity(const VecQ& /*q*/, const VecV& v) const override { return v.head<3>(); }
  void project_coordinates(VecQ& q) const override { matrix_to_rows(so3::nearest_rotation(rows_to_matrix(q)), q); }
  const EulerFormRate* euler_form_rate() const override { return &rate_; }

 private:
  RigidBodyModel body_;
  EulerFormRateOf<LinearKinematics> rate_;
};

}  // namespace

std::unique_ptr<Representation> make_linear_euler(const RigidBodyModel& body, const so3::EulerSequence& /*start_chart*/) {
  return std::make_unique<LinearEuler>(body);
}

}  // namespace rigidae::coords
