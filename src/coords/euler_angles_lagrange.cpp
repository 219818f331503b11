// Euler angles (any of the twelve sequences), Lagrange form.
//
// omega_B = B(a) a' and d(omega_B)/dt = B a'' + b(a, a') (so3::euler_rate_bias),
// so T = 1/2 a'^T B^T J B a' and Lagrange's equations are B^T times Euler's:
//   M(a) a'' = B^T (tau - omega x J omega - J b),   M = B^T J B
// (products of sines and cosines). No constraints; the chart is singular
// where det B = 0 and is switched before it gets there (see EulerChart).
// Unknowns: a (3), v = a' (3).
#include "euler_chart.hpp"
#include "factories.hpp"

namespace rigidae::coords {

namespace {

class EulerAnglesLagrange final : public EulerAnglesRepresentation {
 public:
  using EulerAnglesRepresentation::EulerAnglesRepresentation;

  std::string name() const override { return "euler/lagrange"; }

  void evaluate(double /*t*/, const VecQ& q, const VecV& v, StandardTerms& out) const override {
    const Vec3 a = q.head<3>();
    const Vec3 ad = v.head<3>();
    const Mat3 B = chart_.rate_matrix(a);
    const Vec3 w = B * ad;
    const Vec3 bias = so3::euler_rate_bias(chart_.sequence(), a, ad);
    out.qdot = v;
    out.M = B.transpose() * body_.J_B * B;
    out.f = B.transpose() * (body_.gravity_torque_B(chart_.rotation(a)) - w.cross(body_.J_B * w) - body_.J_B * bias);
    no_constraints(out);
  }

  void from_physical(const Mat3& R_WB, const Vec3& omega_B, VecQ& q, VecV& v) const override {
    const Vec3 a = so3::matrix_to_euler(chart_.sequence(), R_WB);
    q = a;
    v = chart_.rate_matrix(a).partialPivLu().solve(omega_B);
  }
  Vec3 body_angular_velocity(const VecQ& q, const VecV& v) const override {
    return chart_.rate_matrix(q.head<3>()) * v.head<3>();
  }

  bool change_chart(VecQ& q, VecV& v) override {
    const Vec3 w = body_angular_velocity(q, v);
    Vec3 a = q.head<3>();
    if (!chart_.move_to_most_regular(a)) return false;
    q = a;
    v = chart_.rate_matrix(a).partialPivLu().solve(w);
    return true;
  }
};

}  // namespace

std::unique_ptr<Representation> make_euler_angles_lagrange(const Scene& scene, const RigidBodyModel& body) {
  return std::make_unique<EulerAnglesLagrange>(scene, body);
}

}  // namespace rigidae::coords
