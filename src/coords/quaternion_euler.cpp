// Unit quaternions, Euler form.
//
//   q' = 1/2 L(q) omega_B,   J omega_B' = tau(R(q)) - omega_B x J omega_B,
// with the constraint Phi = q^T q - 1 kept by the kinematics: Phi_q N =
// q^T L(q) = 0 for every q, so it takes no force multiplier; a scheme adds
// -Phi_q^T mu = -2 q mu to the kinematic rows instead.
// Unknowns: q (4), omega_B (3).
#include "coordinate_maps.hpp"
#include "euler_form_rate.hpp"
#include "factories.hpp"
#include "rigid_body_derivatives.hpp"

namespace rigidae::coords {

namespace {

// q' = 1/2 L(q) w = 1/2 (-v.w, s w + v x w) for q = (s, v); R(q)^T g of the
// homogeneous R(q) = (s^2 - v.v) I + 2 v v^T + 2 s hat(v).
struct QuaternionKinematics {
  static constexpr int kNq = 4;
  static void rate(const double* q, const Vec3& w, double* qdot) {
    const double s = q[0];
    const Vec3 v(q[1], q[2], q[3]);
    qdot[0] = -0.5 * v.dot(w);
    Eigen::Map<Vec3>(qdot + 1) = 0.5 * (s * w + v.cross(w));
  }
  static Vec3 gravity_in_body(const double* q, const Vec3& g) {
    const double s = q[0];
    const Vec3 v(q[1], q[2], q[3]);
    return (s * s - v.squaredNorm()) * g + (2.0 * v.dot(g)) * v - (2.0 * s) * v.cross(g);
  }
};

class QuaternionEuler final : public Representation {
 public:
  explicit QuaternionEuler(const RigidBodyModel& body) : body_(body), rate_(body) {}

  std::string name() const override { return "quaternion/euler"; }
  int nq() const override { return 4; }
  int nv() const override { return 3; }
  int nc() const override { return 1; }
  ConstraintKind constraint_kind() const override { return ConstraintKind::Kinematic; }
  std::vector<std::string> constraint_names() const override { return {"norm"}; }

  void evaluate(double /*t*/, const VecQ& q, const VecV& v, StandardTerms& out) const override {
    const Vec4 qq = q.head<4>();
    const Vec3 w = v.head<3>();
    out.qdot = 0.5 * quaternion_rate_map(qq) * w;
    out.M = body_.J_B;
    out.f = body_.gravity_torque_B(so3::quaternion_to_matrix(qq)) - w.cross(body_.J_B * w);
    out.phi.resize(1);
    out.phi(0) = qq.squaredNorm() - 1.0;
    out.phi_q = 2.0 * qq.transpose();
  }

  void differentiate(double /*t*/, const VecQ& q, const VecV& v, const VecV& /*a*/,
                     TermDerivatives& out) const override {
    const Vec4 qq = q.head<4>();
    const Vec3 w = v.head<3>();
    // L(q) w = q (x) (0, w) is linear in q: d/dq = [0, -w^T; w, -hat(w)].
    out.qdot_q.resize(4, 4);
    out.qdot_q(0, 0) = 0.0;
    out.qdot_q.block<1, 3>(0, 1) = -0.5 * w.transpose();
    out.qdot_q.block<3, 1>(1, 0) = 0.5 * w;
    out.qdot_q.block<3, 3>(1, 1) = -0.5 * so3::hat(w);
    out.N = 0.5 * quaternion_rate_map(qq);
    out.Ma_q.setZero(3, 4);  // M = J
    // tau(R(q)) with the homogeneous R(q): d tau/dq_k = c x (m R_k^T g).
    const std::array<Mat3, 4> Rk = quaternion_placement_partials(qq);
    const Vec3 mg = body_.mass * body_.gravity_W;
    out.f_q.resize(3, 4);
    for (int k = 0; k < 4; ++k) out.f_q.col(k) = body_.c_B.cross(Rk[k].transpose() * mg);
    out.f_v = gyroscopic_derivative(body_, w);
    out.gamma_q.resize(0, 4);
    out.gamma_v.resize(0, 3);
  }
  // Phi = q.q - 1: the Hessian is 2 I.
  void constraint_hessian_weighted(const VecQ& /*q*/, const VecC& m, MatQQ& out) const override {
    out = (2.0 * m(0)) * MatQQ::Identity(4, 4);
  }
  void constraint_hessian_applied(const VecQ& /*q*/, const VecQ& w, MatCQ& out) const override {
    out = 2.0 * w.head<4>().transpose();
  }

  void from_physical(const Mat3& R_WB, const Vec3& omega_B, VecQ& q, VecV& v) const override {
    q = so3::matrix_to_quaternion(R_WB);
    v = omega_B;
  }
  Vec4 orientation(const VecQ& q) const override { return q.head<4>().normalized(); }
  Mat3 placement(const VecQ& q) const override { return so3::quaternion_to_matrix(q.head<4>()); }
  Vec3 body_angular_velocity(const VecQ& /*q*/, const VecV& v) const override { return v.head<3>(); }
  void project_coordinates(VecQ& q) const override { q.head<4>().normalize(); }
  const EulerFormRate* euler_form_rate() const override { return &rate_; }

 private:
  RigidBodyModel body_;
  EulerFormRateOf<QuaternionKinematics> rate_;
};

}  // namespace

std::unique_ptr<Representation> make_quaternion_euler(const RigidBodyModel& body, const so3::EulerSequence& /*start_chart*/) {
  return std::make_unique<QuaternionEuler>(body);
}

}  // namespace rigidae::coords
