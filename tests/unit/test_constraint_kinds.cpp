// Constraint blocks by kind, checked on the residual by differences: what a
// multiplier does depends on how its block's constraints are held.
//   Kept by the kinematics (Euler form): q' = N v - Phi_q^T mu, M v' = f.
//     The dynamics carry no multiplier at all, and mu moves q' only off the
//     manifold (Phi_q N = 0: no component along an admissible q' = N w).
//   Held by forces (Lagrange form): M v' = f - G^T lambda.
//     lambda enters the dynamics only, and its force does no work on a
//     velocity the constraints allow (G w = 0); GGL's mu again moves q' only
//     off the manifold.
// Every scheme states its rows per kind; this holds for each of them, on the
// scene as every scene runs (a system of one pivoted body).
#include <doctest/doctest.h>

#include <Eigen/Dense>
#include <string>

#include "rigidae/app/compare.hpp"
#include "rigidae/app/solve.hpp"
#include "rigidae/model/one_body_system.hpp"
#include "rigidae/multibody/multibody_problem.hpp"
#include "rigidae/schemes/scheme.hpp"
#include "test_scenes.hpp"

TEST_SUITE_BEGIN("unit");

using namespace rigidae;
using multibody::MultibodyProblem;

namespace {

// dF/d(y_k) by a difference; F is linear in the multipliers, so h = 1 is exact up to round-off.
Eigen::VectorXd column(MultibodyProblem& p, const Eigen::VectorXd& y, const Eigen::VectorXd& yp, int k) {
  Eigen::VectorXd F0(p.size()), F1(p.size()), y1 = y;
  y1[k] += 1.0;
  REQUIRE(p.residual(0.0, y.data(), yp.data(), F0.data()));
  REQUIRE(p.residual(0.0, y1.data(), yp.data(), F1.data()));
  return F1 - F0;
}

// Admissible coordinate rates at q: q' = N w for velocities w that keep the
// constraints' velocity level (every w in the Euler form; G w = 0 in the
// Lagrange form, where N = I), as columns.
Eigen::MatrixXd admissible_rates(const Representation& rep, const VecQ& q, const VecV& v) {
  StandardTerms t;
  Eigen::MatrixXd W = Eigen::MatrixXd::Identity(rep.nv(), rep.nv());
  rep.evaluate(0.0, q, v, t);
  if (rep.constraint_kind() == ConstraintKind::Force) {
    const Eigen::MatrixXd G = t.G;
    W -= G.transpose() * (G * G.transpose()).ldlt().solve(G);  // projector onto G w = 0
  }
  Eigen::MatrixXd rates(rep.nq(), rep.nv());
  for (int j = 0; j < rep.nv(); ++j) {
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
      // The scene as every scene runs: one pivoted body; its rows follow its
      // unknowns' groups (q: kinematics, v: dynamics).
      MultibodyProblem p(one_body_system(s));
      Eigen::VectorXd y, yp;
      p.initial_state(0.0, y, yp);
      const multibody::BodyModel& b = p.bodies()[0];
      const multibody::UnknownGroup &qg = p.groups()[b.q_group], &vg = p.groups()[b.v_group];
      const Representation& rep = *b.rep;
      const Eigen::MatrixXd rates = admissible_rates(rep, y.segment(qg.offset, qg.size), y.segment(vg.offset, vg.size));
      int n_lambda = 0, n_mu = 0, lambda_offset = -1, mu_offset = -1;
      for (const multibody::ConstraintBlock& blk : p.blocks()) {
        if (blk.lambda_group >= 0) {
          n_lambda = p.groups()[blk.lambda_group].size;
          lambda_offset = p.groups()[blk.lambda_group].offset;
        }
        if (blk.mu_group >= 0) {
          n_mu = p.groups()[blk.mu_group].size;
          mu_offset = p.groups()[blk.mu_group].offset;
        }
      }
      REQUIRE(p.size() == qg.size + vg.size + n_lambda + n_mu);
      const ConstraintKind kind = rep.constraint_kind();
      if (rep.nc() > 0 && kind == ConstraintKind::Kinematic) {
        ++kinematic_blocks;
        CHECK(n_lambda == 0);  // no scheme holds a kinematically kept constraint by forces
      }
      if (rep.nc() > 0 && kind == ConstraintKind::Force) ++force_blocks;

      for (int i = 0; i < n_mu; ++i) {
        const Eigen::VectorXd d = column(p, y, yp, mu_offset + i);
        const Eigen::VectorXd dq = d.segment(qg.offset, qg.size);
        CHECK(d.segment(vg.offset, vg.size).cwiseAbs().maxCoeff() == 0.0);  // dynamics free of mu
        CHECK(dq.norm() > 0.1);                                              // mu does act on q'
        CHECK((rates.transpose() * dq).cwiseAbs().maxCoeff() < 1e-12 * dq.norm() * (1.0 + rates.norm()));
      }
      for (int i = 0; i < n_lambda; ++i) {
        const Eigen::VectorXd d = column(p, y, yp, lambda_offset + i);
        const Eigen::VectorXd dv = d.segment(vg.offset, vg.size);
        CHECK(d.segment(qg.offset, qg.size).cwiseAbs().maxCoeff() == 0.0);  // lambda leaves q' alone
        CHECK(dv.norm() > 0.1);                                              // and acts on the dynamics
        // Lagrange form: v = q', so admissible velocities are the admissible rates; no work on them.
        CHECK((rates.transpose() * dv).cwiseAbs().maxCoeff() < 1e-12 * dv.norm() * (1.0 + rates.norm()));
      }
    }
  // Both kinds were met (quaternion and linear coordinates, each form).
  CHECK(kinematic_blocks > 0);
  CHECK(force_blocks > 0);
}

TEST_SUITE_END();
