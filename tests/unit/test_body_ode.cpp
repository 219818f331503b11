// The multibody ODE form of decoupled bodies (MultibodyOde's per-body path,
// schemes/body_ode.hpp) against the one-body ODE form (SingleBodyOde) and
// against its own KKT path:
// - a one-body scene as one_body_system(scene) integrated by cvode-bdf,
//   cvode-adams and arkode-erk takes the same steps and ends in the same
//   state, bit for bit, for every coordinates x equations x {index1,
//   projection} on the heavy top and the free asymmetric body (and a start
//   in the wrong Euler chart: sleeping_top; a lamina, whose mass matrix is
//   singular in linear coordinates' Lagrange form), with the same chart
//   switches;
// - at random states off the manifold the right-hand side, drift,
//   projection, its linearisation and the observed multipliers are
//   SingleBodyOde's bit for bit, and the KKT path's rhs to round-off (an LU
//   of the saddle-point matrix against the Schur complement of M);
// - two decoupled bodies (in different coordinates) take each its own
//   one-body system's rate, drift, multipliers and projection;
// - the right-hand side allocates nothing; a system with a joint keeps the
//   KKT path.
#include <doctest/doctest.h>

#include <random>
#include <string>
#include <vector>

#include "alloc_counter.hpp"
#include "multibody_differences.hpp"
#include "rigidae/dae/dae_system.hpp"
#include "rigidae/dae/single_body_ode.hpp"
#include "rigidae/io/scene_loader.hpp"
#include "rigidae/model/one_body_system.hpp"
#include "rigidae/multibody/multibody_ode.hpp"
#include "rigidae/multibody/multibody_problem.hpp"
#include "rigidae/solver/ode_driver.hpp"

TEST_SUITE_BEGIN("unit");

using namespace rigidae;

namespace {

// The steps' count, every chart switch, the last output state.
class Sink final : public StepSink {
 public:
  long steps = 0;
  std::vector<std::string> switches;  // "t from to"
  Eigen::VectorXd y_last;
  void on_step(double, double, int, const Eigen::VectorXd&) override { ++steps; }
  void on_output(double, const Eigen::VectorXd& y) override { y_last = y; }
  void on_event(const EventNote& e) override {
    if (e.what == "chart_switch") switches.push_back(std::to_string(e.t) + " " + e.from + " " + e.to);
  }
  bool needs_every_output() const override { return false; }
};

Scene scene_for(const std::string& file, const std::string& coords, Equations e, const std::string& scheme,
                double t_end) {
  // "lamina": the free body with moments (1, 2, 3), J3 = J1 + J2: in linear
  // coordinates' Lagrange form its mass matrix is singular (the saddle-point solve).
  const bool lamina = file == "lamina";
  Scene s = io::load_scene(std::string(RIGIDAE_SOURCE_DIR) + "/problems/" + (lamina ? "free_body.toml" : file));
  if (lamina) s.body.inertia_com = Vec3(1.0, 2.0, 3.0).asDiagonal();
  s.formulation.coordinates = Coordinates(coords);
  s.formulation.equations = e;
  s.formulation.scheme = scheme;
  s.solver.rtol = s.solver.atol = 1e-7;
  s.time.end = t_end;
  s.time.output_step = t_end;
  return s;
}

// Entries of a and b that are not the same double.
int differing(const double* a, const double* b, int n) {
  int count = 0;
  for (int i = 0; i < n; ++i) count += a[i] == b[i] ? 0 : 1;
  return count;
}

struct Combination {
  const char* file;
  const char* coords;
  Equations equations;
  const char* scheme;
  double t_end;
};

// Every ODE-capable combination on the heavy top and the free asymmetric
// body; Euler angles (no constraints: index1 and projection are one ODE)
// once per form, plus a start within the z-x-z chart's margin.
std::vector<Combination> combinations() {
  std::vector<Combination> out;
  for (const char* file : {"heavy_top.toml", "free_body.toml"})
    for (const char* coords : {"euler", "quaternion", "linear"})
      for (const Equations e : {Equations::Lagrange, Equations::Euler})
        for (const char* scheme : {"index1", "projection"}) {
          if (std::string(coords) == "euler" && std::string(scheme) == "projection") continue;
          out.push_back({file, coords, e, scheme, std::string(file) == "heavy_top.toml" ? 0.3 : 2.0});
        }
  for (const Equations e : {Equations::Lagrange, Equations::Euler})
    out.push_back({"sleeping_top.toml", "euler", e, "index1", 0.3});
  for (const char* scheme : {"index1", "projection"})
    out.push_back({"lamina", "linear", Equations::Lagrange, scheme, 2.0});
  return out;
}

std::string label(const Combination& c) {
  return std::string(c.file) + " " + c.coords + "/" + (c.equations == Equations::Euler ? "euler" : "lagrange") +
         "/" + c.scheme;
}

}  // namespace

TEST_CASE("body ODE: a one-body scene through MultibodyOde takes SingleBodyOde's steps to its final state, bit for bit") {
  int runs = 0;
  long switches = 0, at_start = 0, projections = 0;
  for (const Combination& c : combinations())
    for (const char* integrator : {"cvode-bdf", "cvode-adams", "arkode-erk"}) {
      const std::string what = label(c) + " " + integrator;
      CAPTURE(what);
      Scene s = scene_for(c.file, c.coords, c.equations, c.scheme, c.t_end);
      // Heavy top in Euler angles: long enough to leave its start chart.
      if (std::string(c.file) == "heavy_top.toml" && std::string(c.coords) == "euler")
        s.time.end = s.time.output_step = 1.0;
      const std::unique_ptr<DaeSystem> dae = assemble_dae(s);
      const ProjectionPolicy p = dae->scheme().projection();
      const OdeMethod method{integrator, "fehlberg78", {p.enabled, p.every_step, p.threshold}};
      SingleBodyOde one(*dae, s);
      Sink one_sink;
      const RunResult a = integrate_ode(one, s.solver, s.time, method, one_sink);

      multibody::MultibodyProblem system(one_body_system(s));
      REQUIRE(system.bodies_decoupled());
      REQUIRE(system.scheme().projection == p.enabled);
      if (p.enabled) REQUIRE(projection_threshold(s) == p.threshold);
      multibody::MultibodyOde ode(system, false, s.source);
      REQUIRE(ode.by_body());
      Sink sys_sink;
      const RunResult b = integrate_ode(ode, s.solver, s.time, method, sys_sink);

      REQUIRE(a.status == RunStatus::Success);
      REQUIRE(b.status == RunStatus::Success);
      CHECK(b.counters.steps == a.counters.steps);
      CHECK(b.counters.residual_evals == a.counters.residual_evals);
      CHECK(b.counters.error_test_fails == a.counters.error_test_fails);
      CHECK(b.counters.projections == a.counters.projections);
      CHECK(b.counters.restarts == a.counters.restarts);
      CHECK(sys_sink.switches == one_sink.switches);
      REQUIRE(sys_sink.y_last.size() == one_sink.y_last.size());
      // The whole observation: q, v and (Lagrange form) the multipliers.
      CHECK(differing(sys_sink.y_last.data(), one_sink.y_last.data(), static_cast<int>(one_sink.y_last.size())) == 0);
      switches += static_cast<long>(one_sink.switches.size());
      for (const std::string& sw : one_sink.switches) at_start += sw.rfind("0.000000 ", 0) == 0 ? 1 : 0;
      projections += a.counters.projections;
      ++runs;
    }
  CHECK(runs == 24 * 3);
  // What is compared is not vacuous: sleeping_top's chart switch at the
  // start (2 forms x 3 integrators), switches during the heavy top's and
  // the free body's Euler-angle runs (measured: 23), projections (measured:
  // 865, most in linear coordinates on cvode-bdf).
  CHECK(at_start == 6);
  CHECK(switches - at_start >= 12);
  CHECK(projections >= 100);
}

TEST_CASE("body ODE: at random states the per-body rhs, drift, projection and multipliers are SingleBodyOde's, "
          "and the KKT path's rhs to round-off") {
  int checked = 0;
  for (const Combination& c : combinations()) {
    CAPTURE(label(c));
    const Scene s = scene_for(c.file, c.coords, c.equations, c.scheme, c.t_end);
    const std::unique_ptr<DaeSystem> dae = assemble_dae(s);
    SingleBodyOde one(*dae, s);
    multibody::MultibodyProblem system(one_body_system(s));
    multibody::MultibodyOde by_body(system, false, s.source);
    multibody::MultibodyOde kkt(system, false, s.source, true, /*by_body=*/false);
    REQUIRE(by_body.by_body());
    REQUIRE_FALSE(kkt.by_body());
    const int n = one.size();
    REQUIRE(by_body.size() == n);
    Eigen::VectorXd x0, x0_sys;
    one.initial_state(0.0, x0);
    by_body.initial_state(0.0, x0_sys);
    CHECK(differing(x0.data(), x0_sys.data(), n) == 0);
    std::mt19937 rng(11);
    for (int trial = 0; trial < 5; ++trial) {
      Eigen::VectorXd x = x0, unused = x0;
      test::perturb_state(rng, x, unused);  // off the start and off the manifold
      const double t = 0.1 * trial;
      Eigen::VectorXd f1(n), f2(n), f3(n);
      REQUIRE(one.rhs(t, x.data(), f1.data()));
      REQUIRE(by_body.rhs(t, x.data(), f2.data()));
      REQUIRE(kkt.rhs(t, x.data(), f3.data()));
      CHECK(differing(f1.data(), f2.data(), n) == 0);
      // The KKT path: another factorisation of the same linear system.
      CHECK((f3 - f2).cwiseAbs().maxCoeff() <= 1e-10 * std::max(1.0, f2.cwiseAbs().maxCoeff()));
      const OdeDrift d1 = one.drift(t, x.data()), d2 = by_body.drift(t, x.data());
      CHECK(d1.position == d2.position);
      CHECK(d1.velocity == d2.velocity);
      Eigen::VectorXd y1, y2, y3;
      one.observe(t, x.data(), y1);
      by_body.observe(t, x.data(), y2);
      kkt.observe(t, x.data(), y3);
      REQUIRE(y1.size() == y2.size());
      CHECK(differing(y1.data(), y2.data(), static_cast<int>(y1.size())) == 0);
      CHECK((y3 - y2).cwiseAbs().maxCoeff() <= 1e-9 * std::max(1.0, y2.cwiseAbs().maxCoeff()));
      if (dae->representation(dae->start_chart()).nc() > 0) {
        Eigen::VectorXd p1 = x, p2 = x;
        one.project(t, p1.data());
        by_body.project(t, p2.data());
        CHECK(differing(p1.data(), p2.data(), n) == 0);
        Eigen::VectorXd e1 = Eigen::VectorXd::Ones(n), e2 = e1;
        one.project_error(t, p1.data(), e1.data());
        by_body.project_error(t, p2.data(), e2.data());
        CHECK(differing(e1.data(), e2.data(), n) == 0);
        CHECK(e2.cwiseAbs().maxCoeff() > 0.0);
      }
      ++checked;
    }
  }
  CHECK(checked == 24 * 5);
}

TEST_CASE("body ODE: two decoupled bodies, each its own one-body system's rate, and the KKT path's to round-off") {
  int checked = 0;
  for (const char* coords : {"quaternion", "linear"})
    for (const Equations e : {Equations::Lagrange, Equations::Euler}) {
      CAPTURE(std::string(coords) + (e == Equations::Euler ? "/euler" : "/lagrange"));
      const Scene s = scene_for("heavy_top.toml", coords, e, "projection", 0.1);
      // The top, and a second top in the other constrained coordinates spinning at half the rate.
      Scene pair = one_body_system(s);
      BodySpec second = pair.multibody->bodies[0];
      second.name = "second";
      second.omega0_B *= 0.5;
      second.coordinates = Coordinates(std::string(coords) == "quaternion" ? "linear" : "quaternion");
      pair.multibody->bodies.push_back(second);
      Scene alone = pair;
      alone.multibody->bodies.erase(alone.multibody->bodies.begin());
      multibody::MultibodyProblem both(pair), first(one_body_system(s)), other(alone);
      REQUIRE(both.bodies_decoupled());
      multibody::MultibodyOde by_body(both, false, s.source), kkt(both, false, s.source, true, false);
      multibody::MultibodyOde ode1(first, false, s.source), ode2(other, false, s.source);
      REQUIRE(by_body.by_body());
      REQUIRE_FALSE(kkt.by_body());
      const int n = by_body.size(), n1 = ode1.size(), n2 = ode2.size();
      REQUIRE(n == n1 + n2);
      Eigen::VectorXd x;
      by_body.initial_state(0.0, x);
      std::mt19937 rng(5);
      for (int trial = 0; trial < 3; ++trial) {
        Eigen::VectorXd xp = x, unused = x;
        test::perturb_state(rng, xp, unused);
        Eigen::VectorXd f(n), g(n), f1(n1), f2(n2);
        REQUIRE(by_body.rhs(0.2, xp.data(), f.data()));
        REQUIRE(kkt.rhs(0.2, xp.data(), g.data()));
        REQUIRE(ode1.rhs(0.2, xp.data(), f1.data()));
        REQUIRE(ode2.rhs(0.2, xp.data() + n1, f2.data()));
        CHECK(differing(f.data(), f1.data(), n1) == 0);
        CHECK(differing(f.data() + n1, f2.data(), n2) == 0);
        CHECK((g - f).cwiseAbs().maxCoeff() <= 1e-10 * std::max(1.0, f.cwiseAbs().maxCoeff()));
        const OdeDrift d = by_body.drift(0.2, xp.data()), d1 = ode1.drift(0.2, xp.data()),
                       d2 = ode2.drift(0.2, xp.data() + n1);
        CHECK(d.position == std::max(d1.position, d2.position));
        CHECK(d.velocity == std::max(d1.velocity, d2.velocity));
        // The observation: each body's multipliers where the layout puts its block's.
        Eigen::VectorXd y, y1, y2, yk;
        by_body.observe(0.2, xp.data(), y);
        ode1.observe(0.2, xp.data(), y1);
        ode2.observe(0.2, xp.data() + n1, y2);
        kkt.observe(0.2, xp.data(), yk);
        REQUIRE(y.size() == y1.size() + y2.size());
        CHECK(differing(y.data(), y1.data(), n1) == 0);
        CHECK(differing(y.data() + n1, y2.data(), n2) == 0);
        CHECK(differing(y.data() + n, y1.data() + n1, static_cast<int>(y1.size()) - n1) == 0);
        CHECK(differing(y.data() + n + y1.size() - n1, y2.data() + n2, static_cast<int>(y2.size()) - n2) == 0);
        CHECK((yk - y).cwiseAbs().maxCoeff() <= 1e-9 * std::max(1.0, y.cwiseAbs().maxCoeff()));
        Eigen::VectorXd p = xp, p1 = xp.head(n1), p2 = xp.tail(n2);
        by_body.project(0.2, p.data());
        ode1.project(0.2, p1.data());
        ode2.project(0.2, p2.data());
        CHECK(differing(p.data(), p1.data(), n1) == 0);
        CHECK(differing(p.data() + n1, p2.data(), n2) == 0);
        ++checked;
      }
    }
  CHECK(checked == 12);
}

TEST_CASE("body ODE: the per-body rhs allocates nothing, and a system with a joint keeps the KKT path") {
  const Scene s = scene_for("heavy_top.toml", "linear", Equations::Lagrange, "projection", 0.1);
  multibody::MultibodyProblem system(one_body_system(s));
  multibody::MultibodyOde ode(system, false, s.source);
  REQUIRE(ode.by_body());
  Eigen::VectorXd x, f(ode.size());
  ode.initial_state(0.0, x);
  REQUIRE(ode.rhs(0.0, x.data(), f.data()));  // the mass matrix's first factorisation
  test::start_counting_allocations();
  const bool ok = ode.rhs(0.05, x.data(), f.data());
  const OdeDrift d = ode.drift(0.05, x.data());
  const long allocations = test::stop_counting_allocations();
  CHECK(ok);
  CHECK(d.position >= 0.0);
  CHECK(allocations == 0);

  // heavy_top_absolute: the same top as a free body on a spherical joint.
  const Scene joint = io::load_scene(std::string(RIGIDAE_SOURCE_DIR) + "/problems/heavy_top_absolute.toml");
  Scene joint_ode = joint;
  joint_ode.formulation.scheme = "projection";
  multibody::MultibodyProblem coupled(joint_ode);
  CHECK_FALSE(coupled.bodies_decoupled());
  multibody::MultibodyOde kkt(coupled, false, joint.source);
  CHECK_FALSE(kkt.by_body());
}

TEST_SUITE_END();
