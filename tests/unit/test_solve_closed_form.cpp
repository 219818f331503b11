// `rigidae solve` on a scene with a closed form reports the error against it:
// printed, in summary.json's closed_form_error, and with the closed form kept
// on the output grid as reference.csv, so that error against time can be
// drawn. Checked here against the angle recomputed from the two files, and
// against the physics: the error falls as the tolerance falls.
#include <doctest/doctest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "rigidae/so3/rotation.hpp"

TEST_SUITE_BEGIN("system");

namespace fs = std::filesystem;
using rigidae::test::fresh_temp_dir;
using rigidae::test::read_file;
using rigidae::test::run_cli;

namespace {

const std::string kProblems = std::string(RIGIDAE_SOURCE_DIR) + "/problems/";

// t and the quaternion columns qw..qz of a trajectory.csv or reference.csv.
struct Grid {
  std::vector<double> t;
  std::vector<rigidae::Vec4> q;
};

Grid read_grid(const fs::path& csv) {
  std::istringstream in(read_file(csv));
  std::string line;
  std::getline(in, line);  // units
  std::getline(in, line);  // header
  std::vector<std::string> header;
  for (std::stringstream h(line); std::getline(h, line, ',');) header.push_back(line);
  std::size_t qw = 0;
  while (qw < header.size() && header[qw] != "qw") ++qw;
  REQUIRE(qw + 3 < header.size());
  Grid g;
  while (std::getline(in, line)) {
    std::vector<double> c;
    for (std::stringstream row(line); std::getline(row, line, ',');) c.push_back(std::stod(line));
    g.t.push_back(c[0]);
    g.q.emplace_back(c[qw], c[qw + 1], c[qw + 2], c[qw + 3]);
  }
  return g;
}

struct Measured {
  double final = 0, max = 0;
};

Measured solve_free_body(const fs::path& dir, const std::string& tol) {
  const auto r = run_cli("solve " + kProblems + "free_body.toml --t-end 5 --rtol " + tol + " --atol " + tol +
                         " --out " + dir.string());
  CAPTURE(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK(r.output.find("closed form   orientation error") != std::string::npos);
  const nlohmann::json s = nlohmann::json::parse(read_file(dir / "summary.json"));
  REQUIRE(s.contains("closed_form_error"));
  const Measured m{s["closed_form_error"]["final_orientation_rad"].get<double>(),
                   s["closed_form_error"]["max_orientation_rad"].get<double>()};
  // The same angles recomputed from the run's grid and the kept closed form.
  const Grid run = read_grid(dir / "trajectory.csv");
  const Grid ref = read_grid(dir / "reference.csv");
  REQUIRE(run.t.size() == ref.t.size());
  REQUIRE(run.t.size() > 10);
  double max = 0, last = 0;
  for (std::size_t i = 0; i < run.t.size(); ++i) {
    CHECK(run.t[i] == doctest::Approx(ref.t[i]).epsilon(1e-12));
    last = rigidae::so3::quaternion_distance(run.q[i], ref.q[i]);
    max = std::max(max, last);
  }
  CHECK(m.final == doctest::Approx(last).epsilon(1e-9));
  CHECK(m.max == doctest::Approx(max).epsilon(1e-9));
  // The closed form starts where the scene does.
  CHECK(rigidae::so3::quaternion_distance(ref.q.front(), run.q.front()) < 1e-14);
  return m;
}

}  // namespace

TEST_CASE("solve reports the error against the closed form, keeps it on the grid, and the error falls with rtol") {
  const fs::path dir = fresh_temp_dir("closed_form");
  const Measured loose = solve_free_body(dir / "loose", "1e-5");
  const Measured tight = solve_free_body(dir / "tight", "1e-9");
  MESSAGE("free body over 5 s: max error " << loose.max << " rad at tolerance 1e-5, " << tight.max << " at 1e-9");
  CHECK(tight.max < 1e-6);
  CHECK(tight.max < loose.max / 100);
}

TEST_CASE("solve on a scene without a closed form writes no reference.csv and no closed_form_error") {
  const fs::path dir = fresh_temp_dir("no_closed_form");
  // A heavy top whose centre of mass is off its symmetry axis (no closed
  // form), and a multibody scene.
  std::string asymmetric = read_file(kProblems + "heavy_top.toml");
  const std::string com = "center_of_mass = [0.0, 1.0, 0.0]";
  REQUIRE(asymmetric.find(com) != std::string::npos);
  asymmetric.replace(asymmetric.find(com), com.size(), "center_of_mass = [0.1, 1.0, 0.0]");
  std::ofstream(dir / "asymmetric_top.toml") << asymmetric;
  for (const std::string scene : {(dir / "asymmetric_top.toml").string(), kProblems + "double_pendulum.toml"}) {
    CAPTURE(scene);
    const fs::path out = dir / fs::path(scene).stem();
    const auto r = run_cli("solve " + scene + " --t-end 0.05 --out " + out.string());
    CAPTURE(r.output);
    REQUIRE(r.exit_code == 0);
    CHECK(!fs::exists(out / "reference.csv"));
    CHECK(!nlohmann::json::parse(read_file(out / "summary.json")).contains("closed_form_error"));
  }
}

TEST_SUITE_END();
