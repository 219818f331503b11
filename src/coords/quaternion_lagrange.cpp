// Unit quaternions, Lagrange form (the paper's regular quadratic mass matrix).
//
// Placement x = R(q) X with the homogeneous quadratic R(q) (scalar first), so
//   T = 1/2 tr(R' E R'^T),  R' = sum_k R_k q'_k,  R_k = dR/dq_k (linear in q).
// Since R(q) = B(q, q) for a symmetric bilinear B, Lagrange's equations reduce to
//   M(q) q'' = Q - h,  M_kl = tr(R_k E R_l^T),  h_k = 2 tr(R_k E R(q')^T),
// with R(q') the same quadratic map applied to q' (the dM/dt q' and
// 1/2 d/dq(q'^T M q') terms combine into h). Gravity Q_k = m g^T R_k c.
// Constraint Phi = q^T q - 1, G = 2 q^T, G q'' = gamma = -2 q'^T q'.
// Unknowns: q (4), v = q' (4); one force multiplier.
#include "coordinate_maps.hpp"
#include "factories.hpp"

namespace rigidae::coords {

namespace {

class QuaternionLagrange final : public Representation {
 public:
  explicit QuaternionLagrange(const RigidBodyModel& body) : body_(body) {
    for (int m = 0; m < 4; ++m) {
      const std::array<Mat3, 4> Rk = quaternion_placement_partials(Vec4::Unit(m));
      for (int k = 0; k < 4; ++k) second_partials_[k][m] = Rk[k];
    }
  }

  std::string name() const override { return "quaternion/lagrange"; }
  int nq() const override { return 4; }
  int nv() const override { return 4; }
  int nc() const override { return 1; }
  ConstraintKind constraint_kind() const override { return ConstraintKind::Force; }
  std::vector<std::string> constraint_names() const override { return {"norm"}; }

  void evaluate(double /*t*/, const VecQ& q, const VecV& v, StandardTerms& out) const override {
    const Vec4 qq = q.head<4>();
    const Vec4 qd = v.head<4>();
    const std::array<Mat3, 4> Rk = quaternion_placement_partials(qq);
    std::array<Mat3, 4> RkE;
    for (int k = 0; k < 4; ++k) RkE[k] = Rk[k] * body_.E_B;

    out.qdot = v;
    out.M.resize(4, 4);
    out.f.resize(4);
    const Mat3 R_of_qd = so3::quaternion_to_matrix(qd);
    const Vec3 mg = body_.mass * body_.gravity_W;
    for (int k = 0; k < 4; ++k) {
      for (int l = k; l < 4; ++l) out.M(k, l) = out.M(l, k) = RkE[k].cwiseProduct(Rk[l]).sum();
      out.f(k) = mg.dot(Rk[k] * body_.c_B) - 2.0 * RkE[k].cwiseProduct(R_of_qd).sum();
    }
    out.phi.resize(1);
    out.phi(0) = qq.squaredNorm() - 1.0;
    out.phi_q = 2.0 * qq.transpose();
    out.G = out.phi_q;
    out.gamma.resize(1);
    out.gamma(0) = -2.0 * qd.squaredNorm();
  }

  // With <A, B> the Frobenius product, R_k linear in q and C_km = R_k(e_m):
  //   (M a)_k = <R_k E, R_a>,  R_a = sum_l a_l R_l(q)
  //     d/dq_m: <C_km E, R_a> + <R_k E, R_m(a)>   (sum_l a_l C_lm = R_m(a))
  //   f_k = m g.(R_k c) - 2 <R_k E, R(q')>
  //     d/dq_m:  m g.(C_km c) - 2 <C_km E, R(q')>
  //     d/dq'_l: -2 <R_k E, R_l(q')>
  void differentiate(double /*t*/, const VecQ& q, const VecV& v, const VecV& a, TermDerivatives& out) const override {
    const Vec4 qq = q.head<4>();
    const Vec4 qd = v.head<4>();
    const Vec4 aa = a.head<4>();
    const std::array<Mat3, 4> Rk = quaternion_placement_partials(qq);
    const std::array<Mat3, 4> Rk_of_a = quaternion_placement_partials(aa);
    const std::array<Mat3, 4> Rk_of_qd = quaternion_placement_partials(qd);
    const Mat3 R_of_qd = so3::quaternion_to_matrix(qd);
    Mat3 R_a = Mat3::Zero();
    for (int l = 0; l < 4; ++l) R_a += aa(l) * Rk[l];
    const Vec3 mg = body_.mass * body_.gravity_W;
    const Mat3& E = body_.E_B;

    out.qdot_q.setZero(4, 4);
    out.N.setIdentity(4, 4);
    out.Ma_q.resize(4, 4);
    out.f_q.resize(4, 4);
    out.f_v.resize(4, 4);
    for (int k = 0; k < 4; ++k) {
      const Mat3 RkE = Rk[k] * E;
      for (int m = 0; m < 4; ++m) {
        const Mat3 CkmE = second_partials_[k][m] * E;
        out.Ma_q(k, m) = CkmE.cwiseProduct(R_a).sum() + RkE.cwiseProduct(Rk_of_a[m]).sum();
        out.f_q(k, m) = mg.dot(second_partials_[k][m] * body_.c_B) - 2.0 * CkmE.cwiseProduct(R_of_qd).sum();
        out.f_v(k, m) = -2.0 * RkE.cwiseProduct(Rk_of_qd[m]).sum();
      }
    }
    out.gamma_q.setZero(1, 4);
    out.gamma_v = -4.0 * qd.transpose();
  }
  // Phi = q.q - 1: the Hessian is 2 I.
  void constraint_hessian_weighted(const VecQ& /*q*/, const VecC& m, MatQQ& out) const override {
    out = (2.0 * m(0)) * MatQQ::Identity(4, 4);
  }
  void constraint_hessian_applied(const VecQ& /*q*/, const VecQ& w, MatCQ& out) const override {
    out = 2.0 * w.head<4>().transpose();
  }

  void from_physical(const Mat3& R_WB, const Vec3& omega_B, VecQ& q, VecV& v) const override {
    const Vec4 qq = so3::matrix_to_quaternion(R_WB);
    q = qq;
    v = 0.5 * quaternion_rate_map(qq) * omega_B;
  }
  Vec4 orientation(const VecQ& q) const override { return q.head<4>().normalized(); }
  Mat3 placement(const VecQ& q) const override { return so3::quaternion_to_matrix(q.head<4>()); }
  Vec3 body_angular_velocity(const VecQ& q, const VecV& v) const override {
    // q' = 1/2 L omega + (q.q'/|q|^2) q, with L^T q = 0 and L^T L = |q|^2 I.
    const Vec4 qq = q.head<4>();
    return 2.0 * quaternion_rate_map(qq).transpose() * v.head<4>() / qq.squaredNorm();
  }
  void project_coordinates(VecQ& q) const override { q.head<4>().normalize(); }

 private:
  RigidBodyModel body_;
  std::array<std::array<Mat3, 4>, 4> second_partials_;  // C_km = d^2 R / dq_k dq_m, constant
};

}  // namespace

std::unique_ptr<Representation> make_quaternion_lagrange(const RigidBodyModel& body, const so3::EulerSequence& /*start_chart*/) {
  return std::make_unique<QuaternionLagrange>(body);
}

}  // namespace rigidae::coords
