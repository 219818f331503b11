// Constraint blocks by kind, checked on the residual by differences: what a
// multiplier does depends on how its block's constraints are held.
//   Kept by the kinematics (Euler form): q' = N v - Phi_q^T mu, M v' = f.
//     The dynamics carry no multiplier at all, and mu moves q' only off the
//     manifold (Phi_q N = 0: no component along an admissible q' = N w).
//   Held by forces (Lagrange form): M v' = f - G^T lambda.
//     lambda enters the dynamics only, and its force does no work on a
//     velocity the constraints allow (G w = 0); GGL's mu again moves q' only
//     off the manifold.
// Every scheme states its rows per kind; this holds for each of them.
#include <doctest/doctest.h>

#include <Eigen/Dense>
#include <string>

#include "rigidae/app/compare.hpp"
#include "rigidae/app/solve.hpp"
#include "rigidae/dae/dae_system.hpp"
#include "rigidae/schemes/scheme.hpp"
#include "test_scenes.hpp"

TEST_SUITE_BEGIN("unit");

using namespace rigidae;

namespace {

// dF/d(y_k) by a difference; F is linear in the multipliers, so h = 1 is exact up to round-off.
Eigen::VectorXd column(const DaeSystem& dae, int chart, const Eigen::VectorXd& y, const Eigen::VectorXd& yp, int k) {
  Eigen::VectorXd F0(dae.size()), F1(dae.size()), y1 = y;
  y1[k] += 1.0;
  dae.residual(chart, 0.0, y.data(), yp.data(), F0.data());
  dae.residual(chart, 0.0, y1.data(), yp.data(), F1.data());
  return F1 - F0;
}

// Admissible coordinate rates at q: q' = N w for velocities w that keep the
// constraints' velocity level (every w in the Euler form; G w = 0 in the
// Lagrange form, where N = I), as columns.
Eigen::MatrixXd admissible_rates(const DaeSystem& dae, int chart, const Eigen::VectorXd& y, StandardTerms& t) {
  const UnknownLayout& lay = dae.layout();
  const Representation& rep = dae.representation(chart);
  const VecQ q = y.segment(lay.q_offset(), lay.nq);
  Eigen::MatrixXd W = Eigen::MatrixXd::Identity(lay.nv, lay.nv);
  rep.evaluate(0.0, q, y.segment(lay.v_offset(), lay.nv), t);
  if (rep.constraint_kind() == ConstraintKind::Force) {
    const Eigen::MatrixXd G = t.G;
    W -= G.transpose() * (G * G.transpose()).ldlt().solve(G);  // projector onto G w = 0
  }
  Eigen::MatrixXd rates(lay.nq, lay.nv);
  for (int j = 0; j < lay.nv; ++j) {
    StandardTerms tj;
    rep.evaluate(0.0, q, W.col(j), tj);
    rates.col(j) = tj.qdot;
  }
  return rates;
}

}  // namespace

TEST_CASE("multipliers act as the kind of their constraint block says, in every scheme") {
  int kinematic_blocks = 0, force_blocks = 0;
  for (const Combination& k : all_combinations())
    for (const std::string& scheme : scheme_names()) {
      CAPTURE(k.name());
      CAPTURE(scheme);
      const Scene s = test::asymmetric_top_scene(k.coordinates, k.equations, scheme);
      const std::unique_ptr<DaeSystem> dae = assemble_dae(s);
      const UnknownLayout& lay = dae->layout();
      const int chart = dae->start_chart();
      Eigen::VectorXd y, yp;
      dae->consistent_state(chart, 0.0, s.R0_WB, s.omega0_B, y, yp);
      StandardTerms t;
      const Eigen::MatrixXd rates = admissible_rates(*dae, chart, y, t);
      const ConstraintKind kind = dae->representation().constraint_kind();
      if (kind == ConstraintKind::Kinematic) {
        ++kinematic_blocks;
        CHECK(lay.n_lambda == 0);  // no scheme holds a kinematically kept constraint by forces
      }
      if (kind == ConstraintKind::Force) ++force_blocks;

      for (int i = 0; i < lay.n_mu; ++i) {
        const Eigen::VectorXd d = column(*dae, chart, y, yp, lay.mu_offset() + i);
        const Eigen::VectorXd dq = d.segment(lay.q_offset(), lay.nq);
        CHECK(d.segment(lay.v_offset(), lay.nv).cwiseAbs().maxCoeff() == 0.0);  // dynamics free of mu
        CHECK(dq.norm() > 0.1);                                                  // mu does act on q'
        CHECK((rates.transpose() * dq).cwiseAbs().maxCoeff() < 1e-12 * dq.norm() * (1.0 + rates.norm()));
      }
      for (int i = 0; i < lay.n_lambda; ++i) {
        const Eigen::VectorXd d = column(*dae, chart, y, yp, lay.lambda_offset() + i);
        const Eigen::VectorXd dv = d.segment(lay.v_offset(), lay.nv);
        CHECK(d.segment(lay.q_offset(), lay.nq).cwiseAbs().maxCoeff() == 0.0);  // lambda leaves q' alone
        CHECK(dv.norm() > 0.1);                                                  // and acts on the dynamics
        // Lagrange form: v = q', so admissible velocities are the admissible rates; no work on them.
        CHECK((rates.transpose() * dv).cwiseAbs().maxCoeff() < 1e-12 * dv.norm() * (1.0 + rates.norm()));
      }
    }
  // Both kinds were met (quaternion and linear coordinates, each form).
  CHECK(kinematic_blocks > 0);
  CHECK(force_blocks > 0);
}

TEST_SUITE_END();
