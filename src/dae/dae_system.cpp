#include "rigidae/dae/dae_system.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <fmt/format.h>

#include "rigidae/core/error.hpp"

namespace rigidae {

DaeSystem::DaeSystem(const Scene& scene, std::unique_ptr<Representation> rep,
                     std::unique_ptr<ConstraintScheme> scheme)
    : body_(make_rigid_body_model(scene)), rep_(std::move(rep)), scheme_(std::move(scheme)) {
  layout_ = scheme_->layout(*rep_);
  const int n = layout_.size();
  y_pert_.resize(n);
  yp_pert_.resize(n);
  F_plus_.resize(n);
  F_minus_.resize(n);
  F_base_.resize(n);
}

VecQ DaeSystem::coordinates(const double* y) const {
  return Eigen::Map<const Eigen::VectorXd>(y + layout_.q_offset(), layout_.nq);
}

VecV DaeSystem::velocities(const double* y) const {
  return Eigen::Map<const Eigen::VectorXd>(y + layout_.v_offset(), layout_.nv);
}

void DaeSystem::residual(double t, const double* y, const double* yp, double* F) const {
  const int n = layout_.size();
  rep_->evaluate(t, coordinates(y), velocities(y), terms_);
  scheme_->residual(terms_, layout_, Eigen::Map<const Eigen::VectorXd>(y, n), Eigen::Map<const Eigen::VectorXd>(yp, n),
                    Eigen::Map<Eigen::VectorXd>(F, n));
}

void DaeSystem::iteration_matrix(double t, double cj, const double* y, const double* yp, double* J) const {
  const int n = layout_.size();
  const Eigen::Map<const Eigen::VectorXd> ym(y, n), ypm(yp, n);
  const ConstVecRef y_ref(ym), yp_ref(ypm);
  Eigen::Map<Eigen::MatrixXd> Jm(J, n, n);
  const VecQ q = coordinates(y);
  const VecV v = velocities(y);
  const VecV a = ypm.segment(layout_.v_offset(), layout_.nv);
  rep_->evaluate(t, q, v, terms_);
  rep_->differentiate(t, q, v, a, derivs_);
  Jm.setZero();
  scheme_->iteration_matrix({*rep_, terms_, derivs_, layout_, y_ref, yp_ref, cj}, Jm);
}

bool DaeSystem::structurally_nonzero(int row, int col) const {
  const UnknownLayout& lay = layout_;
  const auto group = [&](int i) {  // 0 q, 1 v, 2 lambda, 3 mu
    return i < lay.v_offset() ? 0 : i < lay.lambda_offset() ? 1 : i < lay.mu_offset() ? 2 : 3;
  };
  const int rg = group(row), cg = group(col);
  if (cg <= 1) return true;            // every row depends on q and v (or q', v')
  if (cg == 2) return rg == 1;         // G^T lambda in the dynamic rows
  return rg == 0;                      // Phi_q^T mu in the kinematic rows
}

void DaeSystem::iteration_matrix_central(double t, double cj, const double* y, const double* yp, double* J) const {
  const int n = layout_.size();
  Eigen::Map<Eigen::MatrixXd> Jm(J, n, n);
  y_pert_ = Eigen::Map<const Eigen::VectorXd>(y, n);
  yp_pert_ = Eigen::Map<const Eigen::VectorXd>(yp, n);
  constexpr double kCentralStep = 6.0e-6;  // ~ cbrt(machine epsilon)
  residual(t, y, yp, F_base_.data());
  jacobian_residual_evals_ += 3 * n + 1;
  for (int j = 0; j < n; ++j) {
    // d/dy_j by central differences.
    const double yj = y[j];
    const double dy = kCentralStep * std::max(1.0, std::abs(yj));
    y_pert_(j) = yj + dy;
    residual(t, y_pert_.data(), yp, F_plus_.data());
    y_pert_(j) = yj - dy;
    residual(t, y_pert_.data(), yp, F_minus_.data());
    y_pert_(j) = yj;
    Jm.col(j) = (F_plus_ - F_minus_) / (2.0 * dy);
    // d/dy'_j exactly (F is affine in y'), by a difference with a large step.
    const double ypj = yp[j];
    const double dyp = std::max(1.0, std::abs(ypj));
    yp_pert_(j) = ypj + dyp;
    residual(t, y, yp_pert_.data(), F_plus_.data());
    yp_pert_(j) = ypj;
    Jm.col(j) += cj * (F_plus_ - F_base_) / dyp;
  }
}

void DaeSystem::consistent_state(double t, const Mat3& R_WB, const Vec3& omega_B, Eigen::VectorXd& y,
                                 Eigen::VectorXd& yp) const {
  VecQ q;
  VecV v;
  rep_->from_physical(R_WB, omega_B, q, v);
  y.setZero(layout_.size());
  y.segment(layout_.q_offset(), layout_.nq) = q;
  y.segment(layout_.v_offset(), layout_.nv) = v;
  make_consistent(t, y, yp);
}

void DaeSystem::make_consistent(double t, Eigen::VectorXd& y, Eigen::VectorXd& yp) const {
  yp.setZero(layout_.size());
  StandardTerms terms;
  rep_->evaluate(t, coordinates(y.data()), velocities(y.data()), terms);
  scheme_->consistent_start(terms, layout_, y, yp);
}

Eigen::VectorXd DaeSystem::differential_id() const {
  Eigen::VectorXd id = Eigen::VectorXd::Zero(layout_.size());
  id.head(layout_.nq + layout_.nv).setOnes();
  if (scheme_->suppress_velocity_error_test(*rep_)) id.segment(layout_.v_offset(), layout_.nv).setZero();
  return id;
}

std::vector<std::string> DaeSystem::multiplier_names() const {
  std::vector<std::string> names;
  const auto cn = rep_->constraint_names();
  for (int i = 0; i < layout_.n_lambda; ++i) names.push_back("lambda_" + cn[i]);
  for (int i = 0; i < layout_.n_mu; ++i) names.push_back("mu_" + cn[i]);
  return names;
}

ConstraintDrift DaeSystem::drift(double t, const double* y) const {
  ConstraintDrift d;
  if (rep_->nc() == 0) return d;
  StandardTerms terms;
  const VecV v = velocities(y);
  rep_->evaluate(t, coordinates(y), v, terms);
  d.position = terms.phi.norm();
  if (rep_->constraint_kind() == ConstraintKind::Force)
    d.velocity = (terms.G * v).norm();
  else
    d.velocity = (terms.phi_q * terms.qdot).norm();
  return d;
}

void DaeSystem::project(double t, Eigen::VectorXd& y, Eigen::VectorXd& yp) const {
  VecQ q = coordinates(y.data());
  rep_->project_coordinates(q);
  VecV v = velocities(y.data());
  if (rep_->constraint_kind() == ConstraintKind::Force) {
    StandardTerms terms;
    rep_->evaluate(t, q, v, terms);
    // v - M^-1 G^T (G M^-1 G^T)^-1 G v: the nearest v with G v = 0 in kinetic energy.
    const auto M = terms.M.ldlt();
    const MatCV MinvGt = M.solve(terms.G.transpose()).transpose();  // (M^-1 G^T)^T, nc x nv
    const MatCV& G = terms.G;
    const BoundedMat<kMaxConstraints, kMaxConstraints> S = G * MinvGt.transpose();
    v -= MinvGt.transpose() * S.ldlt().solve(G * v);
  }
  y.segment(layout_.q_offset(), layout_.nq) = q;
  y.segment(layout_.v_offset(), layout_.nv) = v;
  make_consistent(t, y, yp);
}

std::unique_ptr<DaeSystem> assemble_dae(const Scene& scene) {
  // One body only: a scene of bodies and joints must never run as the
  // default body its Scene::body holds.
  if (scene.multibody)
    throw InputError(fmt::format("{}: error: this scene has bodies and joints (schema_version = 2); the "
                                 "one-body model cannot run it, and this build has no multibody assembler",
                                 scene.source.empty() ? std::string("scene") : scene.source));
  const RigidBodyModel body = make_rigid_body_model(scene);
  return std::make_unique<DaeSystem>(scene, make_representation(scene, body),
                                     make_scheme(scene.formulation.scheme, scene));
}

}  // namespace rigidae
