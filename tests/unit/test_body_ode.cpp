// The multibody ODE form of decoupled bodies (MultibodyOde's per-body path,
// schemes/body_ode.hpp) against its own KKT path:
// - at random states off the manifold, for every coordinates x equations x
//   {index1, projection} on the heavy top, the free asymmetric body,
//   sleeping_top and a lamina (whose mass matrix is singular in linear
//   coordinates' Lagrange form), the right-hand side and the observed
//   multipliers are the KKT path's to round-off (an LU of the saddle-point
//   matrix against the Schur complement of M), and the projection lands on
//   the manifold. (That the per-body path's runs are the deleted one-body
//   ODE form's, bit for bit, is pinned by tests/guard/pinned.json's
//   ode_runs, recorded while both existed.)
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
#include "rigidae/io/scene_loader.hpp"
#include "rigidae/model/one_body_system.hpp"
#include "rigidae/multibody/multibody_ode.hpp"
#include "rigidae/multibody/multibody_problem.hpp"
#include "rigidae/solver/ode_driver.hpp"

TEST_SUITE_BEGIN("unit");

using namespace rigidae;

namespace {

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

TEST_CASE("body ODE: at random states the per-body rhs and multipliers are the KKT path's to round-off, and the "
          "projection lands on the manifold") {
  int checked = 0, projected = 0;
  for (const Combination& c : combinations()) {
    CAPTURE(label(c));
    const Scene s = scene_for(c.file, c.coords, c.equations, c.scheme, c.t_end);
    multibody::MultibodyProblem system(one_body_system(s));
    multibody::MultibodyOde by_body(system, false, s.source);
    multibody::MultibodyOde kkt(system, false, s.source, true, /*by_body=*/false);
    REQUIRE(by_body.by_body());
    REQUIRE_FALSE(kkt.by_body());
    const int n = by_body.size();
    REQUIRE(kkt.size() == n);
    Eigen::VectorXd x0, x0_kkt;
    by_body.initial_state(0.0, x0);
    kkt.initial_state(0.0, x0_kkt);
    CHECK(differing(x0.data(), x0_kkt.data(), n) == 0);
    std::mt19937 rng(11);
    for (int trial = 0; trial < 5; ++trial) {
      Eigen::VectorXd x = x0, unused = x0;
      test::perturb_state(rng, x, unused);  // off the start and off the manifold
      const double t = 0.1 * trial;
      Eigen::VectorXd f2(n), f3(n);
      REQUIRE(by_body.rhs(t, x.data(), f2.data()));
      REQUIRE(kkt.rhs(t, x.data(), f3.data()));
      // The KKT path: another factorisation of the same linear system.
      CHECK((f3 - f2).cwiseAbs().maxCoeff() <= 1e-10 * std::max(1.0, f2.cwiseAbs().maxCoeff()));
      Eigen::VectorXd y2, y3;
      by_body.observe(t, x.data(), y2);
      kkt.observe(t, x.data(), y3);
      REQUIRE(y3.size() == y2.size());
      CHECK((y3 - y2).cwiseAbs().maxCoeff() <= 1e-9 * std::max(1.0, y2.cwiseAbs().maxCoeff()));
      if (system.bodies()[0].rep->nc() > 0) {
        // Off the manifold before, on it after (the drift's own rule:
        // |Phi| and, for the Lagrange form, |G v|).
        const OdeDrift before = by_body.drift(t, x.data());
        CHECK(std::max(before.position, before.velocity) > 1e-6);
        Eigen::VectorXd p2 = x;
        by_body.project(t, p2.data());
        const OdeDrift after = by_body.drift(t, p2.data());
        CHECK(after.position <= 1e-13);
        CHECK(after.velocity <= 1e-12 * std::max(1.0, p2.cwiseAbs().maxCoeff()));
        Eigen::VectorXd e2 = Eigen::VectorXd::Ones(n);
        by_body.project_error(t, p2.data(), e2.data());
        CHECK(e2.cwiseAbs().maxCoeff() > 0.0);
        ++projected;
      }
      ++checked;
    }
  }
  CHECK(checked == 24 * 5);
  CHECK(projected == 18 * 5);  // all but the six Euler-angle combinations (no constraint)
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
