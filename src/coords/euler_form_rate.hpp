#pragma once
// The Euler form's ODE right-hand side for one representation, fixed-size
// (internal header; the interface is EulerFormRate in representation.hpp):
//
//   x = (q, omega_B),  q' = N(q) omega_B,
//   omega_B' = J^-1 (c x (m R(q)^T g) - omega_B x J omega_B).
//
// `Kinematics` is the representation's part, with q of compile-time size:
//   static constexpr int kNq;
//   static void rate(const double* q, const Vec3& w, double* qdot);   q' = N(q) w
//   static Vec3 gravity_in_body(const double* q, const Vec3& g_W);    R(q)^T g_W
// with R(q) exactly the placement evaluate() uses (for quaternions the
// homogeneous |q|^2 R, not normalised), so that the kernel and evaluate()
// followed by a solve with M = J are the same function (to rounding: J^-1 is
// formed once here where the generic path factorises J).
#include "rigidae/coords/representation.hpp"
#include "rigidae/model/rigid_body.hpp"

namespace rigidae::coords {

template <class Kinematics>
class EulerFormRateOf final : public EulerFormRate {
 public:
  explicit EulerFormRateOf(const RigidBodyModel& body)
      : J_(body.J_B), J_inv_(body.J_B.inverse()), mc_(body.mass * body.c_B), g_(body.gravity_W) {}

  void rate(const double* x, double* xdot) const override {
    constexpr int nq = Kinematics::kNq;
    const Vec3 w(x[nq], x[nq + 1], x[nq + 2]);
    Kinematics::rate(x, w, xdot);
    const Vec3 torque = mc_.cross(Kinematics::gravity_in_body(x, g_)) - w.cross(J_ * w);
    Eigen::Map<Vec3>(xdot + nq) = J_inv_ * torque;
  }

 private:
  Mat3 J_, J_inv_;
  Vec3 mc_;  // m c_B
  Vec3 g_;
};

}  // namespace rigidae::coords
