// Reactions of the joints that a redundant mechanism's constraints do not
// determine (issue 22 item 1): the minimum-norm split.
//
// A redundant mechanism runs on an independent subset of its rows
// (redundancy.cpp): the rows set aside carry no multiplier, the kept rows of
// the joints in the dependency carry the whole load. That is one solution
// among many; the constraints fix only the generalized force the set S of
// those joints applies to the bodies,
//   f = G_S^T lambda_S          (G_S: S's rows over the bodies' velocities),
// and every lambda' with G_S^T lambda' = f is as good. The one reported is
// the least in the scaled norm,
//   min |W lambda'|  subject to  G_S^T lambda' = f,
// over all of S's rows, active and set aside: W = 1 on point rows (their
// multipliers are forces, N) and 1/L on angular rows (torques, N m, divided
// by the scene's length L, redundancy().length_scale), so that forces and
// torques are weighed in the same unit. With mu = W lambda' and
// A = G_S^T W^-1 the answer is mu = A^+ f (complete orthogonal
// decomposition: the minimum-norm solution of a consistent system), then
// lambda' = W^-1 mu.
//
// G_S is written over physical velocities, per body (x', omega in space),
// so the answer does not depend on the rotation coordinates or the form: a
// term c (u_a . u_b) with u = x + R s (a point) or R s (a direction) has the
// rate c (u_b . u_a' + u_a . u_b'), u' = x' + omega x (R s) for a point and
// omega x (R s) for a direction, so its row holds
//   on x'_a: c u_b (a point only),   on omega_a: c (R s_a) x u_b
// and the same with a and b exchanged. A pivoted body has omega alone, a
// point's lever measured from the pivot; a particle's omega columns are zero.
// Rows of joints outside S and bodies'
// own rows do not enter: their multipliers are determined.
#include <Eigen/QR>

#include <algorithm>

#include "rigidae/multibody/multibody_problem.hpp"

namespace rigidae::multibody {

namespace {

// Value of a body vector in space and its lever arm: a point's offset from
// the body's centre of mass (from its pivot when pivoted, whose velocity is
// then omega x lever alone), a direction itself; zero for the ground.
void place(const BodyState* st, const BodyModel* b, const BodyVector& bv, Vec3& value, Vec3& lever) {
  if (!st) {
    value = bv.s;
    lever.setZero();
    return;
  }
  VectorEval e;
  evaluate_vector(*st, bv, e);
  value = e.value;
  lever = !bv.point ? value : b->pivoted() ? Vec3(value - b->pivot) : Vec3(value - st->x());
}

}  // namespace

void MultibodyProblem::prepare_minimum_norm_reactions() {
  MinimumNormReactions& m = minimum_norm_;
  m.joints = redundancy_.indeterminate_joints;
  m.rows.clear();
  m.kept_lambda_offset.clear();
  m.bodies.clear();
  if (m.joints.empty()) return;
  // S's rows, joint by joint: every row of the joint's block, active or set
  // aside behind the mask (row_subset.cpp; a row set aside has its multiplier
  // held at 0 in y, so it adds nothing to f whichever rows are active).
  std::vector<int> first(spec_.joints.size(), -1);
  for (int j : m.joints) {
    first[j] = static_cast<int>(m.rows.size());
    const int b = block_of_joint_[j];
    if (b >= 0)
      for (int r = 0; r < blocks_[b].nr; ++r) {
        m.rows.push_back(&blocks_[b].rows[r]);
        m.kept_lambda_offset.push_back(blocks_[b].lambda_group >= 0 ? groups_[blocks_[b].lambda_group].offset + r : -1);
      }
    for (int body : {spec_.joints[j].body_a, spec_.joints[j].body_b})
      if (body != kGround && std::find(m.bodies.begin(), m.bodies.end(), body) == m.bodies.end())
        m.bodies.push_back(body);
  }
  m.first_row = std::move(first);
  const int nr = static_cast<int>(m.rows.size()), nc = 6 * static_cast<int>(m.bodies.size());
  m.A.setZero(nc, nr);
  m.weight.resize(nr);
  for (int r = 0; r < nr; ++r) m.weight(r) = m.rows[r]->reaction == RowReaction::Turn ? 1.0 / redundancy_.length_scale : 1.0;
  m.lambda.setZero(nr);
  m.f.setZero(nc);
  m.cod = Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd>(nc, nr);
  m.memo_y.resize(0);
}

bool MultibodyProblem::minimum_norm_applies(int joint) const {
  return !minimum_norm_.first_row.empty() && minimum_norm_.first_row[joint] >= 0;
}

void MultibodyProblem::solve_minimum_norm_reactions(const double* y) {
  MinimumNormReactions& m = minimum_norm_;
  const Eigen::Map<const Eigen::VectorXd> Y(y, n_);
  if (m.memo_y.size() == n_ && m.memo_y == Y) return;  // same state: output_row, then step_part_row
  if (y != evaluated_y_) evaluate(0.0, y, 2);
  const int nr = static_cast<int>(m.rows.size());
  // G_S^T, unscaled, over the physical velocities of S's bodies.
  m.A.setZero();
  const auto column_of = [&](int body) {
    return 6 * static_cast<int>(std::find(m.bodies.begin(), m.bodies.end(), body) - m.bodies.begin());
  };
  for (int r = 0; r < nr; ++r) {
    const ConstraintRow& row = *m.rows[r];
    for (int t = 0; t < row.n_terms; ++t) {
      const DotTerm& term = row.terms[t];
      const BodyVector* vec[2] = {&term.a, &term.b};
      Vec3 value[2], lever[2];
      for (int s = 0; s < 2; ++s)
        place(vec[s]->body == kGround ? nullptr : &work_[vec[s]->body].st,
              vec[s]->body == kGround ? nullptr : &bodies_[vec[s]->body], *vec[s], value[s], lever[s]);
      for (int s = 0; s < 2; ++s) {
        if (vec[s]->body == kGround) continue;
        const int c = column_of(vec[s]->body);
        const Vec3& other = value[1 - s];
        if (vec[s]->point && !bodies_[vec[s]->body].pivoted()) m.A.block<3, 1>(c, r) += term.coeff * other;
        m.A.block<3, 1>(c + 3, r) += term.coeff * lever[s].cross(other);
      }
    }
  }
  // f from the integrator's multipliers of the kept rows.
  m.f.setZero();
  for (int r = 0; r < nr; ++r)
    if (m.kept_lambda_offset[r] >= 0) m.f += m.A.col(r) * y[m.kept_lambda_offset[r]];
  // mu = (G_S^T W^-1)^+ f, lambda' = W^-1 mu.
  for (int r = 0; r < nr; ++r) m.A.col(r) /= m.weight(r);
  m.cod.compute(m.A);
  m.lambda = m.cod.solve(m.f);
  m.lambda.array() /= m.weight.array();
  m.memo_y = Y;
}

JointReaction MultibodyProblem::minimum_norm_reaction(int joint, const double* y) {
  solve_minimum_norm_reactions(y);
  const MinimumNormReactions& m = minimum_norm_;
  const int first = m.first_row[joint];
  const int count = block_of_joint_[joint] >= 0 ? blocks_[block_of_joint_[joint]].nr : 0;
  return reaction_of_rows(joint, &m.rows[first], m.lambda.data() + first, count);
}

}  // namespace rigidae::multibody
