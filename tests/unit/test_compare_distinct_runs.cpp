// compare runs only the combinations that can differ, read off the system a
// scene is (app/compare.cpp, combinations_for): a body in Euler angles that
// nothing joins has no constraint rows, so every scheme is the same ODE and
// compare runs it once per integrator (scheme "any"), whether the scene is
// written as one body (schema 1) or as a system of bodies (schema 2).
// Checked where it matters: the schemes it leaves out give the kept run bit
// for bit.
#include <doctest/doctest.h>

#include <algorithm>
#include <fstream>
#include <string>

#include "rigidae/app/compare.hpp"
#include "rigidae/app/solve.hpp"
#include "rigidae/io/scene_loader.hpp"
#include "cli_runner.hpp"

TEST_SUITE_BEGIN("system");

using namespace rigidae;

namespace {

// heavy_top_absolute.toml without its spherical joint: a free body that
// falls and spins, nothing joined.
Scene unjoined_body() {
  Scene s = io::load_scene(std::string(RIGIDAE_SOURCE_DIR) + "/problems/heavy_top_absolute.toml");
  s.multibody->joints.clear();
  s.time.end = 0.2;
  return s;
}

// The last row of a run's trajectory.csv, as written (shortest round-trip digits).
std::string last_row(const std::filesystem::path& dir) {
  std::ifstream f(dir / "trajectory.csv");
  std::string line, last;
  while (std::getline(f, line))
    if (!line.empty()) last = line;
  return last;
}

long count_scheme(const std::vector<Combination>& combos, Coordinates c, const std::string& scheme) {
  return std::count_if(combos.begin(), combos.end(),
                       [&](const Combination& k) { return k.coordinates == c && k.scheme == scheme; });
}

}  // namespace

TEST_CASE("compare: a body that nothing joins runs once per integrator in Euler angles, as a one-body scene does") {
  const Scene system = unjoined_body();
  const Scene one_body = io::load_scene(std::string(RIGIDAE_SOURCE_DIR) + "/problems/heavy_top.toml");
  for (const Scene* s : {&system, &one_body}) {
    CAPTURE(s->source);
    const std::vector<Combination> combos = combinations_for(*s, default_integrators(*s));
    const long integrators = static_cast<long>(default_integrators(*s).size());
    // Euler angles: two forms x each integrator, scheme "any".
    CHECK(count_scheme(combos, Coordinates::EulerAngles, "any") == 2 * integrators);
    CHECK(count_scheme(combos, Coordinates::EulerAngles, "ggl") == 0);
    // Quaternions carry |q| = 1: the schemes differ there.
    CHECK(count_scheme(combos, Coordinates::Quaternion, "ggl") == 2);  // IDA only, both forms
    CHECK(count_scheme(combos, Coordinates::Quaternion, "any") == 0);
  }
  // The joined scene still runs every scheme in Euler angles.
  const Scene joined = io::load_scene(std::string(RIGIDAE_SOURCE_DIR) + "/problems/heavy_top_absolute.toml");
  CHECK(count_scheme(combinations_for(joined, default_integrators(joined)), Coordinates::EulerAngles, "ggl") == 2);
}

TEST_CASE("compare: the schemes left out for a body that nothing joins give the kept run bit for bit") {
  Scene s = unjoined_body();
  s.formulation.coordinates = Coordinates::EulerAngles;
  s.formulation.equations = Equations::Euler;
  const auto run = [&](const std::string& scheme) {
    Scene x = s;
    x.formulation.scheme = scheme;
    return solve_scene(x, test::fresh_temp_dir("unjoined_" + scheme));
  };
  const SolveOutcome kept = run("ggl");
  REQUIRE(kept.run.status == RunStatus::Success);
  REQUIRE(kept.run.counters.steps > 20);
  const std::string kept_end = last_row(kept.out_dir);
  REQUIRE(kept_end.rfind("0.2,", 0) == 0);
  for (const std::string scheme : {"index1", "index3", "baumgarte"}) {
    CAPTURE(scheme);
    const SolveOutcome other = run(scheme);
    CHECK(other.run.counters.steps == kept.run.counters.steps);
    CHECK(other.run.counters.residual_evals == kept.run.counters.residual_evals);
    CHECK(last_row(other.out_dir) == kept_end);  // every column of the final state
  }
}

TEST_SUITE_END();
