// The independent subset of the constraint rows, re-checked during the run
// (see the opening comment of multibody_problem.hpp, "Redundant
// constraints", and redundancy.cpp for the start's choice).
//
// With S G^T the scaled rows as columns (row_rank.hpp), K the rows
// integrated and D those set aside, each set-aside column is a combination
// of the kept ones while the rank holds:
//   S G_K^T alpha_d = S g_d     (least squares on the kept columns),
// and (alpha_d, -1) spans the dependency. The kept rows' conditioning is
// what the coefficients say: when a kept row's part in the dependency grows
// past the set-aside row's, |alpha| grows, and at the pose where the kept
// rows alone lose rank |alpha| -> infinity (the multipliers of the kept
// rows, the particular solution, follow it and Newton fails). Bricard's 6R
// loop does this at theta_1 = 0 (measured: |alpha| and the multiplier of H2
// grow like 1/|theta_1| before IDA fails at t = 1.634 s).
//
// The check, after every accepted step of a mechanism with rows set aside:
// max |alpha| > kMaxDependency times its value right after the last choice
// (at least 1: with several dependencies the best choice may leave some
// |alpha| above 1), or a relative least-squares residual above
// kMaxResidual (the set-aside row became independent: the rank went up,
// e.g. a singular start left behind), chooses the subset again at y:
// SuiteSparseQR's rank at the start's threshold gives how many rows to set
// aside and a basis N of the dependencies (rows x dependencies, N_D = -I,
// N_K = alpha); the rows set aside are then the pivots of a column-pivoted QR
// of N^T (the best-conditioned square block of N: for one dependency the row
// with the largest |N_k|, so afterwards every |alpha| <= 1). The bodies' own
// rows (Lagrange form) are never set aside.
//
// The rows stay in their blocks (the masks ConstraintBlock::active), so the
// unknowns and the iteration matrix's pattern do not change: the caller makes
// the multipliers consistent again and restarts the integrator (IDA) or just
// refactorises (the ODE form, whose state does not hold multipliers).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "rigidae/multibody/multibody_problem.hpp"
#include "row_rank.hpp"

namespace rigidae::multibody {

namespace {

constexpr double kMaxDependency = 10.0;  // |alpha| (relative to its value at the choice) at which the subset is chosen again
constexpr double kMaxResidual = 1e-6;    // relative: the set-aside row is no longer implied

}  // namespace

bool MultibodyProblem::check_row_subset(double t, const double* y) {
  if (redundancy_.dropped.empty()) return false;
  evaluate(t, y, 2);
  // Columns: the bodies' own rows, then every joint row block by block.
  std::vector<ForceRowRef> refs = internal_force_rows(bodies_);
  const int n_internal = static_cast<int>(refs.size());
  std::vector<int> block_of, row_of;
  for (int i = 0; i < n_internal; ++i) block_of.push_back(-1), row_of.push_back(refs[i].index);
  std::vector<int> kept, aside;
  for (int i = 0; i < n_internal; ++i) kept.push_back(i);
  for (int j = 0; j < static_cast<int>(blocks_.size()); ++j) {
    const ConstraintBlock& b = blocks_[j];
    if (b.internal) continue;
    for (int r = 0; r < b.nr; ++r) {
      (b.active[r] ? kept : aside).push_back(static_cast<int>(refs.size()));
      refs.push_back({-1, b.joint, r, &b.rows[r]});
      block_of.push_back(j);
      row_of.push_back(r);
    }
  }
  const SparseL Gt = scaled_transpose(
      refs, bodies_, velocity_offset_, nv_total_, [&](int b) { return &work_[b].st; },
      [&](int b) { return &work_[b].terms.G; }, redundancy_.length_scale, *dropped_eval_);
  double residual = 0.0;
  const Eigen::MatrixXd alpha = row_dependencies(Gt, kept, aside, residual);
  const double dependency = alpha.size() ? alpha.cwiseAbs().maxCoeff() : 0.0;
  largest_dependency_ = std::max(largest_dependency_, std::isfinite(dependency) ? dependency : 1e300);
  if (dependency <= kMaxDependency * std::max(1.0, subset_baseline_) && residual <= kMaxResidual) return false;

  // Choose again: how many rows are dependent here, and which to set aside.
  // (A body's own row among SPQR's set-aside columns is fine here:
  // best_set_aside chooses joint rows only.)
  const Rank rk = spqr_rank(Gt, redundancy_.threshold);
  std::vector<int> aside2(rk.perm.begin() + rk.rank, rk.perm.end()), kept2(rk.perm.begin(), rk.perm.begin() + rk.rank);
  std::sort(aside2.begin(), aside2.end());
  std::sort(kept2.begin(), kept2.end());
  const std::vector<int> chosen = best_set_aside(Gt, kept2, aside2, n_internal);
  // The coefficients of the new choice: the next check measures against them.
  std::vector<int> kept3;
  for (int c = 0; c < static_cast<int>(refs.size()); ++c)
    if (!std::binary_search(chosen.begin(), chosen.end(), c)) kept3.push_back(c);
  double residual3 = 0.0;
  const Eigen::MatrixXd alpha3 = row_dependencies(Gt, kept3, chosen, residual3);
  subset_baseline_ = alpha3.size() ? alpha3.cwiseAbs().maxCoeff() : 0.0;
  if (chosen == aside) return false;

  // The masks, the rows set aside now, and the event.
  std::string from, to, joints;
  const auto label = [&](int c) { return spec_.joints[refs[c].joint].name + "." + blocks_[block_of[c]].row_names[row_of[c]]; };
  std::vector<int> moved_joints;
  for (int c : aside) {
    from += (from.empty() ? "" : " ") + label(c);
    blocks_[block_of[c]].active[row_of[c]] = 1;
    if (std::find(chosen.begin(), chosen.end(), c) == chosen.end()) moved_joints.push_back(refs[c].joint);
  }
  set_aside_.clear();
  for (int c : chosen) {
    to += (to.empty() ? "" : " ") + label(c);
    blocks_[block_of[c]].active[row_of[c]] = 0;
    if (std::find(aside.begin(), aside.end(), c) == aside.end()) moved_joints.push_back(refs[c].joint);
    set_aside_.push_back({refs[c].joint, row_of[c], blocks_[block_of[c]].row_names[row_of[c]], *refs[c].row});
  }
  std::sort(moved_joints.begin(), moved_joints.end());
  moved_joints.erase(std::unique(moved_joints.begin(), moved_joints.end()), moved_joints.end());
  for (int j : moved_joints) joints += (joints.empty() ? "" : " ") + spec_.joints[j].name;
  ++subset_changes_;
  EventNote note;
  note.t = t;
  note.what = "row_subset";
  note.body = joints;
  note.from = from.empty() ? "-" : from;
  note.to = to.empty() ? "-" : to;
  // The largest |alpha|; infinite when the rows set aside were no longer implied.
  note.margin = residual > kMaxResidual ? std::numeric_limits<double>::infinity() : dependency;
  events_.push_back(note);
  drift_memo_valid_ = false;
  return true;
}

}  // namespace rigidae::multibody
