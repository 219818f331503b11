// Redundant constraint rows and mobility at the start (see the opening
// comment of multibody_problem.hpp, "Redundant constraints").
//
// The rank decision: S G^T, S scaling the point rows by 1/L (L the largest
// joint-point offset from a body's centre of mass), factored by SuiteSparseQR
// (column = constraint row). SPQR sets aside a column whose norm, after the
// earlier columns' Householder reflections, is at most its threshold; that
// threshold is 1e-9 max_k |R_kk| of a first factorisation with SPQR's own
// default (20 (m + n) eps max column norm). Exact dependencies (a planar
// loop's out-of-plane rows) leave columns at ~1e-16; a pose at 1e-9 of a
// singular one is taken as singular.
//
// Indeterminate reactions: each set-aside column g_d is a combination of the
// kept ones, G_I^T alpha = g_d (least squares on the kept columns, full
// rank). Adding t (alpha, -1) to the multipliers leaves G^T lambda unchanged
// for every t, so every joint with a non-zero entry of (alpha, -1) has
// reactions the constraints do not determine.
#include <Eigen/SPQRSupport>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <set>

#include "rigidae/core/error.hpp"
#include "rigidae/core/text.hpp"
#include "rigidae/multibody/multibody_problem.hpp"
#include "row_rank.hpp"

namespace rigidae::multibody {

namespace {

using Triplet = Eigen::Triplet<double, SuiteSparse_long>;

constexpr double kRankRelTol = 1e-9;  // of max |R_kk|
constexpr double kNearbyStep = 1e-2;  // of L (and rad): how far the nearby poses lie

}  // namespace

void MultibodyProblem::physical_start(Eigen::VectorXd& y) const {
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const BodySpec& bs = spec_.bodies[i];
    const BodyModel& b = bodies_[i];
    VecQ q;
    VecV v;
    b.rep->from_physical(bs.R0_WB, bs.omega0_B, q, v);
    const int qo = groups_[b.q_group].offset, vo = groups_[b.v_group].offset;
    y.segment(qo, b.nx) = bs.x0_W.head(b.nx);  // a pivoted body has no x
    y.segment(qo + b.nx, b.nqr) = q;
    y.segment(vo, b.nx) = bs.v0_W.head(b.nx);
    y.segment(vo + b.nx, b.nvr) = v;
  }
}

std::string MultibodyProblem::dropped_row_source(int k) const {
  const JointSpec& j = spec_.joints[redundancy_.dropped[k].joint];
  if (j.where.file.empty() && j.where.line == 0) return "";
  return fmt::format("{}:{}:{}", j.where.file, j.where.line, j.where.column);
}


void MultibodyProblem::find_redundant_rows(const Scene& scene, std::vector<std::vector<ConstraintRow>>& rows) {
  RedundancyReport& rep = redundancy_;
  dropped_eval_ = std::make_unique<BlockEval>();
  dropped_of_joint_.assign(spec_.joints.size(), {});
  rep.velocities = nv_total_;
  // L: the largest joint-point offset from a body's centre of mass.
  double L = 0.0;
  for (const JointSpec& j : spec_.joints) {
    if (j.body_a != kGround) L = std::max(L, j.point_a.norm());
    if (j.body_b != kGround) L = std::max(L, j.point_b.norm());
  }
  rep.length_scale = L > 0.0 ? L : 1.0;
  std::vector<ForceRowRef> refs = internal_force_rows(bodies_);
  // Drivers before the joints: when rows depend on each other, the joints'
  // are set aside first (a driver fixes the motion; it is never redundant).
  for (int d = 0; d < static_cast<int>(drivers_.size()); ++d)
    refs.push_back({-1, spec_.drivers[d].joint, 0, nullptr, d, &drivers_[d]});
  for (int j = 0; j < static_cast<int>(rows.size()); ++j) {
    rep.joint_rows += static_cast<int>(rows[j].size());
    for (int r = 0; r < static_cast<int>(rows[j].size()); ++r) refs.push_back({-1, j, r, &rows[j][r]});
  }
  rep.rows = static_cast<int>(refs.size());
  // Gruebler-Kutzbach: each joint removes 6 minus the freedoms its type states
  // (model/joint_type.hpp), the rows it has before any are set aside.
  // A particle counts 3 (it has no rotations): 3 n_p + 6 n_b - rows; a
  // pivot holds like a spherical joint to the ground (3 fewer).
  rep.gruebler_dof = 0;
  for (const BodyModel& b : bodies_) rep.gruebler_dof += (b.particle ? 3 : 6) - (b.pivoted() ? 3 : 0);
  for (const JointSpec& js : spec_.joints) rep.gruebler_dof -= 6 - js.type->freedoms.total();
  rep.gruebler_dof -= static_cast<int>(spec_.drivers.size());
  rep.rank_dof = nv_total_;
  if (refs.empty()) return;

  Eigen::VectorXd y = Eigen::VectorXd::Zero(n_state_);
  physical_start(y);
  evaluate(scene.time.start, y.data(), 2);
  const SparseL Gt = scaled_transpose(
      refs, bodies_, velocity_offset_, nv_total_, [&](int b) { return &work_[b].st; },
      [&](int b) { return &work_[b].terms.G; }, rep.length_scale, *dropped_eval_, scene.time.start);
  const Rank first = spqr_rank(Gt, -1.0);
  rep.threshold = kRankRelTol * std::max(first.rmax, 1e-300);
  Rank rk = spqr_rank(Gt, rep.threshold);
  // The bodies' own rows come first: when the fill-reducing order sets one of
  // them aside, factor again in the given order, which sets aside joint rows.
  for (int k = rk.rank; k < static_cast<int>(rk.perm.size()); ++k)
    if (refs[rk.perm[k]].joint < 0 || refs[rk.perm[k]].driver >= 0) {
      rk = spqr_rank(Gt, rep.threshold, true);
      break;
    }
  rep.rank = rk.rank;
  rep.rank_dof = nv_total_ - rk.rank;
  if (rk.rank == rep.rows) return;

  // The rows set aside, in the scene's order.
  std::vector<int> aside(rk.perm.begin() + rk.rank, rk.perm.end());
  std::sort(aside.begin(), aside.end());
  for (int c : aside)
    if (refs[c].joint < 0)
      throw InputError(fmt::format("body '{}': its own constraint row {} depends on the joints' rows at the start; "
                                   "use coordinates without internal constraints (e.g. euler equations) for it",
                                   bodies_[refs[c].body].name, refs[c].index));
  for (int c : aside)
    if (refs[c].driver >= 0) {
      const DriverSpec& d = spec_.drivers[refs[c].driver];
      const JointSpec& js = spec_.joints[d.joint];
      throw InputError(fmt::format(
          "{}:{}:{}: error: the driver of joint '{}' ({}) prescribes a motion that the other constraints fix "
          "already (its row depends on theirs at the start): drive a coordinate that is free, or remove a driver",
          d.where.file, d.where.line, d.where.column, js.name, drivers_[refs[c].driver].coordinate->name));
    }
  std::vector<int> kept(rk.perm.begin(), rk.perm.begin() + rk.rank);
  std::sort(kept.begin(), kept.end());
  // Of the dependent rows, set aside the best-conditioned choice (each row
  // set aside with the largest part in its dependency: row_rank.hpp), the
  // one the run's re-check (row_subset.cpp) would keep.
  aside = best_set_aside(Gt, kept, aside, static_cast<int>(internal_force_rows(bodies_).size() + drivers_.size()));
  // Indeterminate reactions: G_I^T alpha = g_d over the kept columns.
  std::vector<char> is_aside(refs.size(), 0);
  for (int c : aside) is_aside[c] = 1;
  kept.clear();
  for (int c = 0; c < rep.rows; ++c)
    if (!is_aside[c]) kept.push_back(c);
  std::set<int> indeterminate;
  {
    double residual = 0.0;
    const Eigen::MatrixXd a = row_dependencies(Gt, kept, aside, residual);
    subset_baseline_ = start_baseline_ = std::max(1.0, a.size() ? a.cwiseAbs().maxCoeff() : 1.0);
  }
  {
    std::vector<Triplet> trip;
    Eigen::MatrixXd D = Eigen::MatrixXd::Zero(nv_total_, static_cast<int>(aside.size()));
    for (int k = 0; k < static_cast<int>(kept.size()); ++k)
      for (SparseL::InnerIterator it(Gt, kept[k]); it; ++it) trip.emplace_back(it.row(), k, it.value());
    for (int k = 0; k < static_cast<int>(aside.size()); ++k)
      for (SparseL::InnerIterator it(Gt, aside[k]); it; ++it) D(it.row(), k) = it.value();
    SparseL GI(nv_total_, static_cast<SuiteSparse_long>(kept.size()));
    GI.setFromTriplets(trip.begin(), trip.end());
    GI.makeCompressed();
    Eigen::SPQR<SparseL> qr;
    qr.compute(GI);
    if (qr.info() == Eigen::Success && !kept.empty()) {
      // Column by column: Eigen's SPQR solves one right-hand side at a time
      // (a matrix is an assertion failure with assertions on, and without
      // them only its first column is solved).
      Eigen::MatrixXd alpha(static_cast<int>(kept.size()), D.cols());
      for (int d = 0; d < D.cols(); ++d) alpha.col(d) = qr.solve(Eigen::VectorXd(D.col(d)));
      for (int d = 0; d < alpha.cols(); ++d) {
        indeterminate.insert(refs[aside[d]].joint);
        for (int k = 0; k < alpha.rows(); ++k)
          if (std::abs(alpha(k, d)) > 1e-8 && refs[kept[k]].joint >= 0 && refs[kept[k]].driver < 0)
            indeterminate.insert(refs[kept[k]].joint);
      }
    } else {
      for (int c : aside) indeterminate.insert(refs[c].joint);
    }
  }
  rep.indeterminate_joints.assign(indeterminate.begin(), indeterminate.end());
  // The rows set aside: they stay in their joints' blocks, inactive (the
  // blocks' masks are set from rep.dropped when the blocks are built).
  std::vector<std::vector<int>> drop(rows.size());
  for (int c : aside) drop[refs[c].joint].push_back(refs[c].index);
  for (int j = 0; j < static_cast<int>(rows.size()); ++j) {
    std::sort(drop[j].begin(), drop[j].end());
    for (int r : drop[j]) {
      dropped_of_joint_[j].push_back(static_cast<int>(rep.dropped.size()));
      rep.dropped.push_back({j, r, rows[j][r].name, rows[j][r]});
    }
  }
  set_aside_ = rep.dropped;
  std::string list;
  for (int k = 0; k < static_cast<int>(rep.dropped.size()); ++k) {
    const RedundantRow& d = rep.dropped[k];
    list += fmt::format("{}{}.{}", k ? ", " : "", spec_.joints[d.joint].name, d.row);
  }
  std::string joints;
  for (int j : rep.indeterminate_joints) joints += (joints.empty() ? "" : ", ") + spec_.joints[j].name;
  const std::string src = dropped_row_source(0);
  warnings_.push_back(fmt::format(
      "{}{} of the {} constraint rows {} redundant at the start (rank {}): set aside and monitored as drift: {}; "
      "the reactions of joints {} are not determined by the constraints (statically indeterminate: their force and "
      "torque columns are the minimum-norm split over those joints' rows, torques divided by L = {:.6g} m; their "
      "lambda columns are the kept rows' multipliers)",
      src.empty() ? "" : src + ": ", rep.dropped.size(), rep.rows, rep.dropped.size() == 1 ? "is" : "are", rep.rank,
      list, joints, rep.length_scale));
}

int MultibodyProblem::full_rank(double t, const double* y) {
  evaluate(t, y, 2);
  std::vector<ForceRowRef> refs = internal_force_rows(bodies_);
  for (const ConstraintBlock& b : blocks_)
    if (b.driver >= 0)
      refs.push_back({-1, b.joint, 0, nullptr, b.driver, &drivers_[b.driver]});
    else if (!b.internal)
      for (int r = 0; r < b.nr; ++r) refs.push_back({-1, b.joint, r, &b.rows[r]});  // active or set aside
  const SparseL Gt = scaled_transpose(
      refs, bodies_, velocity_offset_, nv_total_, [&](int b) { return &work_[b].st; },
      [&](int b) { return &work_[b].terms.G; }, redundancy_.length_scale, *dropped_eval_, t);
  return spqr_rank(Gt, redundancy_.threshold).rank;
}

std::pair<double, double> MultibodyProblem::dropped_drift(const double* y) {
  double pos = 0.0, vel = 0.0;
  if (set_aside_.empty()) return {pos, vel};
  if (y != evaluated_y_) evaluate(0.0, y, 2);
  for (int k = 0; k < static_cast<int>(set_aside_.size()); ++k) {
    evaluate_dropped_row(k);
    pos = std::max(pos, std::abs(dropped_eval_->phi(0)));
    vel = std::max(vel, std::abs(dropped_eval_->Gv(0)));
  }
  return {pos, vel};
}

void MultibodyProblem::check_redundant_rows(double t0) {
  if (redundancy_.dropped.empty()) return;
  const double L = redundancy_.length_scale;
  // The dropped rows after the projection onto the kept ones: implied, so
  // they hold; a miss means the loop does not close in that direction.
  evaluate(t0, y0_.data(), 2);
  for (int k = 0; k < static_cast<int>(redundancy_.dropped.size()); ++k) {
    const RedundantRow& d = redundancy_.dropped[k];
    const JointSpec& js = spec_.joints[d.joint];
    const double miss = dropped_row_miss(k);
    if (miss > spec_.start_tolerance) {
      const std::string src = dropped_row_source(k);
      throw InputError(fmt::format(
          "{}joint '{}' ({}) row '{}': the loop does not close: this row, dependent on the others at the start and "
          "set aside, misses by {:.3g} once the other rows hold (more than start_tolerance {:g}); place the bodies "
          "so that the joint holds",
          src.empty() ? "" : src + ": error: ", js.name, js.type->name, d.row, miss, spec_.start_tolerance));
    }
  }
  // Nearby poses: along the start's velocity and a random admissible one.
  int nearby = -1;
  std::mt19937_64 rng(20261126);
  std::normal_distribution<double> normal;
  for (int pass = 0; pass < 2; ++pass) {
    Eigen::VectorXd y = y0_, yp = yp0_;
    try {
      if (pass == 1) {
        for (std::size_t i = 0; i < bodies_.size(); ++i) {
          const UnknownGroup& g = groups_[bodies_[i].v_group];
          for (int k = 0; k < g.size; ++k) y(g.offset + k) = normal(rng) * (k < bodies_[i].nx ? L : 1.0);
        }
        project(t0, y, yp);
      }
      double s = 0.0;
      for (const BodyModel& b : bodies_) {
        const UnknownGroup& g = groups_[b.q_group];
        if (b.nx > 0) s = std::max(s, yp.segment(g.offset, b.nx).norm() / L);
        if (b.nqr > 0) s = std::max(s, yp.segment(g.offset + b.nx, b.nqr).cwiseAbs().maxCoeff());
      }
      if (!(s > 1e-12) || !std::isfinite(s)) continue;
      const double h = kNearbyStep / s;
      for (const BodyModel& b : bodies_) {
        const UnknownGroup& g = groups_[b.q_group];
        y.segment(g.offset, g.size) += h * yp.segment(g.offset, g.size);
      }
      project(t0, y, yp);
      nearby = std::max(nearby, full_rank(t0, y.data()));
    } catch (const std::runtime_error&) {
      // A nearby pose the projection cannot reach says nothing: skip it.
    }
  }
  evaluate(t0, y0_.data(), 2);
  redundancy_.nearby_rank = nearby;
  if (nearby > redundancy_.rank) {
    redundancy_.singular_start = true;
    const std::string src = dropped_row_source(0);
    warnings_.push_back(fmt::format(
        "{}singular start: the constraint rows have rank {} at the start but {} at nearby poses, so {} of the rows "
        "set aside are dependent only at this pose (a dead-centre or flattened loop): the assembly branch is "
        "ambiguous and the motion may leave the rows set aside (their drift is monitored); start off the singular "
        "pose",
        src.empty() ? "" : src + ": ", redundancy_.rank, nearby, nearby - redundancy_.rank));
  }
}

void MultibodyProblem::evaluate_dropped_row(int k) {
  const RedundantRow& d = set_aside_[k];
  const JointSpec& js = spec_.joints[d.joint];
  BlockSides sides;
  sides.body[0] = js.body_a;
  sides.body[1] = js.body_b;
  for (int x = 0; x < 2; ++x) sides.state[x] = sides.body[x] == kGround ? nullptr : &work_[sides.body[x]].st;
  evaluate_rows(&d.constraint, 1, sides, *dropped_eval_);
}

double MultibodyProblem::dropped_row_miss(int k) {
  evaluate_dropped_row(k);
  return std::abs(dropped_eval_->phi(0));
}

}  // namespace rigidae::multibody
