// The heavy-top benchmark solved end to end in every representation.
#include <doctest/doctest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "rigidae/app/solve.hpp"
#include "rigidae/so3/rotation.hpp"
#include "scratch_dir.hpp"
#include "test_scenes.hpp"

TEST_SUITE_BEGIN("system");

using namespace rigidae;

namespace {

std::filesystem::path scratch(const std::string& name) {
  return test::scratch_dir("rigidae_tests", name, false);
}

SolveOutcome run(Coordinates c, Equations e, const std::string& scheme, double tol) {
  Scene s = test::heavy_top_scene(c, e, scheme);
  s.solver.rtol = s.solver.atol = tol;
  return solve_scene(s, scratch(default_run_name(s) + "-" + std::to_string(tol)));
}

struct Combo {
  Coordinates c;
  Equations e;
};
const Combo kSix[] = {{Coordinates::EulerAngles, Equations::Lagrange}, {Coordinates::EulerAngles, Equations::Euler},
                      {Coordinates::Quaternion, Equations::Lagrange},  {Coordinates::Quaternion, Equations::Euler},
                      {Coordinates::Linear, Equations::Lagrange},      {Coordinates::Linear, Equations::Euler}};

std::string label(const Combo& k) { return to_string(k.c) + "/" + to_string(k.e); }

// The reference: quaternions, Euler form, GGL at rtol 1e-12 (its own
// accuracy: it agrees with the Euler-angle and linear-coordinate Euler forms
// at 1e-12 to ~1e-8 rad).
const Vec4& reference_q() {
  static const Vec4 q = run(Coordinates::Quaternion, Equations::Euler, "ggl", 1e-12).extremes.last.q_WB;
  return q;
}

}  // namespace

TEST_CASE("the heavy top ends near the published quaternion at t = 2 s") {
  // Exudyn's RK4 data, 5 digits: (0.12295, -0.49108, 0.35043, -0.78799).
  const SolveOutcome o = run(Coordinates::Quaternion, Equations::Euler, "ggl", 1e-8);
  REQUIRE(o.run.status == RunStatus::Success);
  const Vec4 published(0.12295, -0.49108, 0.35043, -0.78799);
  CHECK(o.extremes.last.t == 2.0);
  CHECK((o.extremes.last.q_WB - published).cwiseAbs().maxCoeff() < 2e-5);
  CHECK(so3::quaternion_distance(reference_q(), published.normalized()) < 3e-5);
}

TEST_CASE("the six combinations agree with each other at t = 2 s" * doctest::test_suite("slow")) {
  for (const Combo& k : kSix) {
    CAPTURE(label(k));
    // At rtol 1e-12 every combination is within 1e-6 rad of the reference.
    const SolveOutcome tight = run(k.c, k.e, "ggl", 1e-12);
    REQUIRE(tight.run.status == RunStatus::Success);
    CHECK(so3::quaternion_distance(tight.extremes.last.q_WB, reference_q()) < 1e-6);
    // At rtol 1e-10 the Euler forms are; the Lagrange forms, whose error
    // control acts on the fast-oscillating coordinate velocities q', measured
    // 1e-6 to 5.3e-5 rad (see README), so they get a wider bound.
    const SolveOutcome loose = run(k.c, k.e, "ggl", 1e-10);
    REQUIRE(loose.run.status == RunStatus::Success);
    const double bound = k.e == Equations::Euler ? 1e-6 : 1e-4;
    CHECK(so3::quaternion_distance(loose.extremes.last.q_WB, reference_q()) < bound);
  }
}

TEST_CASE("every start is consistent to round-off") {
  for (const Combo& k : kSix)
    for (const char* scheme : {"ggl", "index1"}) {
      CAPTURE(label(k));
      CAPTURE(scheme);
      Scene s = test::heavy_top_scene(k.c, k.e, scheme);
      s.time.end = 1e-3;
      const SolveOutcome o = solve_scene(s, scratch("start-" + default_run_name(s)));
      CHECK(o.run.status == RunStatus::Success);
      // Residual rows are forces of size |M v'| ~ 15 kg m^2 * 150^2 / s^2.
      CHECK(o.run.initial_residual < 1e-10 * 15 * 150 * 150);
    }
}

TEST_CASE("energy and vertical angular momentum are conserved to the tolerance's order" * doctest::test_suite("slow")) {
  for (const Combo& k : kSix) {
    CAPTURE(label(k));
    const SolveOutcome o = run(k.c, k.e, "ggl", 1e-10);
    REQUIRE(o.run.status == RunStatus::Success);
    CHECK(o.extremes.max_abs_energy_error < 1e-6);
    CHECK(o.extremes.max_abs_vertical_momentum_error < 1e-6);
    // The spin about the symmetry axis is constant for a symmetric top; the
    // Euler form integrates it directly, the Lagrange form recovers it from q, q'.
    const double spin_tol = k.e == Equations::Euler ? 1e-8 : 1e-5;
    CHECK(o.extremes.last.omega_B(1) == doctest::Approx(150.0).epsilon(spin_tol));
  }
}

TEST_CASE("GGL holds both constraint levels, and index 1 lets them drift") {
  for (const Combo& k : kSix) {
    if (k.c == Coordinates::EulerAngles) continue;
    CAPTURE(label(k));
    const SolveOutcome ggl = run(k.c, k.e, "ggl", 1e-10);
    REQUIRE(ggl.run.status == RunStatus::Success);
    CHECK(ggl.extremes.max_drift_position < 1e-8);
    const SolveOutcome i1 = run(k.c, k.e, "index1", 1e-10);
    REQUIRE(i1.run.status == RunStatus::Success);
    // The report shows index 1's drift: larger than GGL's by a wide margin.
    CHECK(i1.extremes.max_drift_position > 10 * ggl.extremes.max_drift_position);
    if (k.e == Equations::Lagrange) CHECK(i1.extremes.max_drift_velocity > 10 * ggl.extremes.max_drift_velocity);
  }
}

TEST_CASE("Euler angles switch charts around their singularities and record each switch") {
  const SolveOutcome o = run(Coordinates::EulerAngles, Equations::Euler, "ggl", 1e-8);
  REQUIRE(o.run.status == RunStatus::Success);
  CHECK(o.run.switches.size() >= 2);
  CHECK(o.run.counters.restarts == static_cast<long>(o.run.switches.size()));
  for (const ChartSwitch& s : o.run.switches) {
    CHECK(s.from != s.to);
    CHECK(s.margin == doctest::Approx(0.1).epsilon(1e-3));
  }
  std::ifstream events(o.out_dir / "events.csv");
  std::string line;
  long rows = -2;  // units and header
  while (std::getline(events, line)) ++rows;
  CHECK(rows == static_cast<long>(o.run.switches.size()));
}

TEST_CASE("with chart switching off, Euler angles stop at the singularity with a clear message") {
  Scene s = test::heavy_top_scene(Coordinates::EulerAngles, Equations::Euler);
  s.formulation.euler.switching = false;
  const SolveOutcome o = solve_scene(s, scratch("no-switching"));
  CHECK(o.run.status == RunStatus::Failed);
  CHECK(o.run.message.find("singularity") != std::string::npos);
  CHECK(o.run.message.find("switching") != std::string::npos);
  CHECK(o.extremes.steps_recorded > 0);
  CHECK(o.run.t_reached < 2.0);
}

TEST_CASE("a run that fails keeps every step it took on disk") {
  Scene s = test::heavy_top_scene();
  s.solver.max_steps = 50;
  const SolveOutcome o = solve_scene(s, scratch("too-much-work"));
  CHECK(o.run.status == RunStatus::Failed);
  CHECK(o.run.message.find("too much work") != std::string::npos);
  std::ifstream steps(o.out_dir / "steps.csv");
  std::string line;
  long rows = -2;
  while (std::getline(steps, line)) ++rows;
  CHECK(rows == 50);
  std::ifstream summary(o.out_dir / "summary.json");
  const std::string text((std::istreambuf_iterator<char>(summary)), std::istreambuf_iterator<char>());
  CHECK(text.find("\"status\": \"failed\"") != std::string::npos);
}

TEST_CASE("the output grid holds the start and the end exactly") {
  const std::vector<double> g = output_grid({0.0, 2.0, 0.3});
  REQUIRE(g.size() == 8);
  CHECK(g.front() == 0.0);
  CHECK(g[6] == doctest::Approx(1.8));
  CHECK(g.back() == 2.0);
  CHECK(output_grid({0.0, 1.0, 0.1}).size() == 11);
}

TEST_SUITE_END();
