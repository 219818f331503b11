// Euler angles (any of the twelve sequences), Euler form.
//
//   a' = B(a)^{-1} omega_B,   J omega_B' = tau - omega_B x J omega_B.
// No constraints; B^{-1} blows up at the chart's singularity (det B = 0), so
// the chart is switched before it gets there (see EulerChart).
// Unknowns: a (3), omega_B (3).
#include "euler_chart.hpp"
#include "factories.hpp"

namespace rigidae::coords {

namespace {

class EulerAnglesEuler final : public Representation {
 public:
  EulerAnglesEuler(const Scene& scene, const RigidBodyModel& body) : body_(body), chart_(scene) {}

  std::string name() const override { return "euler/euler"; }
  int nq() const override { return 3; }
  int nv() const override { return 3; }
  int nc() const override { return 0; }
  ConstraintKind constraint_kind() const override { return ConstraintKind::None; }
  std::vector<std::string> constraint_names() const override { return {}; }

  void evaluate(double /*t*/, const VecQ& q, const VecV& v, StandardTerms& out) const override {
    const Vec3 a = q.head<3>();
    const Vec3 w = v.head<3>();
    out.qdot = chart_.rate_matrix(a).partialPivLu().solve(w);
    out.M = body_.J_B;
    out.f = body_.gravity_torque_B(chart_.rotation(a)) - w.cross(body_.J_B * w);
    out.phi.resize(0);
    out.phi_q.resize(0, 3);
    out.G.resize(0, 3);
    out.gamma.resize(0);
  }

  void from_physical(const Mat3& R_WB, const Vec3& omega_B, VecQ& q, VecV& v) const override {
    q = so3::matrix_to_euler(chart_.sequence(), R_WB);
    v = omega_B;
  }
  Vec4 orientation(const VecQ& q) const override { return so3::matrix_to_quaternion(placement(q)); }
  Mat3 placement(const VecQ& q) const override { return chart_.rotation(q.head<3>()); }
  Vec3 body_angular_velocity(const VecQ& /*q*/, const VecV& v) const override { return v.head<3>(); }

  bool has_charts() const override { return true; }
  double chart_margin(const VecQ& q) const override { return chart_.margin(q.head<3>()); }
  std::string chart_name() const override { return chart_.sequence().name(); }
  bool change_chart(VecQ& q, VecV& /*v*/) override {
    Vec3 a = q.head<3>();
    if (!chart_.move_to_most_regular(a)) return false;
    q = a;
    return true;
  }

 private:
  RigidBodyModel body_;
  EulerChart chart_;
};

}  // namespace

std::unique_ptr<Representation> make_euler_angles_euler(const Scene& scene, const RigidBodyModel& body) {
  return std::make_unique<EulerAnglesEuler>(scene, body);
}

}  // namespace rigidae::coords
