#pragma once
// The mechanical data a representation needs, derived once from a Scene.
//
// A top with a fixed point rotates about the pivot O: J is the inertia about
// O (parallel-axis), c_B the vector from O to the centre of mass, and gravity
// exerts a torque. A free body rotates about its centre of mass: its centre
// of mass moves ballistically (x_c(t) = x_c0 + v_c0 t + g t^2/2, not
// integrated), c_B = 0 and the rotation is torque free. Either way only the
// three rotational degrees of freedom are unknowns.
#include "rigidae/core/types.hpp"
#include "rigidae/model/scene.hpp"

namespace rigidae {

struct RigidBodyModel {
  double mass = 1.0;          // kg
  Mat3 J_B;                   // kg m^2, inertia about the reference point, body axes
  Mat3 E_B;                   // kg m^2, Euler tensor about the reference point: tr(J)/2 I - J
  Vec3 c_B = Vec3::Zero();    // m, reference point -> centre of mass, body frame
  Vec3 gravity_W;             // m/s^2
  Vec3 up_W = Vec3::UnitZ();  // unit vector opposite gravity (e_z when g = 0)

  // Gravity torque about the reference point in body components: c x (m R^T g).
  Vec3 gravity_torque_B(const Mat3& R_WB) const { return c_B.cross(mass * (R_WB.transpose() * gravity_W)); }
  // Potential energy, zero when the centre of mass is level with the reference point.
  double potential_energy(const Mat3& R_WB) const { return -mass * gravity_W.dot(R_WB * c_B); }
  double kinetic_energy(const Vec3& omega_B) const { return 0.5 * omega_B.dot(J_B * omega_B); }
  // Angular momentum about the reference point along the vertical.
  double vertical_angular_momentum(const Mat3& R_WB, const Vec3& omega_B) const {
    return up_W.dot(R_WB * (J_B * omega_B));
  }
};

RigidBodyModel make_rigid_body_model(const Scene& scene);

}  // namespace rigidae
