#include "rigidae/dae/dae_system.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "rigidae/core/error.hpp"
#include "rigidae/schemes/body_rows.hpp"

namespace rigidae {

DaeSystem::DaeSystem(RigidBodyModel body, std::unique_ptr<Representation> rep,
                     std::unique_ptr<ConstraintScheme> scheme)
    : body_(std::move(body)), start_chart_(rep->chart()), scheme_(std::move(scheme)) {
  layout_ = scheme_->layout(*rep);
  charts_.resize(static_cast<std::size_t>(rep->chart_count()));
  for (int c = 0; c < rep->chart_count(); ++c)
    if (c != start_chart_) charts_[static_cast<std::size_t>(c)] = rep->in_chart(c);
  charts_[static_cast<std::size_t>(start_chart_)] = std::move(rep);
  const UnknownLayout& lay = layout_;
  const int n = lay.size();
  pattern_.col_start.push_back(0);
  for (int c = 0; c < n; ++c) {
    for (int r = 0; r < n; ++r)
      if (structurally_nonzero(r, c)) pattern_.rows.push_back(r);
    pattern_.col_start.push_back(static_cast<std::int64_t>(pattern_.rows.size()));
  }
  lambda_values_ = static_cast<std::int64_t>(n) * (lay.nq + lay.nv);
  mu_values_ = lambda_values_ + static_cast<std::int64_t>(lay.nv) * lay.n_lambda;
  // The blocks' offsets hold only if the pattern is laid out as the view assumes.
  if (pattern_.col_start[lay.lambda_offset()] != lambda_values_ || pattern_.col_start[lay.mu_offset()] != mu_values_ ||
      pattern_.nnz() != mu_values_ + static_cast<std::int64_t>(lay.nq) * lay.n_mu)
    throw std::logic_error("DaeSystem: the sparse pattern does not have the iteration matrix's block layout");
}

VecQ DaeSystem::coordinates(const double* y) const {
  return Eigen::Map<const Eigen::VectorXd>(y + layout_.q_offset(), layout_.nq);
}

VecV DaeSystem::velocities(const double* y) const {
  return Eigen::Map<const Eigen::VectorXd>(y + layout_.v_offset(), layout_.nv);
}

void DaeSystem::residual(int chart, double t, const double* y, const double* yp, double* F) const {
  const int n = layout_.size();
  StandardTerms terms;  // fixed-size: on the stack
  representation(chart).evaluate(t, coordinates(y), velocities(y), terms);
  scheme_->residual(terms, layout_, Eigen::Map<const Eigen::VectorXd>(y, n), Eigen::Map<const Eigen::VectorXd>(yp, n),
                    Eigen::Map<Eigen::VectorXd>(F, n));
}

void DaeSystem::assemble_iteration_matrix(int chart, double t, double cj, const double* y, const double* yp,
                                          IterationMatrixView& J) const {
  const int n = layout_.size();
  const Eigen::Map<const Eigen::VectorXd> ym(y, n), ypm(yp, n);
  const ConstVecRef y_ref(ym), yp_ref(ypm);
  const VecQ q = coordinates(y);
  const VecV v = velocities(y);
  const VecV a = ypm.segment(layout_.v_offset(), layout_.nv);
  const Representation& rep = representation(chart);
  StandardTerms terms;  // fixed-size: on the stack
  TermDerivatives derivs;
  rep.evaluate(t, q, v, terms);
  rep.differentiate(t, q, v, a, derivs);
  scheme_->iteration_matrix({rep, terms, derivs, layout_, y_ref, yp_ref, cj}, J);
}

void DaeSystem::iteration_matrix(int chart, double t, double cj, const double* y, const double* yp, double* J) const {
  const UnknownLayout& lay = layout_;
  const int n = lay.size();
  Eigen::Map<Eigen::MatrixXd> Jm(J, n, n);
  Jm.setZero();
  IterationMatrixView view{Jm.leftCols(lay.nq + lay.nv),
                           Jm.block(lay.v_offset(), lay.lambda_offset(), lay.nv, lay.n_lambda),
                           Jm.block(lay.q_offset(), lay.mu_offset(), lay.nq, lay.n_mu)};
  assemble_iteration_matrix(chart, t, cj, y, yp, view);
}

void DaeSystem::iteration_matrix_sparse(int chart, double t, double cj, const double* y, const double* yp,
                                        double* values) const {
  const UnknownLayout& lay = layout_;
  std::fill(values, values + pattern_.nnz(), 0.0);
  Eigen::Map<Eigen::MatrixXd> state(values, lay.size(), lay.nq + lay.nv);
  Eigen::Map<Eigen::MatrixXd> lambda(values + lambda_values_, lay.nv, lay.n_lambda);
  Eigen::Map<Eigen::MatrixXd> mu(values + mu_values_, lay.nq, lay.n_mu);
  IterationMatrixView view{state, lambda, mu};
  assemble_iteration_matrix(chart, t, cj, y, yp, view);
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

void DaeSystem::consistent_state(int chart, double t, const Mat3& R_WB, const Vec3& omega_B, Eigen::VectorXd& y,
                                 Eigen::VectorXd& yp) const {
  VecQ q;
  VecV v;
  representation(chart).from_physical(R_WB, omega_B, q, v);
  y.setZero(layout_.size());
  y.segment(layout_.q_offset(), layout_.nq) = q;
  y.segment(layout_.v_offset(), layout_.nv) = v;
  make_consistent(chart, t, y, yp);
}

void DaeSystem::make_consistent(int chart, double t, Eigen::VectorXd& y, Eigen::VectorXd& yp) const {
  yp.setZero(layout_.size());
  StandardTerms terms;
  representation(chart).evaluate(t, coordinates(y.data()), velocities(y.data()), terms);
  scheme_->consistent_start(terms, layout_, y, yp);
}

Eigen::VectorXd DaeSystem::differential_id() const {
  Eigen::VectorXd id = Eigen::VectorXd::Zero(layout_.size());
  id.head(layout_.nq + layout_.nv).setOnes();
  if (scheme_->suppress_velocity_error_test(representation().constraint_kind()))
    id.segment(layout_.v_offset(), layout_.nv).setZero();
  return id;
}

std::vector<std::string> DaeSystem::multiplier_names() const {
  std::vector<std::string> names;
  const auto cn = representation().constraint_names();
  for (int i = 0; i < layout_.n_lambda; ++i) names.push_back("lambda_" + cn[i]);
  for (int i = 0; i < layout_.n_mu; ++i) names.push_back("mu_" + cn[i]);
  return names;
}

ConstraintDrift DaeSystem::drift(int chart, double t, const double* y) const {
  ConstraintDrift d;
  const Representation& rep = representation(chart);
  if (rep.nc() == 0) return d;
  StandardTerms terms;
  const VecV v = velocities(y);
  rep.evaluate(t, coordinates(y), v, terms);
  const schemes::BlockDrift b = schemes::block_drift(terms, rep.constraint_kind(), v);
  d.position = b.position;
  d.velocity = b.velocity;
  return d;
}

void DaeSystem::project(int chart, double t, Eigen::VectorXd& y, Eigen::VectorXd& yp) const {
  const Representation& rep = representation(chart);
  VecQ q = coordinates(y.data());
  rep.project_coordinates(q);
  VecV v = velocities(y.data());
  if (rep.constraint_kind() == ConstraintKind::Force) {
    StandardTerms terms;
    rep.evaluate(t, q, v, terms);
    schemes::project_velocities(terms, v);  // the nearest v with G v = 0 in kinetic energy
  }
  y.segment(layout_.q_offset(), layout_.nq) = q;
  y.segment(layout_.v_offset(), layout_.nv) = v;
  make_consistent(chart, t, y, yp);
}

int DaeSystem::change_chart(int chart, double t, Eigen::VectorXd& y, Eigen::VectorXd& yp) const {
  const Representation& from = representation(chart);
  const VecQ q = coordinates(y.data());
  const int best = from.most_regular_chart(q);
  if (best == chart) return chart;
  // Through the physical state: the orientation and the body angular
  // velocity are the same in every chart.
  VecQ q_new;
  VecV v_new;
  representation(best).from_physical(from.placement(q), from.body_angular_velocity(q, velocities(y.data())), q_new,
                                     v_new);
  y.segment(layout_.q_offset(), layout_.nq) = q_new;
  y.segment(layout_.v_offset(), layout_.nv) = v_new;
  make_consistent(best, t, y, yp);
  return best;
}

std::unique_ptr<DaeSystem> assemble_dae(const Scene& scene) {
  // One body only: a scene of bodies and joints must never run as the
  // default body its Scene::body holds.
  if (scene.multibody)
    throw InputError(fmt::format("{}: error: this scene has bodies and joints (schema_version = 2); the "
                                 "one-body model cannot run it, and this build has no multibody assembler",
                                 scene.source.empty() ? std::string("scene") : scene.source));
  const RigidBodyModel body = make_rigid_body_model(scene);
  return std::make_unique<DaeSystem>(body, make_representation(scene, body),
                                     make_scheme(scene.formulation.scheme, scheme_settings(scene)));
}

}  // namespace rigidae
