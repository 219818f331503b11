// One body's ODE form (equations and conventions in
// include/rigidae/schemes/body_ode.hpp). Every expression here is the one
// both ODE forms evaluate: a change changes the one-body and the multibody
// runs alike.
#include "rigidae/schemes/body_ode.hpp"

#include <Eigen/LU>

namespace rigidae::schemes {

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

BodyOde::BodyOde(const Representation& rep)
    : nq_(rep.nq()), nv_(rep.nv()), nc_(rep.nc()), force_(rep.constraint_kind() == ConstraintKind::Force) {
  q_.resize(nq_);
  v_.resize(nv_);
  acc_.resize(nv_);
  lambda_.setZero(force_ ? nc_ : 0);
}

const Eigen::LDLT<MatVV>& BodyOde::factorised_mass() {
  if (mass_factored_.rows() != terms_.M.rows() || mass_factored_ != terms_.M) {
    mass_factored_ = terms_.M;
    mass_ldlt_.compute(mass_factored_);
    mass_regular_ = regular(mass_ldlt_);
  }
  return mass_ldlt_;
}

void BodyOde::saddle_point_solve(const VecV& top, const VecC& bottom, VecV& x, VecC& m) const {
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

bool BodyOde::accelerations(const Representation& rep, double t, const double* x) {
  q_ = Eigen::Map<const Eigen::VectorXd>(x, nq_);
  v_ = Eigen::Map<const Eigen::VectorXd>(x + nq_, nv_);
  rep.evaluate(t, q_, v_, terms_);
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

bool BodyOde::rate(const Representation& rep, double t, const double* x, double* xdot) {
  if (const EulerFormRate* kernel = rep.euler_form_rate()) {
    // The same function at fixed size (no multipliers in the Euler form).
    kernel->rate(x, xdot);
    // Finite iff the sum of 0 * entries is 0 (an inf or NaN entry makes it NaN).
    double zero = 0.0;
    for (int i = 0, n = nq_ + nv_; i < n; ++i) zero += 0.0 * xdot[i];
    return zero == 0.0;
  }
  const bool ok = accelerations(rep, t, x);
  Eigen::Map<Eigen::VectorXd>(xdot, nq_) = terms_.qdot;
  Eigen::Map<Eigen::VectorXd>(xdot + nq_, nv_) = acc_;
  return ok;
}

BlockDrift BodyOde::drift(const Representation& rep, double t, const double* x) {
  if (nc_ == 0) return {};
  q_ = Eigen::Map<const Eigen::VectorXd>(x, nq_);
  v_ = Eigen::Map<const Eigen::VectorXd>(x + nq_, nv_);
  rep.evaluate(t, q_, v_, terms_);
  return block_drift(terms_, rep.constraint_kind(), v_);
}

void BodyOde::project(const Representation& rep, double t, double* x) {
  q_ = Eigen::Map<const Eigen::VectorXd>(x, nq_);
  rep.project_coordinates(q_);
  Eigen::Map<Eigen::VectorXd>(x, nq_) = q_;
  if (!force_) return;
  // v - M^-1 G^T (G M^-1 G^T)^-1 G v: the nearest v with G v = 0 in kinetic energy.
  v_ = Eigen::Map<const Eigen::VectorXd>(x + nq_, nv_);
  rep.evaluate(t, q_, v_, terms_);
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

void BodyOde::project_error(const Representation& rep, double t, const double* x, double* e) {
  // The linearisations of project(): e_q orthogonally onto ker Phi_q, e_v
  // onto ker G in the metric of M.
  q_ = Eigen::Map<const Eigen::VectorXd>(x, nq_);
  v_ = Eigen::Map<const Eigen::VectorXd>(x + nq_, nv_);
  rep.evaluate(t, q_, v_, terms_);
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

}  // namespace rigidae::schemes
