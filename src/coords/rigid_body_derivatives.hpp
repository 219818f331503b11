#pragma once
// Derivatives of the rigid-body torques every representation shares
// (internal header).
#include "rigidae/core/types.hpp"
#include "rigidae/model/rigid_body.hpp"
#include "rigidae/so3/rotation.hpp"

namespace rigidae::coords {

// d(tau)/du of the gravity torque tau = c x (m R^T g) for the body-frame
// perturbation R -> R (I + hat(u)): R^T g gains (R^T g) x u, so
// d tau = c x (m R^T g x u) = hat(c) hat(m R^T g) u.
inline Mat3 gravity_torque_derivative(const RigidBodyModel& body, const Mat3& R_WB) {
  return so3::hat(body.c_B) * so3::hat(body.mass * (R_WB.transpose() * body.gravity_W));
}

// d/d(omega) of the gyroscopic term -omega x J omega: hat(J omega) - hat(omega) J.
inline Mat3 gyroscopic_derivative(const RigidBodyModel& body, const Vec3& w) {
  return so3::hat(body.J_B * w) - so3::hat(w) * body.J_B;
}

}  // namespace rigidae::coords
