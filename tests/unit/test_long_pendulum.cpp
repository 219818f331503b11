// problems/pendulum_1000.toml: a compound pendulum released at 90 degrees,
// whose exact period is T = 4 K(1/2) / w0 (complete elliptic integral). Its
// output grid is every T/4, where the bob is exactly at (1, 0, 0), (0, 0, -1),
// (-1, 0, 0), (0, 0, -1) in turn: the scene's own header claims this, and
// these tests hold it to the integrator at a tight tolerance, with K from
// the library's elliptic integral (an independent computation of the period).
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "rigidae/exact/jacobi_elliptic.hpp"

TEST_SUITE_BEGIN("system");

namespace {

// The bob's exact position at the k-th quarter period.
std::array<double, 3> quarter_point(long k) {
  switch (k % 4) {
    case 0: return {1.0, 0.0, 0.0};
    case 2: return {-1.0, 0.0, 0.0};
    default: return {0.0, 0.0, -1.0};
  }
}

// Largest distance of the bob from the exact quarter points over trajectory.csv's rows.
double worst_quarter_miss(const std::vector<std::map<std::string, std::string>>& rows) {
  double worst = 0.0;
  for (long k = 0; k < static_cast<long>(rows.size()); ++k) {
    const auto p = quarter_point(k);
    const double dx = std::stod(rows[k].at("bob.x")) - p[0], dy = std::stod(rows[k].at("bob.y")) - p[1],
                 dz = std::stod(rows[k].at("bob.z")) - p[2];
    worst = std::max(worst, std::sqrt(dx * dx + dy * dy + dz * dz));
  }
  return worst;
}

}  // namespace

TEST_CASE("pendulum_1000: the scene's period is 4 K(1/2) / w0, and its grid is every quarter of it") {
  const double w0 = std::sqrt(9.81 * 1.0 * 1.0 / (1.0 + 1e-4));
  // complete_elliptic_k takes m1 = 1 - m; here m = m1 = 1/2.
  const double period = 4.0 * rigidae::exact::complete_elliptic_k(0.5) / w0;
  const std::string scene = rigidae::test::read_file(std::string(RIGIDAE_SOURCE_DIR) + "/problems/pendulum_1000.toml");
  CHECK(scene.find("end = 2367.9603367139616") != std::string::npos);
  CHECK(scene.find("output_step = 0.5919900841784904") != std::string::npos);
  CHECK(1000.0 * period == doctest::Approx(2367.9603367139616).epsilon(1e-15));
  CHECK(period / 4.0 == doctest::Approx(0.5919900841784904).epsilon(1e-15));
}

TEST_CASE("pendulum_1000: over two exact periods the bob passes every quarter point within 1e-7 m at rtol 1e-11") {
  const auto dir = rigidae::test::fresh_temp_dir("pendulum-1000");
  const auto r = rigidae::test::run_cli("solve " + std::string(RIGIDAE_SOURCE_DIR) +
                                        "/problems/pendulum_1000.toml --t-end 4.7359206734279234 --rtol 1e-11 "
                                        "--atol 1e-11 --quiet --out " + dir.string());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const auto rows = rigidae::test::read_csv_rows(dir / "trajectory.csv");
  REQUIRE(rows.size() == 9);  // t = 0, T/4, ..., 2T
  const double worst = worst_quarter_miss(rows);
  // The bottom is the sensitive point: a period off by 1e-7 s (0.04 ppm)
  // would already put the bob 4.4e-7 m away there after one period.
  CHECK(worst < 1e-7);
}

TEST_CASE("pendulum_1000_pivot: the same pendulum as a pivoted body, its default run on the exact quarter points over 10 periods") {
  // The same body, hinge, gravity, end and grid as pendulum_1000.toml: only `pivot` and the run's settings differ.
  const std::string dir_problems = std::string(RIGIDAE_SOURCE_DIR) + "/problems/";
  const std::string free = rigidae::test::read_file(dir_problems + "pendulum_1000.toml");
  const std::string pivot = rigidae::test::read_file(dir_problems + "pendulum_1000_pivot.toml");
  auto body_of = [](const std::string& s) { return s.substr(s.find("[[bodies]]"), s.find("[formulation]") - s.find("[[bodies]]")); };
  std::string pivot_body = body_of(pivot);
  const std::string pivot_line = "pivot = [0.0, 0.0, 0.0]\n";
  REQUIRE(pivot_body.find(pivot_line) != std::string::npos);
  pivot_body.erase(pivot_body.find(pivot_line), pivot_line.size());
  CHECK(pivot_body == body_of(free));
  // Its default (ARKODE Fehlberg 7(8), index1, rtol 1e-12) over 10 periods.
  // The grid's rows are integrated to each output time from the step's start
  // (src/solver/arkode_stepper.cpp): measured 1.1e-10 m at worst (a bottom
  // row, where the bob passes at 4.43 m/s), 5.7e-12 m at the turning points
  // and at the end. ARKODE's interpolant between steps of ~0.05 s had left
  // the bottom rows 1e-7 to 5.3e-7 m off.
  const auto dir = rigidae::test::fresh_temp_dir("pendulum-1000-pivot");
  const auto r = rigidae::test::run_cli("solve " + dir_problems + "pendulum_1000_pivot.toml --t-end 23.679603367139617 "
                                        "--record grid --quiet --out " + dir.string());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const auto rows = rigidae::test::read_csv_rows(dir / "trajectory.csv");
  REQUIRE(rows.size() == 41);  // t = 0, T/4, ..., 10 T
  CHECK(worst_quarter_miss(rows) < 1e-9);
  // The turning points (rows 0, 2, 4, ...: (1, 0, 0) and (-1, 0, 0) in turn).
  double worst_turning = 0.0;
  for (std::size_t k = 0; k < rows.size(); k += 2) {
    const auto p = quarter_point(static_cast<long>(k));
    const double dx = std::stod(rows[k].at("bob.x")) - p[0], dz = std::stod(rows[k].at("bob.z")) - p[2];
    worst_turning = std::max(worst_turning, std::sqrt(dx * dx + dz * dz + std::pow(std::stod(rows[k].at("bob.y")), 2)));
  }
  CHECK(worst_turning < 1e-10);
  const auto end = quarter_point(40);
  CHECK(std::abs(std::stod(rows.back().at("bob.x")) - end[0]) < 1e-9);
}

TEST_SUITE_END();
