#pragma once
// What a user reads off one state, whatever the coordinates: the orientation
// as a unit quaternion, the body angular velocity, constraint drift, the
// multipliers and the invariants with their errors against t = start.
#include "rigidae/multibody/one_body_view.hpp"

namespace rigidae {

inline constexpr int kMaxMultipliers = 2 * kMaxConstraints;

struct Observation {
  double t = 0.0;                       // s
  Vec4 q_WB = Vec4(1, 0, 0, 0);         // unit quaternion, scalar first
  Vec3 omega_B = Vec3::Zero();          // rad/s, body frame
  ConstraintDrift drift;                // position level 1, velocity level 1/s
  BoundedVec<kMaxMultipliers> multipliers;  // lambda (J) then mu (1/s)
  double energy = 0.0;                  // J
  double energy_error = 0.0;            // (H - H0) / |H0|  (or / 1 J when H0 = 0)
  double vertical_momentum = 0.0;       // kg m^2/s, about the reference point
  double vertical_momentum_error = 0.0; // (Lz - Lz0) / |L0|
};

// Turns states into observations. Keeps the quaternion sign continuous from
// one observation to the next (q and -q are the same rotation).
class Observer {
 public:
  Observer(const OneBodyView& view, const Scene& scene);
  // y of the view's system, its coordinates in the chart the run is in now.
  Observation observe(double t, const Eigen::VectorXd& y);
  // The energy H0 at the scene's initial state (kinetic plus potential about the reference point), J.
  double initial_energy() const { return energy0_; }

 private:
  const OneBodyView& view_;
  double energy0_, energy_scale_;
  double lz0_, momentum_scale_;
  Vec4 last_q_ = Vec4(1, 0, 0, 0);
};

}  // namespace rigidae
