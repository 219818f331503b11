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
// grow like 1/|theta_1| before IDA fails at t = 1.38 s in ggl).
//
// Ill-conditioned kept rows matter only where load passes through the
// dependency. The amplification
//   A = |mu_K| / |mu*|,   mu_K = S^-1 lambda_K (the kept multipliers in the
//   scaled units),  mu* = (S G^T)^+ (S G_K^T mu_K)  (the minimum-norm
//   multipliers over all rows giving the same generalized force G^T lambda),
// says by how much the choice of rows inflates the multipliers: 1 when the
// dependency carries no load (a planar linkage's out-of-plane rows: the
// driven crank-slider's |alpha| passes 235 at a regular pose with A = 1),
// growing with |alpha| where it does (Bricard: A = 2.8 at |alpha| = 10,
// 41 at 143 just before IDA fails). A new choice is not free: it restarts
// the integrator, and a restarted IDA with index1's multipliers (left out of
// the error test) can carry an alternating error in them that grows x1.33
// per step (measured on the driven crank-slider after a restart alone, same
// rows: driving torque 1e-4 off; without the restart 1e-9).
//
// The check, after every accepted step of a mechanism with rows set aside:
// max |alpha| > kMaxDependency times its value right after the last choice
// (at least 1: with several dependencies the best choice may leave some
// |alpha| above 1) and A > kMaxAmplification (read from y's multipliers;
// the ODE form, whose state holds none, uses |alpha| alone), or a relative
// least-squares residual above kMaxResidual (the set-aside row became
// independent: the rank went up, e.g. a singular start left behind),
// chooses the subset again at y:
// SuiteSparseQR's rank at the start's threshold gives how many rows to set
// aside and a basis N of the dependencies (rows x dependencies, N_D = -I,
// N_K = alpha); the rows set aside are then the pivots of a column-pivoted QR
// of N^T (the best-conditioned square block of N: for one dependency the row
// with the largest |N_k|, so afterwards every |alpha| <= 1). The bodies' own
// rows (Lagrange form) are never set aside.
//
// Singular poses: a rank loss of the WHOLE set of rows (a parallelogram
// four-bar reaching its collinear pose: in-plane rows, while the rows set
// aside are out-of-plane ones), where no choice of rows helps. The watch:
// |R_rr| / |R_11| of a column-pivoted QR of all of S G^T, r the start's
// rank (the r-th pivot: how far the rows are from rank r - 1), relative to
// its value at the first check, below kSingularCondition is a singular pose,
// noted once per approach (singular_poses(), an event "singular_pose"
// naming the joints of the nearly vanishing combination of rows, margin =
// that relative ratio): assembly branches cross there and the run may leave
// its branch, which rigidae cannot tell in general; the caller warns. The
// kept rows alone are not watched: they may turn ill-conditioned at a
// regular pose (the crank-slider's at t = 0.264 s), which is the re-check's
// business. Only in mechanisms with rows set aside (where the check runs
// anyway), when S G^T is small.
//
// The rows stay in their blocks (the masks ConstraintBlock::active), so the
// unknowns and the iteration matrix's pattern do not change: the caller makes
// the multipliers consistent again and restarts the integrator (IDA) or just
// refactorises (the ODE form, whose state does not hold multipliers).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/QR>
#include <Eigen/SVD>

#include "rigidae/multibody/multibody_problem.hpp"
#include "row_rank.hpp"

namespace rigidae::multibody {

namespace {

constexpr double kMaxDependency = 10.0;  // |alpha| (relative to its value at the choice) at which the subset is chosen again
constexpr double kMaxAmplification = 2.0;  // ... when the kept rows also inflate the multipliers this much
constexpr double kMaxResidual = 1e-4;    // relative: the set-aside row is no longer implied (above the drift)
// All the rows' conditioning at the start's rank (|R_rr| / |R_11| of S G^T,
// relative to the start's) below which the pose is taken as singular, and
// the size of S G^T up to which the watch runs (dense QR: ~10 us at 20 x 20).
constexpr double kSingularCondition = 2e-2;
constexpr long kDenseWatch = 40000;
// The rank tolerance during the run (relative to the largest singular value
// or |R_kk|): above the drift off the manifold, below any real direction.
constexpr double kRunRankTol = 1e-6;

}  // namespace

double MultibodyProblem::multiplier_amplification(const SparseL& Gt, const std::vector<ForceRowRef>& refs,
                                                  const std::vector<int>& block_of, const std::vector<int>& kept,
                                                  const double* y) const {
  if (static_cast<long>(Gt.rows()) * Gt.cols() > kDenseWatch) return std::numeric_limits<double>::infinity();
  const double L = redundancy_.length_scale;
  // Each kept row's multiplier in y, in the units of its column of S G^T
  // (a point row's column is divided by L, so its multiplier times L).
  Eigen::VectorXd muK(static_cast<int>(kept.size()));
  for (int k = 0; k < static_cast<int>(kept.size()); ++k) {
    const ForceRowRef& f = refs[kept[k]];
    int block = block_of[kept[k]], row = f.index;
    double scale = 1.0;
    if (f.driver >= 0) {
      for (int j = 0; j < static_cast<int>(blocks_.size()); ++j)
        if (blocks_[j].driver == f.driver) block = j;
      row = 0;
      if (f.drive->coordinate->kind == CoordinateKind::Length) scale = L;
    } else if (f.joint < 0) {
      for (int j = 0; j < static_cast<int>(blocks_.size()); ++j)
        if (blocks_[j].internal && blocks_[j].body == f.body) block = j;
    } else if (is_point_row(*f.row)) {
      scale = L;
    }
    const int g = block >= 0 ? blocks_[block].lambda_group : -1;
    muK(k) = g >= 0 ? scale * y[groups_[g].offset + row] : 0.0;
  }
  const double kept_norm = muK.norm();
  if (!(kept_norm > 0.0)) return 1.0;  // nothing loads the rows: nothing is inflated
  const Eigen::MatrixXd G(Gt);
  Eigen::MatrixXd GK(G.rows(), static_cast<int>(kept.size()));
  for (int k = 0; k < static_cast<int>(kept.size()); ++k) GK.col(k) = G.col(kept[k]);
  // The minimum-norm multipliers over all rows, at the run's rank tolerance
  // (off the manifold the dependency leaves a singular value of the drift's
  // size, which must count as zero here).
  Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod;
  cod.setThreshold(kRunRankTol);
  cod.compute(G);
  const double least = cod.solve(Eigen::VectorXd(GK * muK)).norm();
  return kept_norm / std::max(least, 1e-300 * kept_norm);
}

int MultibodyProblem::held_unknowns() const {
  int held = 0;
  for (const ConstraintBlock& b : blocks_)
    for (int r = 0; r < b.nr; ++r)
      if (!b.active[r]) held += (b.lambda_group >= 0 ? 1 : 0) + (b.mu_group >= 0 ? 1 : 0);
  return held;
}

bool MultibodyProblem::check_row_subset(double t, const double* y, bool multipliers_in_y, const double* yp) {
  // Mechanisms with rows set aside only: the check costs ~11 us a step on
  // a four-bar (+37 % of the user time of problems/four_bar.toml, 5,557
  // steps: measured with the watch on and off), too much for every closed
  // loop; a loop without redundant rows that stalls at a singular pose is
  // still named by describe_stall (stall_report.cpp).
  const bool redundant = !redundancy_.dropped.empty();
  if (!redundant) return false;
  evaluate(t, y, 2);
  // Columns: the bodies' own rows and the drivers' (never set aside: a
  // driver fixes the motion), then every joint row block by block.
  std::vector<ForceRowRef> refs = internal_force_rows(bodies_);
  for (int d = 0; d < static_cast<int>(drivers_.size()); ++d)
    refs.push_back({-1, spec_.drivers[d].joint, 0, nullptr, d, &drivers_[d]});
  const int n_internal = static_cast<int>(refs.size());  // the protected columns
  std::vector<int> block_of, row_of;
  for (int i = 0; i < n_internal; ++i) block_of.push_back(-1), row_of.push_back(refs[i].index);
  std::vector<int> kept, aside;
  for (int i = 0; i < n_internal; ++i) kept.push_back(i);
  for (int j = 0; j < static_cast<int>(blocks_.size()); ++j) {
    const ConstraintBlock& b = blocks_[j];
    if (b.internal || b.driver >= 0) continue;
    for (int r = 0; r < b.nr; ++r) {
      (b.active[r] ? kept : aside).push_back(static_cast<int>(refs.size()));
      refs.push_back({-1, b.joint, r, &b.rows[r]});
      block_of.push_back(j);
      row_of.push_back(r);
    }
  }
  const SparseL Gt = scaled_transpose(
      refs, bodies_, velocity_offset_, nv_total_, [&](int b) { return &work_[b].st; },
      [&](int b) { return &work_[b].terms.G; }, redundancy_.length_scale, *dropped_eval_, t);
  watch_singular_pose(t, Gt, refs);
  check_branch(t, y, yp);
  double residual = 0.0;
  const Eigen::MatrixXd alpha = row_dependencies(Gt, kept, aside, residual);
  const double dependency = alpha.size() ? alpha.cwiseAbs().maxCoeff() : 0.0;
  largest_dependency_ = std::max(largest_dependency_, std::isfinite(dependency) ? dependency : 1e300);
  // The baseline is the smallest |alpha| since the last choice: growth from
  // it is what the check watches (after a singular pose the coefficients fall
  // back, and the next approach is measured from there).
  subset_baseline_ = std::min(subset_baseline_, std::max(1.0, dependency));
  if (residual <= kMaxResidual) {
    if (dependency <= kMaxDependency * subset_baseline_) return false;
    // Ill-conditioned kept rows: chosen again only when they inflate the
    // multipliers (the opening comment), read from y where it holds them.
    if (multipliers_in_y) {
      const double amplification = multiplier_amplification(Gt, refs, block_of, kept, y);
      largest_amplification_ = std::max(largest_amplification_, amplification);
      if (amplification <= kMaxAmplification) return false;
    }
  }

  // Choose again: how many rows are dependent here, and which to set aside.
  // Off the constraint manifold (the drift, ~ the tolerance) a dependency
  // that holds only on it (Bricard's) leaves a singular value of the drift's
  // size: the rank is decided at kRunRankTol, far above the drift, and the
  // number of rows set aside never grows here (a rank loss of all the rows
  // is a singular pose, only watched); it shrinks when rows became
  // independent (a singular start left behind).
  std::vector<int> chosen;
  const int m = static_cast<int>(refs.size()), nd_now = static_cast<int>(aside.size());
  if (static_cast<long>(Gt.rows()) * m <= kDenseWatch) {
    // Dense: the dependencies are the right singular vectors of S G^T of the
    // smallest singular values (m - rank of them).
    const Eigen::MatrixXd Gd(Gt);
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(Gd, Eigen::ComputeFullV);
    const Eigen::VectorXd& sv = svd.singularValues();
    int rank = 0;
    for (int k = 0; k < sv.size(); ++k) rank += sv(k) > kRunRankTol * sv(0) ? 1 : 0;
    const int nd = std::min(nd_now, m - rank);
    if (nd > 0) {
      Eigen::MatrixXd Nt = svd.matrixV().rightCols(nd).transpose();
      Nt.leftCols(n_internal).setZero();  // a body's own rows stay
      const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(Nt);
      const auto& perm = qr.colsPermutation().indices();
      for (int d = 0; d < nd; ++d) chosen.push_back(perm(d));
      std::sort(chosen.begin(), chosen.end());
    }
  } else {
    // Sparse: SuiteSparseQR at the same tolerance (a body's own row among its
    // set-aside columns is fine: best_set_aside chooses joint rows only).
    const Rank first = spqr_rank(Gt, -1.0);
    const Rank rk = spqr_rank(Gt, std::max(redundancy_.threshold, kRunRankTol * first.rmax));
    std::vector<int> aside2(rk.perm.begin() + rk.rank, rk.perm.end()), kept2(rk.perm.begin(), rk.perm.begin() + rk.rank);
    std::sort(aside2.begin(), aside2.end());
    std::sort(kept2.begin(), kept2.end());
    if (static_cast<int>(aside2.size()) <= nd_now) chosen = best_set_aside(Gt, kept2, aside2, n_internal);
    else chosen = aside;  // more dependent rows than before: a singular pose, not a new subset
  }
  // The coefficients of the new choice: the next check measures against them.
  std::vector<int> kept3;
  for (int c = 0; c < static_cast<int>(refs.size()); ++c)
    if (!std::binary_search(chosen.begin(), chosen.end(), c)) kept3.push_back(c);
  double residual3 = 0.0;
  const Eigen::MatrixXd alpha3 = row_dependencies(Gt, kept3, chosen, residual3);
  subset_baseline_ = std::max(1.0, alpha3.size() ? alpha3.cwiseAbs().maxCoeff() : 0.0);
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

void MultibodyProblem::watch_singular_pose(double t, const SparseL& Gt, const std::vector<ForceRowRef>& refs) {
  const int r = redundancy_.rank;  // the start's rank of all the rows
  if (r <= 0 || static_cast<long>(Gt.rows()) * Gt.cols() > kDenseWatch) return;
  const Eigen::MatrixXd G(Gt);
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(G);
  const auto d = qr.matrixR().diagonal().cwiseAbs();
  if (d.size() < r) return;
  const double ratio = d(r - 1) / std::max(d(0), 1e-300);
  if (start_condition_ < 0.0) start_condition_ = ratio;  // the first check: the start's
  const double relative = ratio / std::max(start_condition_, 1e-300);
  // A bridge across the pose ahead (pose_bridge.cpp) notes the pose now,
  // before the watch's own threshold is reached.
  const bool bridge_now = bridge_.enabled && plan_bridge(t, relative);
  if (near_singular_ && bridge_now && !singular_poses_.empty()) {
    near_singular_ = false;  // noted at the last step, bridged from this one
    singular_poses_.back().t = bridge_.pose_t;
    singular_poses_.back().condition = std::min(singular_poses_.back().condition, relative);
    return;
  }
  if (near_singular_) {
    if (relative > 2.0 * kSingularCondition) near_singular_ = false;  // left it behind
    if (!singular_poses_.empty()) singular_poses_.back().condition = std::min(singular_poses_.back().condition, relative);
    return;
  }
  if (relative >= kSingularCondition && !bridge_now) return;
  near_singular_ = !bridge_now;
  // The joints in the near-dependency: the right singular vector of S G^T of
  // its r-th singular value (the combination of rows that nearly vanishes
  // beyond the start's dependencies).
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(G, Eigen::ComputeFullV);
  const Eigen::VectorXd v = svd.matrixV().col(r - 1);
  std::vector<int> joints;
  for (int k = 0; k < static_cast<int>(v.size()); ++k)
    if (std::abs(v(k)) > 0.1 * v.cwiseAbs().maxCoeff() && refs[k].joint >= 0) joints.push_back(refs[k].joint);
  std::sort(joints.begin(), joints.end());
  joints.erase(std::unique(joints.begin(), joints.end()), joints.end());
  SingularPose sp;
  sp.t = bridge_now ? bridge_.pose_t : t;
  sp.condition = relative;
  for (int j : joints) sp.joints += (sp.joints.empty() ? "" : " ") + spec_.joints[j].name;
  singular_poses_.push_back(sp);
  events_.push_back(EventNote::at_joints(sp.t, "singular_pose", sp.joints, relative));
}

}  // namespace rigidae::multibody
