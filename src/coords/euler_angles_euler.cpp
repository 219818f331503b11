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

class EulerAnglesEuler final : public EulerAnglesRepresentation {
 public:
  using EulerAnglesRepresentation::EulerAnglesRepresentation;

  std::string name() const override { return "euler/euler"; }

  void evaluate(double /*t*/, const VecQ& q, const VecV& v, StandardTerms& out) const override {
    const Vec3 a = q.head<3>();
    const Vec3 w = v.head<3>();
    out.qdot = chart_.rate_matrix(a).partialPivLu().solve(w);
    out.M = body_.J_B;
    out.f = body_.gravity_torque_B(chart_.rotation(a)) - w.cross(body_.J_B * w);
    no_constraints(out);
  }

  void from_physical(const Mat3& R_WB, const Vec3& omega_B, VecQ& q, VecV& v) const override {
    q = so3::matrix_to_euler(chart_.sequence(), R_WB);
    v = omega_B;
  }
  Vec3 body_angular_velocity(const VecQ& /*q*/, const VecV& v) const override { return v.head<3>(); }

  bool change_chart(VecQ& q, VecV& /*v*/) override {
    Vec3 a = q.head<3>();
    if (!chart_.move_to_most_regular(a)) return false;
    q = a;
    return true;
  }
};

}  // namespace

std::unique_ptr<Representation> make_euler_angles_euler(const Scene& scene, const RigidBodyModel& body) {
  return std::make_unique<EulerAnglesEuler>(scene, body);
}

}  // namespace rigidae::coords
