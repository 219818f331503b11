// Branch check across singular poses (issue 22, item 3).
//
// At a singular pose two assembly branches of a linkage cross with different
// tangents (the parallelogram and the crossed four-bar at the collinear
// pose). A motion that stays on its branch keeps a continuous velocity; one
// that changes branch must turn its velocity from one tangent to the other
// inside the pose's neighbourhood, an impulse no applied force explains.
// With V the stacked body velocities (per body the centre's velocity v_c and
// the angular velocity omega in space) and A = dV/dt, read at the last
// accepted step before the neighbourhood (t0) and the first after it (t1):
//
//   r    = V(t1) - V(t0) - (t1 - t0) (A(t0) + A(t1)) / 2        (trapezoid)
//   jump = |r|_M / max(|V(t0)|_M, |V(t1)|_M),
//   |x|_M^2 = sum over bodies of m |x_v|^2 + x_w . (R I R^T) x_w
//
// A passage on the branch leaves r = O((t1 - t0)^3 A''): with the
// neighbourhood a few hundredths of a turn wide, jump ~ 1e-4 and less. A
// switch leaves r of the size of V: jump ~ 1. Above kBranchJump, and with r
// above (t1 - t0) |A(t1) - A(t0)| (a bound the trapezoid's own error stays
// far below on a smooth motion: its ratio to r measured 0.003 .. 0.006 on the
// branch, 35 .. 95 at the switches), the pose is a branch switch (event
// branch_switch; solve warns). A check between any two accepted steps, pose
// or not, does not work: ARKODE's steps of a third of a turn leave jumps of
// 0.7 on a smooth motion. The accelerations A are
// read from the integrator's y' (IDA) or the ODE's right-hand side, through a
// directional difference of V along the state's derivative.
//
// What it does not see: branches that cross tangentially (the same velocity
// on both), and a switch that happens outside the watched neighbourhood.
#include <algorithm>
#include <cmath>
#include <limits>

#include "rigidae/multibody/multibody_problem.hpp"
#include "rigidae/so3/rotation.hpp"

namespace rigidae::multibody {

void MultibodyProblem::body_velocities(const double* y, Eigen::VectorXd& V) const {
  const int nb = static_cast<int>(bodies_.size());
  V.resize(6 * nb);
  for (int i = 0; i < nb; ++i) {
    V.segment<3>(6 * i) = body_velocity(i, y);
    V.segment<3>(6 * i + 3) = bodies_[i].particle ? Vec3::Zero() : body_omega_space(i, y);
  }
}

double MultibodyProblem::velocity_norm(const double* y, const Eigen::VectorXd& x) const {
  double s = 0.0;
  for (int i = 0; i < static_cast<int>(bodies_.size()); ++i) {
    const BodyModel& b = bodies_[i];
    const Vec3 v = x.segment<3>(6 * i), w = x.segment<3>(6 * i + 3);
    s += b.mass * v.squaredNorm();
    if (!b.particle) {
      const Mat3 R = so3::quaternion_to_matrix(body_orientation(i, y));
      s += w.dot(R * b.inertia * R.transpose() * w);
    }
  }
  return std::sqrt(s);
}

void MultibodyProblem::check_branch(double t, const double* y, const double* yp) {
  BranchWatch& w = branch_;
  if (yp == nullptr) return;
  if (near_singular_) {
    w.inside = true;  // the anchor stays at the last step before the pose
    return;
  }
  // V and A here: A by a directional difference of V along y' (the state's
  // part: the multipliers' derivatives do not enter V).
  body_velocities(y, w.V1);
  const Eigen::Map<const Eigen::VectorXd> ys(y, n_state_), yps(yp, n_state_);
  const double scale = std::max(1.0, ys.cwiseAbs().maxCoeff());
  const double rate = yps.cwiseAbs().maxCoeff();
  w.y_shift = ys;
  double eps = 0.0;
  if (rate > 0.0 && std::isfinite(rate)) {
    eps = 1e-7 * scale / rate;
    w.y_shift += eps * yps;
  }
  w.scratch.setZero(n_);
  w.scratch.head(n_state_) = w.y_shift;
  body_velocities(w.scratch.data(), w.A1);
  if (eps > 0.0) w.A1 = (w.A1 - w.V1) / eps;
  else w.A1.setZero();
  if (w.inside && w.valid && !singular_poses_.empty()) {
    const Eigen::VectorXd r = w.V1 - w.V0 - 0.5 * (t - w.t0) * (w.A0 + w.A1);
    const double base = std::max({velocity_norm(y, w.V0), velocity_norm(y, w.V1), 1e-300});
    const double jump = velocity_norm(y, r) / base;
    // The trapezoid's own error on a smooth motion, ~ (t1 - t0)^3 A''/12, is
    // far below (t1 - t0) |A(t1) - A(t0)|; a switch's r is far above it.
    const double smooth = velocity_norm(y, (t - w.t0) * (w.A1 - w.A0));
    const bool switched = !(jump <= kBranchJump) && !(velocity_norm(y, r) <= smooth);
    SingularPose& sp = singular_poses_.back();
    sp.velocity_jump = std::isnan(sp.velocity_jump) ? jump : std::max(sp.velocity_jump, jump);
    sp.branch_switch = sp.branch_switch || switched;
    if (switched) events_.push_back(EventNote::at_joints(t, "branch_switch", sp.joints, jump));
  }
  w.inside = false;
  w.valid = true;
  w.t0 = t;
  w.V0.swap(w.V1);
  w.A0.swap(w.A1);
}

}  // namespace rigidae::multibody
