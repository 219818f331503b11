// problems/pendulum_1000.toml: a compound pendulum released at 90 degrees,
// whose exact period is T = 4 K(1/2) / w0 (complete elliptic integral). Its
// output grid is every T/4, where the bob is exactly at (1, 0, 0), (0, 0, -1),
// (-1, 0, 0), (0, 0, -1) in turn: the scene's own header claims this, and
// these tests hold it to the integrator at a tight tolerance, with K from
// the library's elliptic integral (an independent computation of the period).
#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <string>

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
  double worst = 0.0;
  for (long k = 0; k < static_cast<long>(rows.size()); ++k) {
    const auto p = quarter_point(k);
    const double dx = std::stod(rows[k].at("bob.x")) - p[0], dy = std::stod(rows[k].at("bob.y")) - p[1],
                 dz = std::stod(rows[k].at("bob.z")) - p[2];
    worst = std::max(worst, std::sqrt(dx * dx + dy * dy + dz * dz));
  }
  // The bottom is the sensitive point: a period off by 1e-7 s (0.04 ppm)
  // would already put the bob 4.4e-7 m away there after one period.
  CHECK(worst < 1e-7);
}

TEST_SUITE_END();
