// The table of output columns: it writes today's headers and units line (the
// format readers of steps.csv and trajectory.csv rely on), rows as wide as
// their header, and summary.json's final row equal to steps.csv's last.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "rigidae/record/columns.hpp"

TEST_SUITE_BEGIN("system");

namespace fs = std::filesystem;
namespace columns = rigidae::columns;

namespace {

std::vector<std::string> cells(const std::string& line) {
  std::vector<std::string> v;
  std::stringstream ss(line);
  std::string c;
  while (std::getline(ss, c, ',')) v.push_back(c);
  return v;
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> v;
  std::stringstream ss(text);
  std::string l;
  while (std::getline(ss, l)) v.push_back(l);
  return v;
}

}  // namespace

TEST_CASE("columns: the table gives the units line and headers the CSV files have always had") {
  // The format as the recorder wrote it before the table (commit db28b4f).
  CHECK(columns::units_line() ==
        "# units: t s; h s; qw..qz unit quaternion of R_WB (body to space, scalar first); omega_* rad/s body frame; "
        "drift_position |Phi(q)| 1; drift_velocity |dPhi/dt| 1/s; lambda_* J (generalized constraint force); "
        "mu_* 1/s (kinematic multiplier); energy J; energy_rel_error (H-H0)/|H0|; vertical_momentum kg m^2/s about "
        "the reference point; vertical_momentum_rel_error (Lz-Lz0)/|L0|");
  CHECK(columns::header(columns::kSteps, {"lambda_q", "mu_q"}, false) ==
        "t,h,order,qw,qx,qy,qz,omega_x,omega_y,omega_z,drift_position,drift_velocity,lambda_q,mu_q,energy,"
        "energy_rel_error,vertical_momentum,vertical_momentum_rel_error");
  CHECK(columns::header(columns::kTrajectory, {}, true) ==
        "t,qw,qx,qy,qz,omega_x,omega_y,omega_z,drift_position,drift_velocity,energy,energy_rel_error,"
        "vertical_momentum,vertical_momentum_rel_error,chart");
}

TEST_CASE("columns: a run's CSV rows match their header, and summary.json's final row is steps.csv's last") {
  const fs::path out = rigidae::test::fresh_temp_dir("columns");
  const std::string scene = std::string(RIGIDAE_SOURCE_DIR) + "/problems/heavy_top.toml";
  for (const char* coords : {"quaternion", "euler"}) {
    CAPTURE(coords);
    const fs::path dir = out / coords;
    const auto r = rigidae::test::run_cli("solve " + scene + " --coordinates " + coords +
                                          " --t-end 0.02 --quiet --out " + dir.string());
    REQUIRE(r.exit_code == 0);
    for (const char* file : {"steps.csv", "trajectory.csv"}) {
      const std::vector<std::string> l = lines(rigidae::test::read_file(dir / file));
      REQUIRE(l.size() > 3);
      // The table's units, then (quaternions carry a multiplier) the note
      // that IDA's error test leaves the multipliers out.
      CHECK(l[0].rfind(columns::units_line(), 0) == 0);
      CHECK((l[0].find("; multipliers NOT error-controlled: scheme ggl") != std::string::npos) ==
            (std::string(coords) == "quaternion"));
      const std::vector<std::string> head = cells(l[1]);
      const auto qw = std::find(head.begin(), head.end(), "qw") - head.begin();
      for (std::size_t k = 2; k < l.size(); ++k) {
        const std::vector<std::string> row = cells(l[k]);
        REQUIRE(row.size() == head.size());
        double norm2 = 0;
        for (int i = 0; i < 4; ++i) norm2 += std::pow(std::stod(row[qw + i]), 2);
        CHECK(std::abs(norm2 - 1.0) < 1e-12);  // the orientation is a unit quaternion
      }
      CHECK((std::find(head.begin(), head.end(), "chart") != head.end()) == (std::string(coords) == "euler"));
    }
    // The final row is the last recorded step's observation.
    const std::vector<std::string> grid = lines(rigidae::test::read_file(dir / "steps.csv"));
    const std::vector<std::string> head = cells(grid[1]), last = cells(grid.back());
    const nlohmann::json summary = nlohmann::json::parse(rigidae::test::read_file(dir / "summary.json"));
    const nlohmann::json& final_row = summary["final_row"];
    int compared = 0;
    for (std::size_t i = 0; i < head.size(); ++i) {
      if (head[i] == "chart" || head[i] == "h" || head[i] == "order") continue;
      CAPTURE(head[i]);
      REQUIRE(final_row.contains(head[i]));
      CHECK(final_row[head[i]].get<double>() == std::stod(last[i]));  // shortest round-trip text: exact
      ++compared;
    }
    CHECK(compared == static_cast<int>(final_row.size()));
  }
  fs::remove_all(out);
}

TEST_SUITE_END();
