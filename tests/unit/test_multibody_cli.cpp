// `rigidae solve` on every shipped multibody scene (schema 2), as a user runs
// it: each one finishes with exit 0 and its files; and the absolute-coordinate
// heavy top (a free body held by a spherical joint) ends where the one-body
// pivoted heavy top ends, an independent model of the same motion.
#include <doctest/doctest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.hpp"

TEST_SUITE_BEGIN("system");

namespace {

namespace fs = std::filesystem;
const std::string kProblems = std::string(RIGIDAE_SOURCE_DIR) + "/problems/";

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string cell;
  while (std::getline(ss, cell, ',')) out.push_back(cell);
  return out;
}

// The last row of trajectory.csv, the named columns (# comment lines skipped).
std::vector<double> last_row(const fs::path& csv, const std::vector<std::string>& columns) {
  std::ifstream in(csv);
  REQUIRE(in);
  std::string line, header, last;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (header.empty())
      header = line;
    else
      last = line;
  }
  const std::vector<std::string> names = split(header), values = split(last);
  REQUIRE(names.size() == values.size());
  std::vector<double> out;
  for (const std::string& c : columns) {
    std::size_t k = 0;
    while (k < names.size() && names[k] != c) ++k;
    REQUIRE_MESSAGE(k < names.size(), "no column " << c << " in " << csv);
    out.push_back(std::stod(values[k]));
  }
  return out;
}

}  // namespace

TEST_CASE("multibody cli: every shipped multibody scene solves (short span) with exit 0 and writes its files") {
  for (const char* name : {"heavy_top_absolute", "double_pendulum", "four_bar", "slider_mechanism", "chain_10"}) {
    CAPTURE(name);
    const fs::path dir = rigidae::test::fresh_temp_dir(std::string("mb_") + name);
    const rigidae::test::CliResult r =
        rigidae::test::run_cli("solve " + kProblems + name + ".toml --t-end 0.2 --quiet --out " + dir.string());
    CAPTURE(r.output);
    CHECK(r.exit_code == 0);
    for (const char* f : {"steps.csv", "trajectory.csv", "events.csv", "summary.json"})
      CHECK(fs::exists(dir / f));
    // The output grid reaches t_end.
    CHECK(std::abs(last_row(dir / "trajectory.csv", {"t"})[0] - 0.2) < 1e-12);
  }
}

TEST_CASE("multibody cli: heavy_top_absolute ends at heavy_top's orientation (same t_end, rtol 1e-8)") {
  // Both files: t_end = 2 s, rtol = atol = 1e-8, the same top and start. The
  // two models differ in coordinates (6 + 4 plus 3 joint multipliers against
  // a pivoted quaternion), so they agree to the integration error only: at
  // rtol 1e-8 over 2 s of a 150 rad/s spin the measured difference is
  // 5.1e-6; the bound 1e-4 leaves room for the error's growth and still
  // fails for a wrong joint point, mass or inertia (those move q by O(1)).
  const fs::path a = rigidae::test::fresh_temp_dir("mb_top_abs"), b = rigidae::test::fresh_temp_dir("mb_top");
  const auto ra = rigidae::test::run_cli("solve " + kProblems + "heavy_top_absolute.toml --quiet --out " + a.string());
  const auto rb = rigidae::test::run_cli("solve " + kProblems + "heavy_top.toml --quiet --out " + b.string());
  REQUIRE_MESSAGE(ra.exit_code == 0, ra.output);
  REQUIRE_MESSAGE(rb.exit_code == 0, rb.output);
  const std::vector<double> qa = last_row(a / "trajectory.csv", {"t", "top.qw", "top.qx", "top.qy", "top.qz"});
  const std::vector<double> qb = last_row(b / "trajectory.csv", {"t", "qw", "qx", "qy", "qz"});
  CHECK(qa[0] == doctest::Approx(2.0).epsilon(1e-12));
  CHECK(qb[0] == doctest::Approx(2.0).epsilon(1e-12));
  // q and -q are one orientation.
  double plus = 0, minus = 0;
  for (int k = 1; k <= 4; ++k) {
    plus = std::max(plus, std::abs(qa[k] - qb[k]));
    minus = std::max(minus, std::abs(qa[k] + qb[k]));
  }
  const double diff = std::min(plus, minus);
  MESSAGE("heavy top: |q_absolute - q_pivoted|_max at t = 2 s: " << diff);
  CHECK(diff < 1e-4);
}

TEST_CASE("multibody cli: compare runs a multibody scene against its tight reference, and errors fall with rtol") {
  // Independent truth: a tight run (rtol 1e-12) of the same scene, itself
  // cross-checked by other coordinates. Short span: the double pendulum is chaotic.
  double previous[3] = {0, 0, 0};
  int k = 0;
  for (const char* rtol : {"1e-5", "1e-7", "1e-9"}) {
    CAPTURE(rtol);
    const fs::path dir = rigidae::test::fresh_temp_dir(std::string("mb_compare_") + rtol) / "out";
    const auto r = rigidae::test::run_cli("compare " + kProblems + "double_pendulum.toml --t-end 0.3 --repeat 1 --rtol " +
                                          rtol + " --atol " + rtol +
                                          " --only 'quaternion/euler/ggl,linear/lagrange/index2,euler/euler/baumgarte' "
                                          "--quiet --out " + dir.string());
    CAPTURE(r.output);
    REQUIRE(r.exit_code == 0);
    const auto rows = rigidae::test::read_csv_rows(dir / "compare.csv");
    REQUIRE(rows.size() == 3);
    int i = 0;
    for (const auto& row : rows) {
      CAPTURE(row.at("combination"));
      CHECK(row.at("status") == "success");
      const double err = std::stod(row.at("error_final_rad")), pos = std::stod(row.at("error_position_final_m"));
      MESSAGE(row.at("combination") << " rtol " << std::string(rtol) << ": final error " << err << " rad, position " << pos << " m");
      CHECK(err > 0.0);
      CHECK(err < 1e3 * std::stod(rtol));  // within the tolerance's order, not off the reference
      CHECK(std::isfinite(pos));
      CHECK(std::stod(row.at("max_drift_position")) >= 0.0);
      if (k > 0) CHECK(err < previous[i]);  // tighter rtol, smaller error
      previous[i++] = err;
    }
    CHECK(fs::exists(dir / "reference" / "trajectory.csv"));
    CHECK(fs::exists(dir / "reference-check" / "summary.json"));
    ++k;
  }
}

TEST_CASE("multibody cli: compare on a multibody scene runs every coordinates x equations x scheme of every integrator") {
  const fs::path dir = rigidae::test::fresh_temp_dir("mb_compare_all") / "out";
  auto r = rigidae::test::run_cli("compare " + kProblems + "four_bar.toml --t-end 0.05 --repeat 1 --quiet --out " +
                                  dir.string());
  CAPTURE(r.output);
  REQUIRE(r.exit_code == 0);
  const auto rows = rigidae::test::read_csv_rows(dir / "compare.csv");
  // IDA: every scheme (Euler angles carry the joints too); the three ODE
  // integrators: index1 and projection (their ODE form).
  CHECK(rows.size() == 3 * 2 * 6 + 3 * (3 * 2 * 2));
  std::map<std::string, int> per_integrator;
  for (const auto& row : rows) {
    ++per_integrator[row.at("integrator").substr(0, row.at("integrator").find(':'))];  // arkode-erk:TABLE
    CHECK(row.at("status") == "success");
  }
  CHECK(per_integrator["ida"] == 36);
  CHECK(per_integrator["cvode-adams"] == 12);
  CHECK(per_integrator["cvode-bdf"] == 12);
  CHECK(per_integrator["arkode-erk"] == 12);
  // A DAE-only scheme on an ODE integrator: refused with the valid ones.
  r = rigidae::test::run_cli("solve " + kProblems + "four_bar.toml --integrator arkode-erk --scheme ggl --quiet --out " +
                             (dir.parent_path() / "solve").string());
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("valid schemes with arkode-erk: index1, projection") != std::string::npos);
}

TEST_SUITE_END();
