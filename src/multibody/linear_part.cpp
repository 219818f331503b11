// The linear part of an acceleration-level residual, for the ODE form
// (multibody_ode.hpp). With index1's rows (and projection's, the same rows)
// the residual of multibody_problem.cpp reads, per body and per block,
//   kinematics  F_q      = q' - qdot(q, v)                 (no mu)
//   dynamics    F_v      = M(q) v' - f(t, q, v) + G^T lambda
//   block rows  F_lambda = w_A (G v' - gamma) + w_V G v + w_P Phi
// so F = A [y'_state; lambda] + F(t, (q, v, 0), 0) with
//   A = [ I  0    0   ]   rows q
//       [ 0  M    G^T ]   rows v
//       [ 0  w_A G  0 ]   rows lambda
// (columns q', v', lambda); a row set aside reads F_lambda = lambda (a 1 on
// the diagonal, no G). A is written through the iteration matrix's sink,
// so its entries land on sparsity()'s pattern: every pair written here is
// one the exact iteration matrix writes too (cj dF/dy' and G^T).
#include "rigidae/multibody/multibody_problem.hpp"

#include <algorithm>

#include "rigidae/core/error.hpp"

namespace rigidae::multibody {

void MultibodyProblem::assemble_linear_part(double t, const double* y, JacobianSink& sink, bool just_evaluated) {
  if (!just_evaluated) evaluate(t, y, lagrange_form_ ? 2 : 1, /*for_rows=*/true);
  for (const BodyModel& b : bodies_) {
    const BodyWork& w = work_[&b - bodies_.data()];
    sink.add_diagonal(b.q_group, 1.0);
    if (b.nx == 3) sink.add(b.v_group, b.v_group, 0, 0, b.mass * Mat3::Identity());
    sink.add(b.v_group, b.v_group, b.nx, b.nx, w.terms.M);
  }
  for (int j = 0; j < static_cast<int>(blocks_.size()); ++j) {
    const ConstraintBlock& blk = blocks_[j];
    if (blk.mu_group >= 0 || blk.kind != ConstraintKind::Force)
      throw SolverError("linear_part: a block with mu or of the kinematic kind has no acceleration-level form");
    if (!just_evaluated) evaluate_block(j, y, nullptr);
    const BlockEval& e = block_eval_[j];
    for (int x = 0; x < 2; ++x) {
      const int bi = blk.body_of_side[x];
      if (bi == kGround) continue;
      const int V = bodies_[bi].v_group;
      BlockMatV Ga = blk.lambda_rows.acceleration * e.G[x];
      for (int r = 0; r < blk.nr; ++r)
        if (!blk.active[r]) Ga.row(r).setZero();
      sink.add(blk.lambda_group, V, 0, 0, Ga);
      sink.add(V, blk.lambda_group, 0, 0, e.G[x].transpose());
    }
    // A row set aside (row_subset.cpp): lambda_r = 0.
    for (int r = 0; r < blk.nr; ++r)
      if (!blk.active[r]) sink.add(blk.lambda_group, blk.lambda_group, r, r, Eigen::Matrix<double, 1, 1>::Constant(1.0));
  }
}

void MultibodyProblem::linear_part_sparse(double t, const double* y, double* values, bool just_evaluated) {
  std::fill(values, values + pattern_.nnz(), 0.0);
  linear_part_into(t, y, *sink_, values, just_evaluated);
}

void MultibodyProblem::linear_part_into(double t, const double* y, JacobianSink& sink, double* values,
                                        bool just_evaluated) {
  sink.start_sparse(values);
  assemble_linear_part(t, y, sink, just_evaluated);
}

void MultibodyProblem::follow_motion(double t, const double* y) {
  if (!forces_follow_motion_ && coordinates_.empty()) return;
  evaluate(t, y, 2);
  follow_force_elements();
}

void MultibodyProblem::follow_force_elements() {
  for (const auto& f : forces_)
    if (f->follows_motion()) f->follow(force_bodies_);
  // An angle's branch: the value at this accepted step (reporting.cpp).
  for (CoordinateTrack& c : coordinates_) {
    if (c.def->kind != CoordinateKind::Angle) continue;
    double value = 0.0, rate = 0.0;
    coordinate_value(c, value, rate);
    c.branch.accept(value, rate, evaluated_t_);  // value's branch is re-chosen across the step
  }
}

}  // namespace rigidae::multibody
