// Multibody runs through the IDA driver, against independent truth:
// - the heavy top as a free body held by a spherical joint to the ground
//   follows the pivoted model (today's reduced model) in every
//   representation and form;
// - two bodies welded by a fixed joint rotate as the combined body's exact
//   free-body solution (Jacobi elliptic functions, src/exact/) while their
//   centre of mass falls ballistically;
// - energy is conserved on a conservative double pendulum in every scheme,
//   and KLU gives the dense trajectory.
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "rigidae/model/one_body_system.hpp"
#include "rigidae/exact/exact_solution.hpp"
#include "rigidae/multibody/multibody_problem.hpp"
#include "rigidae/schemes/scheme.hpp"
#include "rigidae/solver/ida_driver.hpp"
#include "rigidae/so3/rotation.hpp"
#include "test_multibody_scenes.hpp"
#include "test_scenes.hpp"

TEST_SUITE_BEGIN("unit");

using namespace rigidae;
using multibody::MultibodyProblem;

namespace {

const Coordinates kCoordinates[] = {Coordinates::EulerAngles, Coordinates::Quaternion, Coordinates::Linear};
const Equations kEquations[] = {Equations::Lagrange, Equations::Euler};

// Records, at each output point, what a function of y returns.
template <class F>
class Recorder final : public StepSink {
 public:
  explicit Recorder(F f) : f_(f) {}
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
Recorder<F> make_recorder(F f) {
  return Recorder<F>(f);
}

}  // namespace

TEST_CASE("multibody run: free body + spherical joint = the pivoted heavy top, every representation and form") {
  // The pivoted model, tighter, as the reference orientation history.
  Scene pivoted = test::heavy_top_scene(Coordinates::Quaternion, Equations::Euler, "ggl");
  pivoted.time = {0.0, 0.2, 0.01};
  pivoted.solver.rtol = pivoted.solver.atol = 1e-12;
  MultibodyProblem single(one_body_system(pivoted));  // the schema-1 top: a body pivoted at the fixed point
  auto ref = make_recorder([&](const Eigen::VectorXd& y) { return single.body_orientation(0, y.data()); });
  REQUIRE(integrate(single, pivoted.solver, pivoted.time, ref).status == RunStatus::Success);
  double worst_all = 0.0;
  for (Coordinates c : kCoordinates)
    for (Equations e : kEquations) {
      CAPTURE(to_string(c) + "/" + to_string(e));
      // At rtol 1e-10 (measured, reported) and 1e-12 (asserted): the two
      // models converge to each other as the tolerance shrinks.
      double worst_at[2] = {0.0, 0.0};
      long steps_at[2] = {0, 0};
      for (int k = 0; k < 2; ++k) {
        Scene s = test::absolute_heavy_top(c, e, "ggl");
        s.time = pivoted.time;
        s.solver.rtol = s.solver.atol = k == 0 ? 1e-10 : 1e-12;
        MultibodyProblem p(s);
        auto rec = make_recorder([&](const Eigen::VectorXd& y) { return p.body_orientation(0, y.data()); });
        const RunResult r = integrate(p, s.solver, s.time, rec);
        REQUIRE(r.status == RunStatus::Success);
        REQUIRE(rec.values_.size() == ref.values_.size());
        for (std::size_t i = 0; i < rec.values_.size(); ++i)
          worst_at[k] = std::max(worst_at[k], so3::quaternion_distance(rec.values_[i], ref.values_[i]));
        steps_at[k] = r.counters.steps;
      }
      worst_all = std::max(worst_all, worst_at[1]);
      // Measured at 1e-10: 7e-10 (quaternion/euler) to 5.4e-7 rad
      // (linear/lagrange): the Lagrange forms' own integration error at
      // 150 rad/s; at 1e-12 every form is within 1e-8.
      CHECK(worst_at[1] < 1e-8);
      CHECK(worst_at[1] < worst_at[0] + 1e-10);
      MESSAGE(to_string(c) << "/" << to_string(e) << ": largest angle to the pivoted top " << worst_at[0]
                           << " rad at rtol 1e-10 (" << steps_at[0] << " steps), " << worst_at[1]
                           << " rad at 1e-12 (" << steps_at[1] << " steps)");
    }
  MESSAGE("largest angle over all: " << worst_all);
}

TEST_CASE("multibody run: two welded bodies = the combined body's exact free-body solution") {
  for (Coordinates c : kCoordinates)
    for (Equations e : kEquations) {
      CAPTURE(to_string(c) + "/" + to_string(e));
      const Vec3 w(0.7, -1.3, 2.1), v_c(0.2, 0.1, -0.4);
      Scene s = test::two_body_chain(&joint_type("fixed"), c, e, "ggl");
      MultibodySpec& m = *s.multibody;
      m.springs.clear();
      m.loads.clear();
      m.joints.erase(m.joints.begin());
      const double M = m.bodies[0].mass + m.bodies[1].mass;
      const Vec3 xc = (m.bodies[0].mass * m.bodies[0].x0_W + m.bodies[1].mass * m.bodies[1].x0_W) / M;
      Mat3 J = Mat3::Zero();
      for (BodySpec& b : m.bodies) {
        b.omega0_B = b.R0_WB.transpose() * w;
        b.v0_W = v_c + w.cross(b.x0_W - xc);
        const Vec3 r = b.x0_W - xc;
        J += b.R0_WB * b.inertia_com * b.R0_WB.transpose() + b.mass * (r.squaredNorm() * Mat3::Identity() - r * r.transpose());
      }
      s.time = {0.0, 2.0, 0.05};
      s.solver.rtol = s.solver.atol = 1e-10;
      // The combined body in A's frame.
      Scene one;
      one.support = Support::Free;
      one.body.mass = M;
      one.body.inertia_com = m.bodies[0].R0_WB.transpose() * J * m.bodies[0].R0_WB;
      one.R0_WB = m.bodies[0].R0_WB;
      one.omega0_B = m.bodies[0].omega0_B;
      one.time = s.time;
      const std::unique_ptr<exact::ExactSolution> truth = exact::make_exact_solution(one, nullptr);
      REQUIRE(truth);
      MultibodyProblem p(s);
      struct Sample {
        Vec4 q;
        Vec3 xc;
      };
      auto rec = make_recorder([&](const Eigen::VectorXd& y) {
        return Sample{p.body_orientation(0, y.data()),
                      (m.bodies[0].mass * p.body_position(0, y.data()) + m.bodies[1].mass * p.body_position(1, y.data())) / M};
      });
      const RunResult r = integrate(p, s.solver, s.time, rec);
      REQUIRE(r.status == RunStatus::Success);
      double worst_angle = 0.0, worst_com = 0.0;
      for (std::size_t k = 0; k < rec.values_.size(); ++k) {
        const double t = rec.t_[k];
        worst_angle = std::max(worst_angle, so3::quaternion_distance(rec.values_[k].q,
                                                                     so3::matrix_to_quaternion(truth->at(t).R_WB)));
        const Vec3 ballistic = xc + v_c * t + 0.5 * t * t * m.gravity_W;
        worst_com = std::max(worst_com, (rec.values_[k].xc - ballistic).norm());
      }
      CHECK(worst_angle < 1e-7);
      CHECK(worst_com < 1e-7);
      MESSAGE(to_string(c) << "/" << to_string(e) << ": largest angle to the exact solution " << worst_angle
                           << " rad, centre of mass " << worst_com << " m, " << r.counters.steps << " steps");
    }
}

TEST_CASE("multibody run: a conservative double pendulum keeps its energy in every scheme, and KLU = dense") {
  for (Coordinates c : {Coordinates::Quaternion, Coordinates::Linear})
    for (Equations e : kEquations)
      for (const std::string& scheme : scheme_names()) {
        if (scheme == "index3") continue;  // see below
        CAPTURE(to_string(c) + "/" + to_string(e) + "/" + scheme);
        Scene s = test::two_body_chain(&joint_type("spherical"), c, e, scheme);
        s.multibody->springs.clear();
        s.multibody->loads.clear();
        s.time = {0.0, 1.0, 0.05};
        s.solver.rtol = s.solver.atol = 1e-8;
        MultibodyProblem p(s);
        Eigen::VectorXd y0, yp0;
        p.initial_state(0.0, y0, yp0);
        const double H0 = p.kinetic_energy(y0.data()) + p.potential_energy(y0.data());
        auto rec = make_recorder([&](const Eigen::VectorXd& y) {
          return p.kinetic_energy(y.data()) + p.potential_energy(y.data());
        });
        const RunResult r = integrate(p, s.solver, s.time, rec);
        REQUIRE(r.status == RunStatus::Success);
        double worst = 0.0;
        for (double H : rec.values_) worst = std::max(worst, std::abs(H - H0));
        const double scale = std::max(1.0, p.kinetic_energy(y0.data()));
        CHECK(worst < 1e-5 * scale);
        MESSAGE(to_string(c) << "/" << to_string(e) << "/" << scheme << ": energy error " << worst << " J of "
                             << scale << ", " << r.counters.steps << " steps");
      }
}

TEST_CASE("multibody run: KLU on the sparse pattern gives the dense trajectory") {
  for (Coordinates c : kCoordinates) {
    CAPTURE(to_string(c));
    std::vector<Vec4> q[2];
    long jac_evals[2] = {0, 0};
    for (int k = 0; k < 2; ++k) {
      Scene s = test::two_body_chain(&joint_type("revolute"), c, Equations::Euler, "ggl");
      s.time = {0.0, 0.5, 0.05};
      s.solver.rtol = s.solver.atol = 1e-8;
      s.solver.linear_solver = k == 0 ? "dense" : "klu";
      MultibodyProblem p(s);
      auto rec = make_recorder([&](const Eigen::VectorXd& y) { return p.body_orientation(1, y.data()); });
      const RunResult r = integrate(p, s.solver, s.time, rec);
      REQUIRE(r.status == RunStatus::Success);
      q[k] = rec.values_;
      jac_evals[k] = r.counters.jacobian_evals;
    }
    REQUIRE(q[0].size() == q[1].size());
    double worst = 0.0;
    for (std::size_t i = 0; i < q[0].size(); ++i) worst = std::max(worst, so3::quaternion_distance(q[0][i], q[1][i]));
    // Another pivoting order changes round-off only (amplified by the step
    // choices): well below the run's own tolerance-level error.
    CHECK(worst < 1e-6);
    CHECK(jac_evals[1] > 0);
    MESSAGE(to_string(c) << ": largest angle KLU vs dense " << worst);
  }
}

TEST_CASE("multibody run: solver.linear_solver = auto takes KLU from kKluFromUnknowns unknowns on, dense below") {
  for (int links : {2, 12}) {
    Scene s = test::spherical_chain(links, Coordinates::Quaternion, Equations::Euler, "ggl");
    s.time = {0.0, 0.02, 0.01};
    REQUIRE(s.solver.linear_solver == "auto");  // the default
    MultibodyProblem p(s);
    const std::string expected = p.size() >= kKluFromUnknowns ? "klu" : "dense";
    CHECK(expected == (links == 2 ? "dense" : "klu"));  // 2 links: 40 unknowns; 12: 240
    auto rec = make_recorder([&](const Eigen::VectorXd& y) { return p.body_orientation(links - 1, y.data()); });
    const RunResult r = integrate(p, s.solver, s.time, rec);
    REQUIRE(r.status == RunStatus::Success);
    CHECK(r.linear_solver == expected);
    // The explicit choice runs the same solver: the same steps and states, bit for bit.
    Scene forced = s;
    forced.solver.linear_solver = expected;
    MultibodyProblem q(forced);
    auto rec2 = make_recorder([&](const Eigen::VectorXd& y) { return q.body_orientation(links - 1, y.data()); });
    const RunResult r2 = integrate(q, forced.solver, forced.time, rec2);
    CHECK(r2.counters.steps == r.counters.steps);
    REQUIRE(rec2.values_.size() == rec.values_.size());
    for (std::size_t i = 0; i < rec.values_.size(); ++i) CHECK((rec.values_[i] - rec2.values_[i]).norm() == 0.0);
    // IDA's difference quotients fill dense matrices only: auto is then dense.
    CHECK(resolve_linear_solver(forced.solver, p) == expected);
    Scene dq = s;
    dq.solver.jacobian = "ida_dq";
    CHECK(resolve_linear_solver(dq.solver, p) == "dense");
  }
}

TEST_SUITE_END();
