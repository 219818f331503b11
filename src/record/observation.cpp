#include "rigidae/record/observation.hpp"

#include <cmath>

#include "rigidae/so3/rotation.hpp"

namespace rigidae {

Observer::Observer(const OneBodyView& view, const Scene& scene) : view_(view) {
  const RigidBodyModel& b = view.body();
  energy0_ = b.kinetic_energy(scene.omega0_B) + b.potential_energy(scene.R0_WB);
  energy_scale_ = std::abs(energy0_) > 0 ? std::abs(energy0_) : 1.0;
  lz0_ = b.vertical_angular_momentum(scene.R0_WB, scene.omega0_B);
  const double L0 = (b.J_B * scene.omega0_B).norm();
  momentum_scale_ = L0 > 0 ? L0 : 1.0;
}

Observation Observer::observe(double t, const Eigen::VectorXd& y) {
  const Representation& rep = view_.representation();
  const RigidBodyModel& b = view_.body();
  const VecQ q = view_.coordinates(y.data());
  const VecV v = view_.velocities(y.data());

  Observation o;
  o.t = t;
  o.q_WB = rep.orientation(q);
  if (o.q_WB.dot(last_q_) < 0) o.q_WB = -o.q_WB;
  last_q_ = o.q_WB;
  o.omega_B = rep.body_angular_velocity(q, v);
  o.drift = view_.drift(t, y.data());
  o.multipliers = y.segment(view_.multiplier_offset(), view_.multiplier_count());

  const Mat3 R = so3::quaternion_to_matrix(o.q_WB);
  o.energy = b.kinetic_energy(o.omega_B) + b.potential_energy(R);
  o.energy_error = (o.energy - energy0_) / energy_scale_;
  o.vertical_momentum = b.vertical_angular_momentum(R, o.omega_B);
  o.vertical_momentum_error = (o.vertical_momentum - lz0_) / momentum_scale_;
  return o;
}

}  // namespace rigidae
