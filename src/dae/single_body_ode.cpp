// The single rigid body as an ODE (equations and conventions in
// include/rigidae/dae/single_body_ode.hpp).
#include "rigidae/dae/single_body_ode.hpp"

#include <fmt/format.h>

#include <cmath>

#include <Eigen/Cholesky>

#include "rigidae/core/error.hpp"

namespace rigidae {

SingleBodyOde::SingleBodyOde(const DaeSystem& dae, const Scene& scene)
    : dae_(dae), chart_(dae.start_chart()), scene_(scene) {
  const Representation& r = rep();
  nq_ = r.nq();
  nv_ = r.nv();
  nc_ = r.nc();
  force_ = r.constraint_kind() == ConstraintKind::Force;
  const UnknownLayout& lay = dae.layout();
  if (lay.nq != nq_ || lay.nv != nv_ || lay.n_mu != 0 || lay.n_lambda != (force_ ? nc_ : 0))
    throw InputError(fmt::format("the ODE form of {} needs an acceleration-level scheme (index1 or projection), "
                                 "not '{}'",
                                 r.name(), dae.scheme().name()));
  q_.resize(nq_);
  v_.resize(nv_);
  acc_.resize(nv_);
  lambda_.setZero(force_ ? nc_ : 0);
  kernel_ = rep().euler_form_rate();
}

void SingleBodyOde::initial_state(double t0, Eigen::VectorXd& x) {
  chart_ = dae_.start_chart();
  kernel_ = rep().euler_form_rate();
  Eigen::VectorXd y, yp;
  dae_.consistent_state(chart_, t0, scene_.R0_WB, scene_.omega0_B, y, yp);
  const EulerChartSpec& charts = scene_.formulation.euler;
  const double margin = rep().chart_margin(dae_.coordinates(y.data()));
  if (rep().has_charts() && margin <= charts.switch_threshold) {
    if (!charts.switching)
      throw InputError(fmt::format(
          "{}: the Euler-angle sequence '{}' is within its singularity margin at t = {} (margin {:.3g} <= "
          "switch_threshold {}); choose another sequence, 'auto', or enable switching",
          scene_.source, rep().chart_name(), t0, margin, charts.switch_threshold));
    x = y.head(nq_ + nv_);
    // Rebuilt from the physical start in the new chart (as SingleBodyProblem
    // does: rates through the old chart are lost at its singularity).
    if (change_chart(t0, x)) {
      dae_.consistent_state(chart_, t0, scene_.R0_WB, scene_.omega0_B, y, yp);
      x = y.head(nq_ + nv_);
    }
    return;
  }
  x = y.head(nq_ + nv_);
}

void SingleBodyOde::absolute_tolerances(double /*rtol*/, double atol, const Eigen::VectorXd& /*x0*/,
                                        Eigen::Ref<Eigen::VectorXd> out) const {
  out.setConstant(atol);
}

namespace {

// Whether an LDLT of a symmetric positive semi-definite matrix can be used to
// solve with it: every pivot positive and none negligible against the largest.
// Linear coordinates in the Lagrange form have a mass matrix built from the
// body's second moments E = tr(J)/2 I - J; a lamina (J3 = J1 + J2) has no
// second moment along its normal, so M is singular there, while [M G^T; G 0]
// stays regular (M is positive definite on ker G: every admissible velocity
// has kinetic energy). Solving through M^-1 would then go wrong silently.
bool regular(const Eigen::LDLT<MatVV>& ldlt) {
  if (ldlt.info() != Eigen::Success || ldlt.rows() == 0) return ldlt.info() == Eigen::Success;
  const auto d = ldlt.vectorD();
  return d.minCoeff() > 1e-12 * d.cwiseAbs().maxCoeff();
}

using MatSaddle = BoundedMat<kMaxVelocities + kMaxConstraints, kMaxVelocities + kMaxConstraints>;
using VecSaddle = BoundedVec<kMaxVelocities + kMaxConstraints>;

}  // namespace

const Eigen::LDLT<MatVV>& SingleBodyOde::factorised_mass() {
  if (mass_factored_.rows() != terms_.M.rows() || mass_factored_ != terms_.M) {
    mass_factored_ = terms_.M;
    mass_ldlt_.compute(mass_factored_);
    mass_regular_ = regular(mass_ldlt_);
  }
  return mass_ldlt_;
}

void SingleBodyOde::saddle_point_solve(const VecV& top, const VecC& bottom, VecV& x, VecC& m) const {
  const int n = nv_ + nc_;
  MatSaddle K = MatSaddle::Zero(n, n);
  K.topLeftCorner(nv_, nv_) = terms_.M;
  K.topRightCorner(nv_, nc_) = terms_.G.transpose();
  K.bottomLeftCorner(nc_, nv_) = terms_.G;
  VecSaddle b(n);
  b << top, bottom;
  const VecSaddle s = K.fullPivLu().solve(b);
  x = s.head(nv_);
  m = s.tail(nc_);
}

bool SingleBodyOde::accelerations(double t, const double* x) {
  q_ = Eigen::Map<const Eigen::VectorXd>(x, nq_);
  v_ = Eigen::Map<const Eigen::VectorXd>(x + nq_, nv_);
  rep().evaluate(t, q_, v_, terms_);
  const Eigen::LDLT<MatVV>& M = factorised_mass();
  if (force_ && nc_ > 0 && !mass_regular_) {
    saddle_point_solve(terms_.f, terms_.gamma, acc_, lambda_);
  } else if (force_ && nc_ > 0) {
    // Schur complement of [M G^T; G 0]: S lambda = G M^-1 f - gamma.
    const VecV Minv_f = M.solve(terms_.f);
    const BoundedMat<kMaxVelocities, kMaxConstraints> Minv_Gt = M.solve(terms_.G.transpose());
    const BoundedMat<kMaxConstraints, kMaxConstraints> S = terms_.G * Minv_Gt;
    lambda_ = S.ldlt().solve(terms_.G * Minv_f - terms_.gamma);
    acc_ = Minv_f - Minv_Gt * lambda_;
  } else {
    acc_ = M.solve(terms_.f);
  }
  return acc_.allFinite() && terms_.qdot.allFinite();
}

bool SingleBodyOde::rhs(double t, const double* x, double* xdot) {
  if (kernel_) {
    // The same function at fixed size (no multipliers in the Euler form).
    kernel_->rate(x, xdot);
    // Finite iff the sum of 0 * entries is 0 (an inf or NaN entry makes it NaN).
    double zero = 0.0;
    for (int i = 0, n = nq_ + nv_; i < n; ++i) zero += 0.0 * xdot[i];
    return zero == 0.0;
  }
  const bool ok = accelerations(t, x);
  Eigen::Map<Eigen::VectorXd>(xdot, nq_) = terms_.qdot;
  Eigen::Map<Eigen::VectorXd>(xdot + nq_, nv_) = acc_;
  return ok;
}

OdeDrift SingleBodyOde::drift(double t, const double* x) const {
  // q and v sit at the same offsets in x and in the DAE's y.
  const ConstraintDrift d = dae_.drift(chart_, t, x);
  return {d.position, d.velocity};
}

void SingleBodyOde::project(double t, double* x) {
  q_ = Eigen::Map<const Eigen::VectorXd>(x, nq_);
  rep().project_coordinates(q_);
  Eigen::Map<Eigen::VectorXd>(x, nq_) = q_;
  if (!force_) return;
  // v - M^-1 G^T (G M^-1 G^T)^-1 G v: the nearest v with G v = 0 in kinetic energy.
  v_ = Eigen::Map<const Eigen::VectorXd>(x + nq_, nv_);
  rep().evaluate(t, q_, v_, terms_);
  const Eigen::LDLT<MatVV> M(terms_.M);
  if (!regular(M)) {
    // The same projection as the saddle point [M G^T; G 0] [v+; m] = [M v; 0].
    VecC m;
    const VecV Mv = terms_.M * v_;
    saddle_point_solve(Mv, VecC::Zero(nc_), v_, m);
    Eigen::Map<Eigen::VectorXd>(x + nq_, nv_) = v_;
    return;
  }
  const BoundedMat<kMaxVelocities, kMaxConstraints> Minv_Gt = M.solve(terms_.G.transpose());
  const BoundedMat<kMaxConstraints, kMaxConstraints> S = terms_.G * Minv_Gt;
  v_ -= Minv_Gt * S.ldlt().solve(terms_.G * v_);
  Eigen::Map<Eigen::VectorXd>(x + nq_, nv_) = v_;
}

void SingleBodyOde::project_error(double t, const double* x, double* e) {
  // The linearisations of project(): e_q orthogonally onto ker Phi_q, e_v
  // onto ker G in the metric of M.
  q_ = Eigen::Map<const Eigen::VectorXd>(x, nq_);
  v_ = Eigen::Map<const Eigen::VectorXd>(x + nq_, nv_);
  rep().evaluate(t, q_, v_, terms_);
  Eigen::Map<Eigen::VectorXd> eq(e, nq_);
  const BoundedMat<kMaxConstraints, kMaxConstraints> P = terms_.phi_q * terms_.phi_q.transpose();
  const VecC cq = P.ldlt().solve(terms_.phi_q * eq);
  eq -= terms_.phi_q.transpose() * cq;
  if (!force_) return;
  Eigen::Map<Eigen::VectorXd> ev(e + nq_, nv_);
  const Eigen::LDLT<MatVV> M(terms_.M);
  if (!regular(M)) {
    VecC m;
    VecV projected;
    const VecV Mev = terms_.M * ev;
    saddle_point_solve(Mev, VecC::Zero(nc_), projected, m);
    ev = projected;
    return;
  }
  const BoundedMat<kMaxVelocities, kMaxConstraints> Minv_Gt = M.solve(terms_.G.transpose());
  const BoundedMat<kMaxConstraints, kMaxConstraints> S = terms_.G * Minv_Gt;
  const VecC cv = S.ldlt().solve(terms_.G * ev);
  ev -= Minv_Gt * cv;
}

void SingleBodyOde::observe(double t, const double* x, Eigen::VectorXd& y) {
  y.setZero(dae_.size());
  y.head(nq_ + nv_) = Eigen::Map<const Eigen::VectorXd>(x, nq_ + nv_);
  if (force_ && nc_ > 0) {
    accelerations(t, x);
    y.segment(dae_.layout().lambda_offset(), nc_) = lambda_;
  }
}

int SingleBodyOde::event_count() const { return rep().has_charts() ? 1 : 0; }

void SingleBodyOde::event_functions(double /*t*/, const double* x, double* g) {
  q_ = Eigen::Map<const Eigen::VectorXd>(x, nq_);
  g[0] = rep().chart_margin(q_) - scene_.formulation.euler.switch_threshold;
}

StepAction SingleBodyOde::on_event(double t, Eigen::VectorXd& x) {
  StepAction a;
  if (!scene_.formulation.euler.switching) {
    const VecQ q = x.head(nq_);
    a.kind = StepAction::Kind::Fail;
    a.message = fmt::format(
        "chart singularity: root finding found the Euler-angle chart '{}' at its singularity margin {:.3g} at "
        "t = {:.9g} s (gimbal lock ahead; the angle rates would blow up). Chart switching is off: enable it "
        "([formulation.euler_angles] switching = true), or use quaternion or linear coordinates",
        rep().chart_name(), rep().chart_margin(q), t);
    return a;
  }
  if (!change_chart(t, x)) return a;  // already the most regular chart
  a.kind = StepAction::Kind::Restart;
  return a;
}

// Through the DAE's layout: DaeSystem::change_chart re-expresses (y, y') via
// the physical state (R, omega); the ODE keeps q and v of the result.
bool SingleBodyOde::change_chart(double t, Eigen::VectorXd& x) {
  const VecQ q = x.head(nq_);
  EventNote note;
  note.t = t;
  note.what = "chart_switch";
  note.from = rep().chart_name();
  note.margin = rep().chart_margin(q);
  Eigen::VectorXd y = Eigen::VectorXd::Zero(dae_.size()), yp = Eigen::VectorXd::Zero(dae_.size());
  y.head(nq_ + nv_) = x;
  const int to = dae_.change_chart(chart_, t, y, yp);
  if (to == chart_) return false;
  chart_ = to;
  kernel_ = rep().euler_form_rate();
  x = y.head(nq_ + nv_);
  note.to = rep().chart_name();
  notes_.push_back(std::move(note));
  return true;
}

std::vector<EventNote> SingleBodyOde::take_events() {
  std::vector<EventNote> out;
  out.swap(notes_);
  return out;
}

}  // namespace rigidae
