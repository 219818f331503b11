// Pivoted bodies in the multibody model (src/multibody/pivot.cpp): a body
// held at a fixed point has its rotation coordinates and velocities as its
// only unknowns, and it must behave as the same body free and held by a
// spherical joint to the ground, and as the one-body model of a top.
// - the exact iteration matrix equals central differences (every
//   representation x form x scheme, and every joint type to a second body);
// - the pivoted heavy top written as a mechanism equals
//   problems/heavy_top.toml as a one-body system (one_body_system) within
//   the integration error;
// - it equals the free body + spherical joint (heavy_top_absolute.toml) to
//   the integration error, and its support force equals that joint's
//   reaction (and the closed form m (a_c - g) at the start);
// - with joints, springs and loads on the pivoted body, the support force at
//   the start equals the spherical joint's reaction of the free-body model.
#include <doctest/doctest.h>

#include <algorithm>
#include <random>
#include <string>
#include <vector>

#include "multibody_differences.hpp"
#include "rigidae/model/one_body_system.hpp"
#include "rigidae/multibody/multibody_problem.hpp"
#include "rigidae/schemes/scheme.hpp"
#include "rigidae/so3/rotation.hpp"
#include "rigidae/solver/ida_driver.hpp"
#include "test_multibody_scenes.hpp"
#include "test_scenes.hpp"

TEST_SUITE_BEGIN("unit");

using namespace rigidae;
using multibody::MultibodyProblem;
using test::richardson_matrix;
using test::row_relative_difference;

namespace {

const Coordinates kCoordinates[] = {Coordinates::EulerAngles, Coordinates::Quaternion, Coordinates::Linear};
const Equations kEquations[] = {Equations::Lagrange, Equations::Euler};

// The heavy top held at its pivot (the origin): one body, no joint.
Scene pivoted_heavy_top(Coordinates c, Equations e, const std::string& scheme) {
  Scene s = test::absolute_heavy_top(c, e, scheme);
  s.name = "heavy_top_pivoted";
  s.multibody->joints.clear();
  s.multibody->bodies[0].pivot_W = Vec3::Zero();
  return s;
}

// two_body_chain with its first body A held at the pivot P (where the
// chain's first joint was) instead of joined to the ground; `free_body`:
// A free, held by a spherical joint at P (the same mechanics).
Scene pivoted_chain(const JointType* type, Coordinates c, Equations e, const std::string& scheme, bool free_body) {
  Scene s = test::two_body_chain(type, c, e, scheme);
  MultibodySpec& m = *s.multibody;
  const Vec3 P(0.1, 0.0, 0.0);
  m.joints.erase(m.joints.begin());
  BodySpec& a = m.bodies[0];
  a.v0_W = (a.R0_WB * a.omega0_B).cross(a.x0_W - P);
  if (free_body)
    m.joints.insert(m.joints.begin(), test::joint_at(m, &joint_type("spherical"), kGround, 0, P, Vec3::UnitZ(),
                                                     Vec3::UnitX(), "pivot"));
  else
    a.pivot_W = P;
  return s;
}

// The exact matrix against differences at the start and at a perturbed
// state; returns the largest row-relative difference.
double matrix_difference(MultibodyProblem& p, std::mt19937& rng) {
  const int n = p.size();
  Eigen::VectorXd y, yp;
  p.initial_state(0.0, y, yp);
  Eigen::VectorXd F(n);
  REQUIRE(p.residual(0.0, y.data(), yp.data(), F.data()));
  const double scale = std::max({1.0, y.cwiseAbs().maxCoeff(), yp.cwiseAbs().maxCoeff()});
  CHECK(F.cwiseAbs().maxCoeff() < 1e-10 * scale);  // a consistent start
  double worst = 0.0;
  for (int k = 0; k < 2; ++k) {
    Eigen::VectorXd yk = y, ypk = yp;
    if (k == 1) test::perturb_state(rng, yk, ypk);
    const double cj = k == 0 ? 3.7 : 250.0;
    Eigen::MatrixXd dense(n, n);
    p.iteration_matrix_dense(0.2, cj, yk.data(), ypk.data(), dense.data());
    Eigen::VectorXd values(p.sparsity().nnz());
    p.iteration_matrix_sparse(0.2, cj, yk.data(), ypk.data(), values.data());
    Eigen::MatrixXd sparse = Eigen::MatrixXd::Zero(n, n);
    for (int c = 0; c < n; ++c)
      for (std::int64_t q = p.sparsity().col_start[c]; q < p.sparsity().col_start[c + 1]; ++q)
        sparse(p.sparsity().rows[q], c) = values(q);
    const double d = row_relative_difference(dense, richardson_matrix(p, 0.2, cj, yk, ypk));
    CAPTURE(k);
    CHECK(d < 1e-8);
    CHECK((sparse - dense).cwiseAbs().maxCoeff() == 0.0);
    worst = std::max(worst, d);
  }
  return worst;
}

// Final value of f(y) of a run.
template <class F>
class FinalValue final : public StepSink {
 public:
  explicit FinalValue(F f) : f_(f) {}
  void on_step(double, double, int, const Eigen::VectorXd&) override {}
  void on_output(double t, const Eigen::VectorXd& y) override {
    t_.push_back(t);
    values_.push_back(f_(y));
  }
  std::vector<double> t_;
  std::vector<decltype(std::declval<F>()(Eigen::VectorXd()))> values_;

 private:
  F f_;
};
template <class F>
FinalValue<F> record(F f) {
  return FinalValue<F>(f);
}

}  // namespace

TEST_CASE("pivot: a pivoted body's unknowns are its rotation coordinates and velocities only") {
  for (Coordinates c : kCoordinates)
    for (Equations e : kEquations) {
      CAPTURE(to_string(c) + "/" + to_string(e));
      const Scene s = pivoted_heavy_top(c, e, "ggl");
      const MultibodyProblem p(s);
      const multibody::BodyModel& b = p.bodies()[0];
      CHECK(b.pivoted());
      // Rotation coordinates and velocities (no translation), then the
      // representation's own multipliers (GGL: at most two per constraint).
      CHECK(p.groups()[b.q_group].size == b.nqr);
      CHECK(b.nqr == b.rep->nq());
      CHECK(p.groups()[b.v_group].size == b.rep->nv());
      CHECK(p.size() - b.rep->nq() - b.rep->nv() <= 2 * b.rep->nc());
      CHECK((b.rep->nc() == 0) == (p.size() == b.rep->nq() + b.rep->nv()));
      // The same size as the schema-1 heavy top's (one_body_system).
      const Scene one = test::heavy_top_scene(c, e, "ggl");
      CHECK(p.size() == MultibodyProblem(one_body_system(one)).size());
    }
}

TEST_CASE("pivot: exact iteration matrix = differences, every representation x form x scheme") {
  std::mt19937 rng(777);
  double worst = 0.0;
  for (Coordinates c : kCoordinates)
    for (Equations e : kEquations)
      for (const std::string& scheme : scheme_names()) {
        CAPTURE(to_string(c) + "/" + to_string(e) + "/" + scheme);
        MultibodyProblem top(pivoted_heavy_top(c, e, scheme));
        worst = std::max(worst, matrix_difference(top, rng));
        // A pivoted body joined to a second one, springs and loads of every kind on both.
        MultibodyProblem chain(pivoted_chain(&joint_type("revolute"), c, e, scheme, false));
        worst = std::max(worst, matrix_difference(chain, rng));
      }
  MESSAGE("largest row-relative difference: " << worst);
}

TEST_CASE("pivot: exact iteration matrix = differences, every joint type to a pivoted body") {
  std::mt19937 rng(778);
  for (const JointType* jt : joint_types())
    for (Equations e : kEquations) {
      CAPTURE(jt->name);
      CAPTURE(to_string(e));
      MultibodyProblem p(pivoted_chain(jt, Coordinates::Quaternion, e, "ggl", false));
      matrix_difference(p, rng);
    }
}

TEST_CASE("pivot: the pivoted heavy top written as a mechanism = problems/heavy_top.toml as a one-body system") {
  // Same representation, scheme and tolerances as the file; the hand-built
  // pivoted spec (its centre of mass and inertia about it) and the schema-1
  // scene's conversion (one_body_system: inertia and lever about the fixed
  // point) hold the same equations, so they may differ only by round-off
  // grown along the run, below the run's own error against a tight run.
  for (Coordinates c : {Coordinates::Quaternion, Coordinates::EulerAngles})
    for (Equations e : kEquations) {
      CAPTURE(to_string(c) + "/" + to_string(e));
      Scene one = test::heavy_top_scene(c, e, "ggl");
      one.time = {0.0, 0.5, 0.05};
      one.solver.rtol = one.solver.atol = 1e-8;
      MultibodyProblem single(one_body_system(one));
      auto ref = record([&](const Eigen::VectorXd& y) { return single.body_orientation(0, y.data()); });
      const RunResult rs = integrate(single, one.solver, one.time, ref);
      REQUIRE(rs.status == RunStatus::Success);

      Scene s = pivoted_heavy_top(c, e, "ggl");
      s.time = one.time;
      s.solver.rtol = s.solver.atol = 1e-8;
      MultibodyProblem p(s);
      auto got = record([&](const Eigen::VectorXd& y) { return p.body_orientation(0, y.data()); });
      const RunResult rm = integrate(p, s.solver, s.time, got);
      REQUIRE(rm.status == RunStatus::Success);

      // The integration error of the single-body run: against itself at 1e-12.
      Scene tight = one;
      tight.solver.rtol = tight.solver.atol = 1e-12;
      MultibodyProblem single_t(one_body_system(tight));
      auto truth = record([&](const Eigen::VectorXd& y) { return single_t.body_orientation(0, y.data()); });
      REQUIRE(integrate(single_t, tight.solver, tight.time, truth).status == RunStatus::Success);

      const double between = so3::quaternion_distance(got.values_.back(), ref.values_.back());
      const double error = so3::quaternion_distance(ref.values_.back(), truth.values_.back());
      MESSAGE(to_string(c) << "/" << to_string(e) << ": one-body system " << rs.counters.steps << " steps, "
                           << rs.counters.residual_evals << " residuals; pivoted multibody "
                           << rm.counters.steps << " steps, " << rm.counters.residual_evals
                           << " residuals; final angle between them " << between << " rad, one-body error "
                           << error << " rad");
      // Measured: the same run bit for bit (the two constructions give the
      // same numbers: lever, inertia about the pivot, start). Asserted so,
      // and in any case below the run's own error.
      CHECK(error > 0.0);
      CHECK(between < error);
      CHECK(rm.counters.steps == rs.counters.steps);
      CHECK(rm.counters.residual_evals == rs.counters.residual_evals);
      CHECK(between == 0.0);
    }
}

TEST_CASE("pivot: the pivoted heavy top = free body + spherical joint, support force = the joint's reaction") {
  Scene s = pivoted_heavy_top(Coordinates::Quaternion, Equations::Euler, "ggl");
  s.time = {0.0, 0.3, 0.05};
  s.solver.rtol = s.solver.atol = 1e-11;
  Scene a = test::absolute_heavy_top(Coordinates::Quaternion, Equations::Euler, "ggl");
  a.time = s.time;
  a.solver = s.solver;
  MultibodyProblem p(s), q(a);
  // At the start, the closed form m (a_c - g) of heavy_top_absolute.toml's header.
  {
    Eigen::VectorXd y, yp;
    p.initial_state(0.0, y, yp);
    const Vec3 F = p.support_force(0, y.data());
    CHECK(std::abs(F(0)) < 1e-6);
    CHECK(F(1) == doctest::Approx(-319.526).epsilon(1e-5));
    CHECK(F(2) == doctest::Approx(-317.262).epsilon(1e-5));
  }
  struct Sample {
    Vec4 q;
    Vec3 force;
  };
  auto got = record([&](const Eigen::VectorXd& y) { return Sample{p.body_orientation(0, y.data()), p.support_force(0, y.data())}; });
  auto ref = record([&](const Eigen::VectorXd& y) {
    return Sample{q.body_orientation(0, y.data()), q.joint_reaction(0, y.data()).force};
  });
  REQUIRE(integrate(p, s.solver, s.time, got).status == RunStatus::Success);
  REQUIRE(integrate(q, a.solver, a.time, ref).status == RunStatus::Success);
  REQUIRE(got.values_.size() == ref.values_.size());
  double angle = 0.0, force = 0.0;
  for (std::size_t i = 0; i < got.values_.size(); ++i) {
    angle = std::max(angle, so3::quaternion_distance(got.values_[i].q, ref.values_[i].q));
    force = std::max(force, (got.values_[i].force - ref.values_[i].force).norm() / ref.values_[i].force.norm());
  }
  MESSAGE("pivoted vs free + spherical joint at rtol 1e-11 over 0.3 s: angle " << angle << " rad, support force "
                                                                              << force << " relative");
  // Measured by test_multibody_runs.cpp for the free body against the
  // single-body model: within 1e-8 rad at rtol 1e-12.
  CHECK(angle < 1e-7);
  CHECK(force < 1e-5);
}

TEST_CASE("pivot: support force = a spherical joint's reaction, with joints, springs and loads on the body") {
  for (const JointType* jt : {&joint_type("revolute"), &joint_type("spherical"), &joint_type("prismatic")})
    for (Coordinates c : kCoordinates)
      for (Equations e : kEquations) {
        CAPTURE(jt->name);
        CAPTURE(to_string(c) + "/" + to_string(e));
        MultibodyProblem p(pivoted_chain(jt, c, e, "index1", false));
        MultibodyProblem q(pivoted_chain(jt, c, e, "index1", true));
        Eigen::VectorXd y, yp, yq, ypq;
        p.initial_state(0.0, y, yp);
        q.initial_state(0.0, yq, ypq);
        // The same motion: the second body's velocity, projected onto its joint in either model.
        CHECK((p.body_velocity(1, y.data()) - q.body_velocity(1, yq.data())).norm() < 1e-9);
        CHECK((p.body_velocity(0, y.data()) - q.body_velocity(0, yq.data())).norm() < 1e-9);
        const Vec3 F = p.support_force(0, y.data());
        const Vec3 R = q.joint_reaction(0, yq.data()).force;
        CAPTURE(F.transpose());
        CAPTURE(R.transpose());
        CHECK((F - R).norm() < 1e-8 * std::max(1.0, R.norm()));
        // The joint between the bodies carries the same reaction in both.
        const Vec3 J1 = p.joint_reaction(0, y.data()).force, J2 = q.joint_reaction(1, yq.data()).force;
        CHECK((J1 - J2).norm() < 1e-8 * std::max(1.0, J2.norm()));
      }
}

TEST_SUITE_END();
