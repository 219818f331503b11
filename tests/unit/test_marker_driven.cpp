// A marker on a driven crank: its acceleration is solved at the recorded
// row's own time (markers.cpp), which a driver's row depends on. Independent
// truth: the crank turns by the prescribed angle f(t) = A sin(W t) about z,
// so the tip at radius r has
//   p = r (cos f, sin f, 0),  p' = r f' (-sin f, cos f, 0),
//   p'' = r (-f'^2 cos f - f'' sin f, -f'^2 sin f + f'' cos f, 0).
#include <doctest/doctest.h>

#include <cmath>
#include <fstream>
#include <string>

#include "cli_runner.hpp"

TEST_SUITE_BEGIN("system");

namespace {

constexpr double kR = 0.3, kA = 0.8, kW = 5.0;

const char* kScene = R"(schema_version = 2
name = "driven_crank_marker"

[[bodies]]
name = "crank"
mass = 0.5
inertia_principal = [0.0005, 0.004, 0.004]
position = [0.15, 0.0, 0.0]
angular_velocity = [0.0, 0.0, 4.0]     # A W: consistent with the driver at t = 0

[[joints]]
name = "bearing"
type = "revolute"
bodies = ["ground", "crank"]
point = [0.0, 0.0, 0.0]
axis = [0.0, 0.0, 1.0]

[[drivers]]
joint = "bearing"
motion = { type = "harmonic", amplitude = 0.8, omega = 5.0 }

[[markers]]
name = "tip"
body = "crank"
point = [0.3, 0.0, 0.0]

[gravity]
acceleration = [0.0, 0.0, 0.0]

[time]
end = 1.0
output_step = 0.05

[solver]
rtol = 1e-10
atol = 1e-10
)";

double cell(const std::map<std::string, std::string>& row, const std::string& key) {
  REQUIRE_MESSAGE(row.count(key), key);
  return std::stod(row.at(key));
}

}  // namespace

TEST_CASE("a marker on a driven crank: position, velocity and acceleration of the prescribed motion") {
  const auto dir = rigidae::test::fresh_temp_dir("marker_driven");
  { std::ofstream(dir / "crank.toml") << kScene; }
  const auto r = rigidae::test::run_cli("solve " + (dir / "crank.toml").string() + " --quiet --out " +
                                        (dir / "run").string());
  REQUIRE_MESSAGE(r.exit_code == 0, r.output);
  double worst_p = 0.0, worst_v = 0.0, worst_a = 0.0;
  int rows = 0;
  for (const auto& row : rigidae::test::read_csv_rows(dir / "run" / "trajectory.csv")) {
    const double t = cell(row, "t");
    const double f = kA * std::sin(kW * t), fd = kA * kW * std::cos(kW * t), fdd = -kA * kW * kW * std::sin(kW * t);
    const double c = std::cos(f), s = std::sin(f);
    const double p[3] = {kR * c, kR * s, 0.0};
    const double v[3] = {-kR * fd * s, kR * fd * c, 0.0};
    const double a[3] = {kR * (-fd * fd * c - fdd * s), kR * (-fd * fd * s + fdd * c), 0.0};
    const char* axes[3] = {"x", "y", "z"};
    for (int k = 0; k < 3; ++k) {
      worst_p = std::max(worst_p, std::abs(cell(row, std::string("tip.") + axes[k]) - p[k]));
      worst_v = std::max(worst_v, std::abs(cell(row, std::string("tip.v") + axes[k]) - v[k]));
      worst_a = std::max(worst_a, std::abs(cell(row, std::string("tip.a") + axes[k]) - a[k]));
    }
    ++rows;
  }
  MESSAGE("rows " << rows << ": position " << worst_p << " m, velocity " << worst_v << " m/s, acceleration "
                  << worst_a << " m/s^2 (|a| up to " << kR * (kA * kW) * (kA * kW) << ")");
  CHECK(rows == 21);
  CHECK(worst_p < 1e-8);
  CHECK(worst_v < 1e-7);
  CHECK(worst_a < 1e-6);
}

TEST_SUITE_END();
