// solve_scene on a multibody scene: the files a run writes, with columns
// named BODY.qw and JOINT.force_x, and the heavy top's pivot reaction at
// t = 0 (450.28 N in the literature) in trajectory.csv.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <cmath>
#include <sstream>
#include <vector>
#include <string>

#include "scratch_dir.hpp"
#include "rigidae/app/solve.hpp"
#include "test_multibody_scenes.hpp"

TEST_SUITE_BEGIN("system");

using namespace rigidae;

TEST_CASE("multibody solve: trajectory, steps, events and summary with named columns") {
  Scene s = test::absolute_heavy_top(Coordinates::Quaternion, Equations::Euler, "ggl");
  s.name = "heavy_top_absolute";
  s.time = {0.0, 0.05, 0.01};
  const std::filesystem::path dir = test::scratch_dir("rigidae_multibody_solve_test", "solve", false);
  const SolveOutcome o = solve_scene(s, dir);
  REQUIRE(o.run.status == RunStatus::Success);
  for (const char* f : {"trajectory.csv", "steps.csv", "events.csv", "summary.json"})
    CHECK(std::filesystem::exists(dir / f));
  std::ifstream in(dir / "trajectory.csv");
  std::string units, header, first;
  std::getline(in, units);
  std::getline(in, header);
  std::getline(in, first);
  CHECK(units.rfind("# units:", 0) == 0);
  CHECK(header.rfind("t,top.qw,top.qx,top.qy,top.qz,top.wx", 0) == 0);
  const std::size_t col = header.find("pivot.force_x");
  REQUIRE(col != std::string::npos);
  // Column index of pivot.force_x, then |force| from the first row.
  int index = 0;
  for (std::size_t i = 0; i < col; ++i) index += header[i] == ',';
  std::vector<double> values;
  std::stringstream ss(first);
  for (std::string cell; std::getline(ss, cell, ',');) values.push_back(std::stod(cell));
  const double fx = values[index], fy = values[index + 1], fz = values[index + 2];
  CHECK(std::sqrt(fx * fx + fy * fy + fz * fz) == doctest::Approx(450.28).epsilon(1e-4));
  CHECK(o.extremes.steps_recorded == o.run.counters.steps);
  std::filesystem::remove_all(dir);
}

TEST_SUITE_END();
