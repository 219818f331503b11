// The bridge across singular poses (issue 22, item 3: pass a pose without
// stalling and without switching assembly branch).
//
// At a singular pose two assembly branches cross (the parallelogram and the
// crossed four-bar at the collinear pose): the rows lose rank, the
// saddle-point matrix [M G^T; G 0] is singular, and a state off the
// constraints by the integrator's own error (~ the tolerance) is amplified
// by 1/sigma_min there. Steps that land near the pose creep or jump branch
// (singular_linkage.toml: IDA's steps fall to 1e-7 s and leave the branch).
// The motion itself is smooth through the pose. So the run does not step
// into it: it stops before, at a conditioning it handles well, extrapolates
// the motion to the mirror point beyond and projects onto the constraints
// there, where the branches are apart again and the projection (Gauss-Newton
// from the extrapolated guess) lands on the branch the motion arrived on.
//
// Conditioning: r(t), the kept rows' R ratio at the start's rank relative
// to the start's (row_subset.cpp), sampled at accepted steps. Near a simple
// rank loss r ~ c |t - t*|, so from two samples approaching (r1 < r0):
//   t*  = t1 + r1 (t1 - t0) / (r0 - r1)
//   t_L = t* - (t* - t1) kBridgeCondition / r1   (r = kBridgeCondition there)
// Below kBridgeWatch the integrator's stop time is set to a fraction of the
// way to t_L (half while r > 0.2, where r is not yet linear in t; 0.8 on),
// so no step crosses the pose; at r <= 1.5 kBridgeCondition the run bridges
// from t1 to t2 = t* + (t* - t1).
//
// Extrapolation: Hermite interpolation of the state (positions and
// velocities at the nodes, their derivatives recomputed from them by
// make_consistent: the constrained accelerations) through the last accepted step and up
// to two earlier ones spaced at least (t2 - t1) / 2 apart, evaluated at t2
// (value and derivative): a polynomial of degree 2K - 1 on K nodes, error
// ~ y^(2K) / (2K)! prod (t2 - t_i)^2. The estimate is the difference from
// the interpolant without the oldest node, in units of the tolerance,
//   max_i |difference_i| / (rtol |y_i| + atol).
// Then project() (positions in the mass metric, velocities, multipliers
// and y' consistent), and for a conservative mechanism without drivers the
// velocities scaled back to the energy at t1 (below). The branch check (branch_check.cpp) compares the
// velocity across the bridge. Inside (t1, t2] the output grid gets the
// interpolant's state and multipliers interpolated linearly between the two
// ends (not error-controlled; the reactions at the pose itself are not
// determined by the constraints).
//
// Measured: see problems/singular_linkage.toml's header.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "rigidae/core/hermite.hpp"
#include "rigidae/multibody/multibody_problem.hpp"

namespace rigidae::multibody {

namespace {

// The conditioning at which a bridge starts and lands; below kBridgeWatch
// the approach is watched (stop times). Measured on singular_linkage.toml
// at rtol 1e-10 (every combination on IDA, both equation forms, before the
// energy scaling): IDA's steps collapse from r ~ 0.015 on; bridging at
// r = 0.05 with 3 nodes kept all but index3 within 5.2e-7 rad of the closed
// form to t = 1 s; at 0.03
// (a shorter reach) or with 4 nodes (degree 7) the nodes' own errors,
// amplified, made it worse (up to 1.1e-6 and 4.7e-6), at 0.1 the
// truncation (1.3e-5 with 3 nodes).
constexpr double kBridgeCondition = 0.05;
constexpr double kBridgeWatch = 0.5;
constexpr int kHistory = 48;
constexpr int kNodes = 3;

}  // namespace

bool MultibodyProblem::plan_bridge(double t, double r) {
  PoseBridge& b = bridge_;
  const bool approaching = std::isfinite(b.r_last) && r < b.r_last && t > b.t_last;
  b.stop_hint = std::numeric_limits<double>::infinity();
  b.pending = false;
  if (approaching && r < kBridgeWatch) {
    const double t_star = t + r * (t - b.t_last) / (b.r_last - r);
    if (r <= 1.5 * kBridgeCondition) {
      // Bridge now, when the mirror point lies inside the run.
      if (t_star + (t_star - t) < b.t_end) {
        b.pending = true;
        b.pose_t = t_star;
      }
    } else {
      const double t_land = t_star - (t_star - t) * kBridgeCondition / r;
      b.stop_hint = t + (r > 0.2 ? 0.5 : 0.8) * (t_land - t);
    }
  }
  b.t_last = t;
  b.r_last = r;
  return b.pending;
}

double MultibodyProblem::bridge_after_step(double t, Eigen::VectorXd& y, Eigen::VectorXd& yp) {
  PoseBridge& b = bridge_;
  // The state for later extrapolations (the newest last).
  if (!b.t.empty() && t <= b.t.back()) forget_bridge_history();  // an earlier time: a new run
  if (static_cast<int>(b.t.size()) == kHistory) {
    b.t.erase(b.t.begin());
    b.y.erase(b.y.begin());
  }
  b.t.push_back(t);
  b.y.push_back(y);  // y' is not kept: the nodes' derivatives are recomputed from y (below)
  if (!b.pending) return 0.0;
  b.pending = false;

  const double t2 = b.pose_t + (b.pose_t - t);
  const double reach = t2 - t;
  // Nodes: this step and up to two earlier ones, each at least reach / 2
  // before the one after it.
  std::vector<int> picked{static_cast<int>(b.t.size()) - 1};
  for (int k = static_cast<int>(b.t.size()) - 2; k >= 0 && static_cast<int>(picked.size()) < kNodes; --k)
    if (b.t[picked.back()] - b.t[k] >= 0.5 * reach) picked.push_back(k);
  if (picked.size() < 2 || !(reach > 0.0)) {
    // Too little history (a restart just before): the integrator passes the
    // pose, watched as without the bridge (row_subset.cpp).
    near_singular_ = true;
    return 0.0;
  }
  std::reverse(picked.begin(), picked.end());
  std::vector<double> nodes;
  std::vector<const Eigen::VectorXd*> f, fp;
  // The derivatives at the nodes from the state itself (the constrained
  // accelerations of make_consistent): the integrator's y' is not
  // error-controlled (IDA's is its BDF formula's, or its interpolant's at a
  // stop time), and its error, times the reach, was the bridge's largest.
  std::vector<Eigen::VectorXd> node_y(picked.size()), node_yp(picked.size());
  for (std::size_t i = 0; i < picked.size(); ++i) {
    const int k = picked[i];
    node_y[i] = b.y[k];
    make_consistent(b.t[k], node_y[i], node_yp[i]);
    nodes.push_back(b.t[k]);
    f.push_back(&node_y[i]);
    fp.push_back(&node_yp[i]);
  }
  const int ns = n_state_;
  Eigen::VectorXd ys, yps, lower;
  std::vector<double> z_lower;
  std::vector<Eigen::VectorXd> c_lower;
  {
    // The interpolant without the oldest node: the estimate.
    const std::vector<double> n2(nodes.begin() + 1, nodes.end());
    const std::vector<const Eigen::VectorXd*> f2(f.begin() + 1, f.end()), fp2(fp.begin() + 1, fp.end());
    hermite_coefficients(n2, f2, fp2, ns, z_lower, c_lower);
    hermite_value(z_lower, c_lower, t2, lower, nullptr);
  }
  hermite_coefficients(nodes, f, fp, ns, b.z, b.c);
  hermite_value(b.z, b.c, t2, ys, &yps);
  double estimate = 0.0;
  for (int i = 0; i < ns; ++i)
    estimate = std::max(estimate, std::abs(ys(i) - lower(i)) / (b.rtol * std::abs(ys(i)) + b.atol));

  b.from = t;
  b.to = t2;
  b.y_from = node_y.back();  // this step's, its multipliers consistent (the ODE form's state has none)
  y.head(ns) = ys;
  yp.head(ns) = yps;
  const auto [drift_position, drift_velocity] = drift(t2, y.data());
  project(t2, y, yp);
  // Energy: a conservative mechanism without drivers keeps H = T + V across
  // the bridge. The extrapolation's error along the motion (which the
  // projection leaves) shows as an energy error; scaling the velocities
  // removes it (G v = 0 is linear: they stay on the constraints):
  //   v *= sqrt((H(t1) - V(t2)) / T(t2)).
  if (conserves_energy() && drivers_.empty()) {
    const double h1 = kinetic_energy(node_y.back().data()) + potential_energy(node_y.back().data());
    const double t2_kinetic = kinetic_energy(y.data()), v2 = potential_energy(y.data());
    if (t2_kinetic > 0.0 && h1 - v2 > 0.0) {
      for (const BodyModel& body : bodies_)  // each body's velocities are a group of their own
        y.segment(groups_[body.v_group].offset, groups_[body.v_group].size) *= std::sqrt((h1 - v2) / t2_kinetic);
      make_consistent(t2, y, yp);
    }
  }
  b.y_to = y;

  SingularPose& sp = singular_poses_.back();
  sp.bridged = true;
  sp.bridged_from = t;
  sp.bridged_to = t2;
  sp.estimate = estimate;
  EventNote note = EventNote::at_joints(t2, "pose_bridge", sp.joints, estimate);
  note.from = fmt::format("{:.9g}", t);
  note.to = fmt::format("{:.9g}", t2);
  note.drift_position = drift_position;
  note.drift_velocity = drift_velocity;
  events_.push_back(note);
  drift_memo_valid_ = false;
  // The branch check across the bridge: the anchor is this step's.
  branch_.inside = true;
  check_branch(t2, y.data(), yp.data());
  // The landing is the next extrapolation's newest node; the conditioning's
  // samples start again beyond the pose.
  b.t.push_back(t2);
  b.y.push_back(y);
  b.t_last = b.r_last = std::numeric_limits<double>::quiet_NaN();
  b.stop_hint = std::numeric_limits<double>::infinity();
  return t2;
}

void MultibodyProblem::bridged_state(double t, Eigen::VectorXd& y) {
  const PoseBridge& b = bridge_;
  const double s = b.to > b.from ? std::clamp((t - b.from) / (b.to - b.from), 0.0, 1.0) : 1.0;
  y = (1.0 - s) * b.y_from + s * b.y_to;  // the multipliers
  Eigen::VectorXd state;
  hermite_value(b.z, b.c, t, state, nullptr);
  if (t >= b.to) state = b.y_to.head(n_state_);  // the landing is the projected state
  y.head(n_state_) = state;
}

}  // namespace rigidae::multibody
