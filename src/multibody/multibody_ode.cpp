// A mechanism as an ODE (equations and conventions in
// include/rigidae/multibody/multibody_ode.hpp).
#include "rigidae/multibody/multibody_ode.hpp"

#include <fmt/format.h>
#include <klu.h>

#include <algorithm>
#include <cmath>

#include "rigidae/core/error.hpp"
#include "schur_saddle.hpp"
#include "small_lu.hpp"

namespace rigidae::multibody {

namespace {

// A pivot this small against the largest: the KKT matrix is taken as
// singular (the constraints lost rank, or a body has no mass on ker G).
constexpr double kSingularPivotRatio = 1e-13;
// W's absolute tolerance: its error weight 1e-100 keeps it out of the error
// test (and of CVODE's Newton convergence test) without a zero weight.
constexpr double kWorkAtol = 1e100;

}  // namespace

// KLU on the KKT matrix's fixed pattern: analysed once, refactorised in place
// with the pivot order of the last full factorisation (no allocation), and
// factorised afresh (new pivots) when the pivot ratio has dropped by 1e3
// since that factorisation: old pivots can turn bad as the mechanism moves.
class KluSaddle {
 public:
  KluSaddle(int n, std::vector<int> col_start, std::vector<int> rows)
      : n_(n), ap_(std::move(col_start)), ai_(std::move(rows)) {
    klu_defaults(&common_);
    symbolic_ = klu_analyze(n_, ap_.data(), ai_.data(), &common_);
    if (!symbolic_) throw SolverError(fmt::format("KLU could not analyse the {0} x {0} KKT pattern", n_));
  }
  ~KluSaddle() {
    if (numeric_) klu_free_numeric(&numeric_, &common_);
    if (symbolic_) klu_free_symbolic(&symbolic_, &common_);
  }
  KluSaddle(const KluSaddle&) = delete;
  KluSaddle& operator=(const KluSaddle&) = delete;

  // Factorises the matrix of values ax (the pattern's order); false if singular.
  bool factorise(double* ax) {
    if (numeric_ && klu_refactor(ap_.data(), ai_.data(), ax, symbolic_, numeric_, &common_) &&
        klu_rcond(symbolic_, numeric_, &common_) && common_.rcond >= 1e-3 * fresh_rcond_ &&
        common_.rcond >= kSingularPivotRatio)
      return true;
    if (numeric_) klu_free_numeric(&numeric_, &common_);
    ++fresh_factorisations_;
    numeric_ = klu_factor(ap_.data(), ai_.data(), ax, symbolic_, &common_);
    if (!numeric_ || !klu_rcond(symbolic_, numeric_, &common_)) {
      fresh_rcond_ = 0.0;
      return false;
    }
    fresh_rcond_ = common_.rcond;
    return common_.rcond >= kSingularPivotRatio;
  }
  void solve(double* b) { klu_solve(symbolic_, numeric_, n_, 1, b, &common_); }
  long fresh_factorisations() const { return fresh_factorisations_; }

 private:
  int n_;
  std::vector<int> ap_, ai_;
  klu_common common_;
  klu_symbolic* symbolic_ = nullptr;
  klu_numeric* numeric_ = nullptr;
  double fresh_rcond_ = 0.0;
  long fresh_factorisations_ = 0;
};

MultibodyOde::MultibodyOde(MultibodyProblem& problem, bool sparse, const std::string& where, bool small_dense,
                           bool by_body, bool schur)
    : problem_(problem) {
  n_ = problem.size();
  n_state_ = problem.state_size();
  for (const ConstraintBlock& blk : problem.blocks())
    if (blk.mu_group >= 0 || blk.lambda_group < 0 || blk.kind != ConstraintKind::Force ||
        blk.lambda_rows.acceleration == 0.0)
      throw InputError(fmt::format("{}: error: the ODE form of a mechanism needs an acceleration-level scheme "
                                   "(valid: index1, projection), not '{}'",
                                   where, problem.scheme().name));
  for (const BodyModel& b : problem.bodies()) has_internal_ = has_internal_ || b.rep->nc() > 0;
  by_body_ = by_body && problem.bodies_decoupled();
  // Decoupled bodies have no drivers and no force element acting on them: no work.
  integrates_work_ = problem.has_work() && !by_body_;
  if (by_body_) {
    for (std::size_t i = 0; i < problem.bodies().size(); ++i) {
      const BodyModel& b = problem.bodies()[i];
      body_ode_.emplace_back(*b.rep);
      body_offset_.push_back(problem.groups()[b.q_group].offset);
      if (problem.groups()[b.v_group].offset != body_offset_.back() + b.nqr)
        throw SolverError("MultibodyOde: a pivoted body's q and v are not contiguous");
      body_lambda_offset_.push_back(-1);
    }
    for (const ConstraintBlock& blk : problem.blocks())
      body_lambda_offset_[static_cast<std::size_t>(blk.body)] = problem.groups()[blk.lambda_group].offset;
    single_body_ = body_ode_.size() == 1 && body_offset_[0] == 0;
  }

  // Which unknowns of y are q, v or multipliers.
  std::vector<int> pos(n_, -1);
  for (const BodyModel& b : problem.bodies()) {
    const UnknownGroup& q = problem.groups()[b.q_group];
    for (int k = 0; k < q.size; ++k) q_index_.push_back(q.offset + k);
    const UnknownGroup& v = problem.groups()[b.v_group];
    for (int k = 0; k < v.size; ++k) s_index_.push_back(v.offset + k);
  }
  nv_ = static_cast<int>(s_index_.size());
  for (const ConstraintBlock& blk : problem.blocks()) {
    const UnknownGroup& l = problem.groups()[blk.lambda_group];
    for (int k = 0; k < l.size; ++k) s_index_.push_back(l.offset + k);
  }
  std::sort(s_index_.begin(), s_index_.end());
  ns_ = static_cast<int>(s_index_.size());
  n_lambda_ = ns_ - nv_;
  for (int k = 0; k < ns_; ++k) pos[s_index_[k]] = k;
  // The KKT unknowns are velocities then multipliers: the bodies' groups come first in y.
  for (int k = 0; k < nv_; ++k)
    if (s_index_[k] >= n_state_) throw SolverError("MultibodyOde: the layout is not (q | v | lambda)");

  // The KKT block of the pattern, in compressed columns (its order is the pattern's).
  const SparsityPattern& p = problem.sparsity();
  std::vector<int> ap(ns_ + 1, 0), ai;
  for (int c = 0; c < ns_; ++c) {
    const int col = s_index_[c];
    for (std::int64_t k = p.col_start[col]; k < p.col_start[col + 1]; ++k) {
      const int r = pos[p.rows[k]];
      if (r < 0) continue;
      k_from_.push_back(k);
      k_row_.push_back(r);
      k_col_.push_back(c);
      ai.push_back(r);
    }
    ap[c + 1] = static_cast<int>(ai.size());
  }
  if (!sparse) values_.setZero(p.nnz());  // the dense paths copy the KKT block from it
  kkt_values_.setZero(static_cast<Eigen::Index>(k_from_.size()));
  solution_.setZero(ns_);
  y_.setZero(n_);
  yp_zero_.setZero(n_);
  F0_.setZero(n_);
  rhs_.setZero(ns_);
  lambda_.setZero(n_lambda_);
  y_drift_.setZero(n_);
  xdot_scratch_.setZero(size());
  if (sparse) {
    // The linear part written straight into the KKT block (no pass over the
    // whole iteration-matrix pattern, 3.4x the KKT block's entries on the
    // 1000-link chain); the q rows' identity goes to a scratch range after it.
    int largest = 0;
    for (const UnknownGroup& g : problem.groups()) largest = std::max(largest, g.size);
    const auto dump = static_cast<std::int64_t>(k_from_.size());
    std::vector<std::int64_t> position(static_cast<std::size_t>(p.nnz()), dump);
    for (std::size_t k = 0; k < k_from_.size(); ++k)
      position[static_cast<std::size_t>(k_from_[k])] = static_cast<std::int64_t>(k);
    kkt_sink_ = problem.sparsity_sink().remapped(position);
    kkt_values_.setZero(static_cast<Eigen::Index>(k_from_.size()) + largest);
    if (schur && n_lambda_ > 0) make_schur(pos, ap, ai);
    klu_ = std::make_unique<KluSaddle>(ns_, std::move(ap), std::move(ai));
  } else if (small_dense && ns_ <= SmallLu::kCapacity) {
    small_ = std::make_unique<SmallLu>();
    small_->resize(ns_);  // zero outside the pattern, for ever
  } else {
    K_.setZero(ns_, ns_);
    lu_ = Eigen::PartialPivLU<Eigen::MatrixXd>(ns_);
  }
}

MultibodyOde::~MultibodyOde() = default;

void MultibodyOde::make_schur(const std::vector<int>& pos, const std::vector<int>& col_start,
                              const std::vector<int>& rows) {
  // The bodies' velocity ranges and the blocks' multiplier ranges in KKT
  // order (contiguous there as in y: s_index_ is y's order).
  auto range = [&](const UnknownGroup& g) {
    const KktRange r{pos[g.offset], g.size};
    for (int k = 0; k < g.size; ++k)
      if (pos[g.offset + k] != r.start + k)
        throw SolverError("MultibodyOde: a group is not contiguous in the KKT order");
    return r;
  };
  std::vector<KktRange> bodies, blocks;
  for (const BodyModel& b : problem_.bodies()) bodies.push_back(range(problem_.groups()[b.v_group]));
  lambda_block_.assign(n_lambda_, -1);
  lambda_row_.assign(n_lambda_, -1);
  for (int j = 0; j < static_cast<int>(problem_.blocks().size()); ++j) {
    const KktRange r = range(problem_.groups()[problem_.blocks()[j].lambda_group]);
    blocks.push_back(r);
    for (int k = 0; k < r.size; ++k) {
      lambda_block_[r.start - nv_ + k] = j;
      lambda_row_[r.start - nv_ + k] = k;
    }
  }
  schur_ = SchurSaddle::make(bodies, blocks, col_start, rows);
  active_.assign(n_lambda_, 1);
  // w_A is the scheme's, fixed when the problem is assembled.
  inv_weight_.resize(n_lambda_);
  for (int k = 0; k < n_lambda_; ++k)
    inv_weight_[k] = 1.0 / problem_.blocks()[lambda_block_[k]].lambda_rows.acceleration;
}

void MultibodyOde::initial_state(double t0, Eigen::VectorXd& x) {
  Eigen::VectorXd y, yp;
  problem_.initial_state(t0, y, yp);
  x.setZero(size());
  x.head(n_state_) = y.head(n_state_);  // W(t0) = 0
  last_work_ = 0.0;
}

void MultibodyOde::absolute_tolerances(double /*rtol*/, double atol, const Eigen::VectorXd& /*x0*/,
                                       Eigen::Ref<Eigen::VectorXd> out) const {
  out.setConstant(atol);  // the DAE's tolerance of q and v (MultibodyProblem::absolute_tolerances)
  if (integrates_work_) out[n_state_] = kWorkAtol;
}

bool MultibodyOde::factorise(double t, const double* x) {
  y_.head(n_state_) = Eigen::Map<const Eigen::VectorXd>(x, n_state_);
  y_.tail(n_ - n_state_).setZero();
  if (!problem_.residual(t, y_.data(), yp_zero_.data(), F0_.data())) return false;
  for (int k = 0; k < ns_; ++k) rhs_[k] = -F0_[s_index_[k]];
  if (klu_) {
    kkt_values_.setZero();
    problem_.linear_part_into(t, y_.data(), *kkt_sink_, kkt_values_.data(), /*just_evaluated=*/true);
    schur_used_ = false;
    if (schur_) {
      // The subset of rows set aside may change after any step (row_subset.cpp).
      for (int k = 0; k < n_lambda_; ++k) active_[k] = problem_.blocks()[lambda_block_[k]].active[lambda_row_[k]];
      switch (schur_->factorise(kkt_values_.data(), active_.data())) {
        case SchurSaddle::Outcome::Factorised: return schur_used_ = true;
        case SchurSaddle::Outcome::NotApplicable: schur_.reset(); break;  // KLU from now on
        case SchurSaddle::Outcome::Singular: break;                       // KLU's pivoting may still succeed
      }
    }
    return klu_->factorise(kkt_values_.data());
  }
  problem_.linear_part_sparse(t, y_.data(), values_.data(), /*just_evaluated=*/true);
  if (small_) {
    SmallLu& K = *small_;
    for (std::size_t k = 0; k < k_from_.size(); ++k) K(k_row_[k], k_col_[k]) = values_[k_from_[k]];
    return K.factorise() >= kSingularPivotRatio;
  }
  for (std::size_t k = 0; k < k_from_.size(); ++k) K_(k_row_[k], k_col_[k]) = values_[k_from_[k]];
  lu_.compute(K_);
  const auto d = lu_.matrixLU().diagonal().cwiseAbs();
  return d.minCoeff() >= kSingularPivotRatio * d.maxCoeff();
}


bool MultibodyOde::solve(const Eigen::VectorXd& b) {
  if (schur_used_) {
    solution_ = b;
    schur_->solve(solution_.data(), inv_weight_.data());
  } else if (klu_) {
    solution_ = b;
    klu_->solve(solution_.data());
  } else if (small_) {
    solution_ = b;
    small_->solve(solution_.data());
  } else {
    solution_.noalias() = lu_.solve(b);
  }
  return solution_.allFinite();
}

bool MultibodyOde::rhs(double t, const double* x, double* xdot) {
  // One decoupled body (a one-body scene) as a bare tail call to the
  // one-body arithmetic; everything else out of line, so that this path
  // pays no register saves (measured on the heavy top, quaternion/euler on
  // ARKODE: 16.61 M instructions with the loop in this function, 16.02 M
  // so; the one-body form 15.85 M; bench/callgrind_through_system.sh).
  if (single_body_) return body_ode_[0].rate(*problem_.bodies()[0].rep, t, x, xdot);
  return rhs_general(t, x, xdot);
}

bool MultibodyOde::rhs_general(double t, const double* x, double* xdot) {
  if (by_body_) {
    bool ok = true;
    for (std::size_t i = 0; i < body_ode_.size(); ++i)
      ok = body_ode_[i].rate(body_rep(i), t, x + body_offset_[i], xdot + body_offset_[i]) && ok;
    return ok;
  }
  if (!factorise(t, x) || !solve(rhs_)) return false;
  // q' = -F_q(t, (q, v, 0), 0); v' and lambda from the KKT solution.
  for (int i : q_index_) xdot[i] = -F0_[i];
  for (int k = 0; k < nv_; ++k) xdot[s_index_[k]] = solution_[k];
  lambda_ = solution_.tail(n_lambda_);
  for (int i : q_index_)
    if (!std::isfinite(xdot[i])) return false;
  if (integrates_work_) {
    // W' = P at the state and the KKT solution's multipliers, written into
    // y_, at whose positions and velocities factorise's residual evaluated
    // the bodies (measured on crank_slider_driven, arkode-erk index1: the
    // second evaluation was 5.6 % of the run's instructions).
    for (int k = nv_; k < ns_; ++k) y_[s_index_[k]] = solution_[k];
    xdot[n_state_] = problem_.work_rate(t, y_.data(), /*just_evaluated=*/true);
    if (!std::isfinite(xdot[n_state_])) return false;
  }
  return true;
}

OdeDrift MultibodyOde::drift(double t, const double* x) const {
  if (by_body_) {
    // The one-body rule per body (2-norms), the largest over bodies.
    OdeDrift d{0.0, 0.0};
    for (std::size_t i = 0; i < body_ode_.size(); ++i) {
      const schemes::BlockDrift b = body_ode_[i].drift(body_rep(i), t, x + body_offset_[i]);
      d.position = std::max(d.position, b.position);
      d.velocity = std::max(d.velocity, b.velocity);
    }
    return d;
  }
  y_drift_.head(n_state_) = Eigen::Map<const Eigen::VectorXd>(x, n_state_);
  y_drift_.tail(n_ - n_state_).setZero();
  // The max norms of the records, not the per-block 2-norms that trigger the
  // IDA path's projection (MultibodyProblem::projection_drift). Measured:
  // with the 2-norms cvode-bdf on heavy_top_absolute at rtol 1e-8 projects
  // more often and ends 9.1e-5 rad from IDA's rtol 1e-11 run, against 5.6e-6
  // rad with these (tests/unit/test_multibody_ode.cpp bounds it by 1e-5).
  const auto [position, velocity] = problem_.drift(t, y_drift_.data());
  return {position, velocity};
}

void MultibodyOde::project(double t, double* x) {
  if (by_body_) {
    for (std::size_t i = 0; i < body_ode_.size(); ++i) body_ode_[i].project(body_rep(i), t, x + body_offset_[i]);
    return;
  }
  y_big_.setZero(n_);
  yp_big_.setZero(n_);
  y_big_.head(n_state_) = Eigen::Map<const Eigen::VectorXd>(x, n_state_);
  problem_.project(t, y_big_, yp_big_);
  Eigen::Map<Eigen::VectorXd>(x, n_state_) = y_big_.head(n_state_);
}

void MultibodyOde::project_error(double t, const double* x, double* e) {
  if (by_body_) {  // each body's exact linearisation
    for (std::size_t i = 0; i < body_ode_.size(); ++i)
      body_ode_[i].project_error(body_rep(i), t, x + body_offset_[i], e + body_offset_[i]);
    return;
  }
  // The linearisation of project() at x (CVODE-BDF passes the point just
  // projected) by a difference of project() itself: (P(x + s e) - P(x)) / s,
  // s |e| = 1e-6 max(1, |x|). Both the position part (Gauss-Newton onto
  // Phi = 0, the quaternion norm) and the velocity part (onto G v = 0, with
  // its dependence on q) are projected: the normal component of e, which
  // carries the projection's own correction, leaves the error test.
  Eigen::Map<Eigen::VectorXd> E(e, n_state_);
  const Eigen::Map<const Eigen::VectorXd> X(x, n_state_);
  const double e_max = E.cwiseAbs().maxCoeff();
  if (e_max == 0.0 || !std::isfinite(e_max)) return;
  const double s = 1e-6 * std::max(1.0, X.cwiseAbs().maxCoeff()) / e_max;
  error_base_ = X;
  project(t, error_base_.data());
  error_moved_ = X + s * E;
  project(t, error_moved_.data());
  E = (error_moved_ - error_base_) / s;
}

void MultibodyOde::observe(double t, const double* x, Eigen::VectorXd& y) {
  y.setZero(observed_size());
  y.head(n_state_) = Eigen::Map<const Eigen::VectorXd>(x, n_state_);
  if (integrates_work_) y[n_] = last_work_ = x[n_state_];
  if (n_lambda_ == 0) return;
  if (by_body_) {  // each body's own multipliers (Lagrange form), from its Schur complement
    for (std::size_t i = 0; i < body_ode_.size(); ++i) {
      schemes::BodyOde& b = body_ode_[i];
      if (body_lambda_offset_[i] < 0 || !b.force() || b.nc() == 0) continue;
      b.accelerations(body_rep(i), t, x + body_offset_[i]);
      y.segment(body_lambda_offset_[i], b.nc()) = b.multipliers();
    }
    return;
  }
  if (!rhs(t, x, xdot_scratch_.data())) {
    for (int k = nv_; k < ns_; ++k) y[s_index_[k]] = std::nan("");
    return;
  }
  for (int k = nv_; k < ns_; ++k) y[s_index_[k]] = solution_[k];
}

void MultibodyOde::event_functions(double t, const double* x, double* g) {
  // Reads q only: x holds the state at the DAE's offsets.
  problem_.event_functions(t, x, g);
}

StepAction MultibodyOde::on_event(double t, Eigen::VectorXd& x) {
  y_big_.setZero(n_);
  yp_big_.setZero(n_);
  y_big_.head(n_state_) = x.head(n_state_);
  const StepAction a = problem_.on_event(t, 0.0, y_big_, yp_big_);
  if (a.kind == StepAction::Kind::Restart) x.head(n_state_) = y_big_.head(n_state_);  // W kept
  return a;
}

void MultibodyOde::after_step(double t, const double* x) {
  // Decoupled bodies have no joints (no row subsets, no joint coordinates'
  // branches) and no force element acting on them: nothing follows the motion.
  if (by_body_) return;
  y_drift_.head(n_state_) = Eigen::Map<const Eigen::VectorXd>(x, n_state_);
  y_drift_.tail(n_ - n_state_).setZero();
  problem_.follow_motion(t, y_drift_.data());
  // The independent subset of the rows (row_subset.cpp): the state holds no
  // multipliers, so a new subset only changes the next KKT factorisation.
  // The branch check across singular poses reads the state's derivative.
  const double* xdot = nullptr;
  if (problem_.watches_singular_poses() && rhs(t, x, xdot_scratch_.data())) xdot = xdot_scratch_.data();
  problem_.check_row_subset(t, y_drift_.data(), /*multipliers_in_y=*/false, xdot);
}

double MultibodyOde::stop_time_hint() const { return problem_.stop_time_hint(); }

double MultibodyOde::bridge(double t, Eigen::VectorXd& x) {
  if (by_body_ || !problem_.bridges_singular_poses() || !problem_.watches_singular_poses()) return 0.0;
  // The DAE's layout: the state, no multipliers (the bridge recomputes its
  // nodes' derivatives and the landing's multipliers itself).
  y_big_.setZero(n_);
  yp_big_.setZero(n_);
  y_big_.head(n_state_) = x.head(n_state_);
  const double landing = problem_.bridge_after_step(t, y_big_, yp_big_);
  if (landing > t) x.head(n_state_) = y_big_.head(n_state_);  // W kept: the bridge spans an instant
  return landing;
}

void MultibodyOde::bridged_observation(double t, Eigen::VectorXd& y) {
  problem_.bridged_state(t, y);
  if (!integrates_work_) return;
  // The bridge's nodes inside a step: W as last observed (the bridge spans
  // a small fraction of a step).
  y.conservativeResize(observed_size());
  y[n_] = last_work_;
}

std::string MultibodyOde::describe_stall(double t, const double* x) {
  y_big_.setZero(n_);
  y_big_.head(n_state_) = Eigen::Map<const Eigen::VectorXd>(x, n_state_);
  return problem_.describe_stall(t, y_big_.data());
}

long MultibodyOde::fresh_factorisations() const { return klu_ ? klu_->fresh_factorisations() : 0; }

}  // namespace rigidae::multibody
