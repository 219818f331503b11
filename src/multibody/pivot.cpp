// Pivoted bodies: a body held at a fixed point o (scene key `pivot`) in the
// multibody system, and the support force that holds it.
//
// Model (the one-body model of a top, src/model/rigid_body.cpp): the body
// only turns about o, so its unknowns are its rotation coordinates q_rot and
// velocities v_rot (nx = 0: no x, x'). Its rotation block is the
// representation of a one-body scene with support "fixed_point" and centre
// of mass c (body frame, from o):
//   J_O = J_c + m (|c|^2 I - c c^T)       inertia about the pivot
//   tau_g = c x (m R^T g)                 gravity torque, in f_rot
// so the gravity force element leaves the body out (gravity.cpp) and a
// load's force acts at the centre of mass through the lever R c
// (body_load.cpp). Its body vectors are p = o + R (c + s), s from the centre
// of mass as for a free body, and directions d = R s (body_vector.hpp), so
// joints and springs to other bodies work unchanged.
//
// Support force (space frame, on the body at o), from the body's momentum
// balance:
//   m a_c = F_support + m g + sum of the joints', springs' and loads' forces
//   a_c   = d^2/dt^2 (o + R c) = W_c v' + b_c    (the centre of mass as a body point)
// v' comes from the body's own dynamic rows at y: with r = -F_v(t, y, 0)
// (M v' = r holds, the multipliers of y in it),
//   [M G_i^T; G_i 0] (v', dl) = (r, gamma_i)
// when the representation's internal constraints are forces (Lagrange
// forms: M alone is singular off the constraint manifold), else M v' = r.
// The other forces are those the system's elements and joints would put on
// the body's translation if it were free: the body is evaluated once more as
// a free body at its centre of mass (nx = 3, x = o + R c, x' = the centre of
// mass's velocity), the elements' add_force and the joints' G^T lambda
// written into a scratch row, whose translation part is
//   F_x = -(m g + sum of the forces) + sum_joints G_x^T lambda.
// A free body's residual would read m a_c + F_x + (support's G^T lambda) =
// 0, so the support's force on the body is
//   F_support = m a_c + F_x.
// Not the hot path (one residual per call, for the records); allocates only
// on the first call.
#include <Eigen/LU>

#include "rigidae/multibody/multibody_problem.hpp"

namespace rigidae::multibody {

void pivot_body_scene(const BodySpec& bs, Scene& one_body, BodyModel& b) {
  b.nx = 0;
  b.pivot = *bs.pivot_W;
  b.lever = bs.com_from_pivot_B.value_or(Vec3(bs.R0_WB.transpose() * (bs.x0_W - *bs.pivot_W)));
  one_body.support = Support::FixedPoint;
  one_body.body.com_B = b.lever;  // gravity_W: the system's (set by the caller)
}

Vec3 MultibodyProblem::support_force(int i, const double* y) {
  const BodyModel& b = bodies_[i];
  if (!b.pivoted()) return Vec3::Zero();
  if (pivot_F_.size() != n_ + kMaxBodyV) {
    pivot_F_.setZero(n_ + kMaxBodyV);
    pivot_yp_.setZero(n_);
    pivot_bodies_ = force_bodies_;
    pivot_eval_ = std::make_unique<BlockEval>();
  }
  // v' from the body's dynamic rows.
  pivot_yp_.setZero();
  residual(0.0, y, pivot_yp_.data(), pivot_F_.data());
  evaluate(0.0, y, 2);  // order 2 for the body vectors whatever the form
  const BodyWork& w = work_[i];
  const int nv = b.nvr, vo = groups_[b.v_group].offset;
  const bool internal_forces = b.rep->nc() > 0 && b.rep->constraint_kind() == ConstraintKind::Force;
  const int nc = internal_forces ? b.rep->nc() : 0;
  constexpr int kMax = kMaxVelocities + kMaxConstraints;
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMax, kMax> K(nv + nc, nv + nc);
  Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMax, 1> rhs(nv + nc);
  K.setZero();
  K.topLeftCorner(nv, nv) = w.terms.M;
  for (int k = 0; k < nv; ++k) rhs(k) = -pivot_F_[vo + k];
  if (nc > 0) {
    K.bottomLeftCorner(nc, nv) = w.terms.G;
    K.topRightCorner(nv, nc) = w.terms.G.transpose();
    rhs.tail(nc) = w.terms.gamma;
  }
  const Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMax, 1> sol = K.fullPivLu().solve(rhs);
  // a_c = W_c v' + b_c: the centre of mass as a point of the pivoted body.
  VectorEval com;
  evaluate_vector(w.st, {i, Vec3::Zero(), true}, com);
  Vec3 a_c = com.bias;
  for (int k = 0; k < nv; ++k) a_c += com.Wm.col(k) * sol(k);

  // The body once more as a free body at its centre of mass.
  double q_free[3 + kMaxCoordinates], v_free[3 + kMaxVelocities];
  const Vec3 x_c = w.st.x();
  for (int k = 0; k < 3; ++k) q_free[k] = x_c(k), v_free[k] = com.Wv(k);
  for (int k = 0; k < b.nqr; ++k) q_free[3 + k] = w.st.q[k];
  for (int k = 0; k < nv; ++k) v_free[3 + k] = w.st.v[k];
  BodyState free = w.st;
  free.nx = 3;
  free.lever.setZero();
  free.q = q_free;
  free.v = v_free;
  pivot_bodies_.state[i] = &free;
  pivot_bodies_.v_offset[i] = n_;  // its row past the system's: only it is read
  std::fill(pivot_F_.data() + n_, pivot_F_.data() + n_ + 3 + nv, 0.0);
  for (const auto& f : forces_) f->add_force(pivot_bodies_, pivot_F_.data());
  pivot_bodies_.state[i] = &work_[i].st;
  pivot_bodies_.v_offset[i] = force_bodies_.v_offset[i];
  Vec3 F_x(pivot_F_[n_], pivot_F_[n_ + 1], pivot_F_[n_ + 2]);
  for (const ConstraintBlock& blk : blocks_) {
    if (blk.internal || blk.lambda_group < 0) continue;
    const int side = blk.body_of_side[0] == i ? 0 : blk.body_of_side[1] == i ? 1 : -1;
    if (side < 0) continue;
    BlockSides sides;
    for (int x = 0; x < 2; ++x) {
      sides.body[x] = blk.body_of_side[x];
      sides.state[x] = x == side ? &free : blk.body_of_side[x] == kGround ? nullptr : &work_[blk.body_of_side[x]].st;
    }
    evaluate_rows(blk.rows.data(), blk.nr, sides, *pivot_eval_);
    const double* lambda = y + groups_[blk.lambda_group].offset;
    for (int r = 0; r < blk.nr; ++r)
      for (int k = 0; k < 3; ++k) F_x(k) += pivot_eval_->G[side](r, k) * lambda[r];
  }
  return b.mass * a_c + F_x;
}

}  // namespace rigidae::multibody
