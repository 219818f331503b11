#include "rigidae/model/rigid_body.hpp"

namespace rigidae {

RigidBodyModel make_rigid_body_model(const Scene& scene) {
  RigidBodyModel b;
  b.mass = scene.body.mass;
  b.gravity_W = scene.gravity_W;
  if (scene.support == Support::FixedPoint) {
    // Parallel-axis theorem: J_O = J_c + m (|c|^2 I - c c^T).
    const Vec3& c = scene.body.com_B;
    b.c_B = c;
    b.J_B = scene.body.inertia_com + b.mass * (c.squaredNorm() * Mat3::Identity() - c * c.transpose());
  } else {
    b.c_B.setZero();
    b.J_B = scene.body.inertia_com;
  }
  b.E_B = 0.5 * b.J_B.trace() * Mat3::Identity() - b.J_B;
  const double g = scene.gravity_W.norm();
  b.up_W = g > 0 ? Vec3(-scene.gravity_W / g) : Vec3(Vec3::UnitZ());
  return b;
}

}  // namespace rigidae
