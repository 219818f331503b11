// Joint coordinates in the records (issue 22 item 5), against truths that do
// not go through them:
//   - a revolute pendulum (hinge about y through the origin, released at
//     60 degrees): JOINT.angle equals the body's rotation about y computed
//     from its orientation columns (theta = atan2(-R_zx, R_xx) for a body
//     that starts at R = I), JOINT.angle_rate equals the body's angular
//     velocity about y (wy) and a central difference of the angle column
//     over the output grid;
//   - a crank spinning freely about a revolute joint (no gravity, no
//     load): its angle is omega t exactly, growing monotonically past 2 pi
//     (four turns), in trajectory.csv and steps.csv alike;
//   - the shipped slider-crank (problems/slider_mechanism.toml, driven by a
//     torque): the crank's angle equals its orientation's angle about z
//     unwrapped here, and the guide's (prismatic) displacement equals the
//     slider's x minus its start x.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "rigidae/app/solve.hpp"
#include "rigidae/io/scene_loader.hpp"
#include "rigidae/so3/rotation.hpp"
#include "test_multibody_scenes.hpp"

TEST_SUITE_BEGIN("system");

using namespace rigidae;
namespace fs = std::filesystem;

namespace {

struct Table {
  std::vector<std::string> names;
  std::vector<std::vector<double>> rows;
  int col(const std::string& name) const {
    for (std::size_t k = 0; k < names.size(); ++k)
      if (names[k] == name) return static_cast<int>(k);
    FAIL("no column " << name);
    return -1;
  }
  double at(std::size_t row, const std::string& name) const { return rows[row][static_cast<std::size_t>(col(name))]; }
};

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  for (std::string cell; std::getline(ss, cell, ',');) out.push_back(cell);
  return out;
}

// A CSV the recorder wrote: a units line, the header, numbers (a steps.csv
// cell that is not a number, e.g. a chart name, reads as NaN).
Table read_table(const fs::path& csv) {
  std::ifstream in(csv);
  REQUIRE(in);
  Table t;
  std::string line;
  std::getline(in, line);  // units
  std::getline(in, line);
  t.names = split(line);
  while (std::getline(in, line)) {
    std::vector<double> row;
    for (const std::string& c : split(line)) {
      char* end = nullptr;
      const double v = std::strtod(c.c_str(), &end);
      row.push_back(end == c.c_str() ? std::nan("") : v);
    }
    REQUIRE(row.size() == t.names.size());
    t.rows.push_back(row);
  }
  return t;
}

Mat3 rotation_of(const Table& t, std::size_t row, const std::string& body) {
  const Vec4 q(t.at(row, body + ".qw"), t.at(row, body + ".qx"), t.at(row, body + ".qy"), t.at(row, body + ".qz"));
  return so3::quaternion_to_matrix(q.normalized());
}

}  // namespace

TEST_CASE("joint coordinates: a revolute pendulum's angle and rate against its orientation and a difference") {
  Scene s = test::multibody_base(Coordinates::Quaternion, Equations::Euler, "ggl");
  s.time = {0.0, 1.0, 0.001};
  s.solver.rtol = s.solver.atol = 1e-10;
  MultibodySpec& m = *s.multibody;
  m.gravity_W = Vec3(0, 0, -9.81);
  BodySpec bob;
  bob.name = "bob";
  bob.mass = 1.0;
  bob.inertia_com = Vec3(0.01, 0.02, 0.015).asDiagonal();
  // Released at 60 degrees about y: the bob at 0.5 m from the hinge.
  const double theta0 = std::numbers::pi / 3;
  const Mat3 R0 = so3::axis_angle_to_matrix(Vec3::UnitY(), theta0);
  bob.R0_WB = R0;
  bob.x0_W = R0 * Vec3(0, 0, -0.5);
  m.bodies.push_back(bob);
  // Hinge about y through the origin; joint_at gives both bodies the normal
  // x in space at the start (R0^T x in the bob), so the angle is zero at
  // the start pose and equals the rotation about y since then.
  JointSpec hinge = test::joint_at(m, &joint_type("revolute"), kGround, 0, Vec3::Zero(), Vec3::UnitY(), Vec3::UnitX(),
                                   "hinge");
  m.joints.push_back(hinge);
  const fs::path dir = test::fresh_temp_dir("joint_coordinates_pendulum");
  const SolveOutcome o = solve_scene(s, dir);
  REQUIRE(o.run.status == RunStatus::Success);
  const Table t = read_table(dir / "trajectory.csv");
  REQUIRE(t.rows.size() > 900);
  double angle_miss = 0.0, rate_miss = 0.0, diff_miss = 0.0, rate_scale = 0.0, swing = 0.0;
  for (std::size_t r = 0; r < t.rows.size(); ++r) {
    const Mat3 R = rotation_of(t, r, "bob");
    // The rotation about y since the start: R = Ry(theta0 + angle).
    const double from_orientation = std::atan2(-R(2, 0), R(0, 0)) - theta0;
    angle_miss = std::max(angle_miss, std::abs(t.at(r, "hinge.angle") - from_orientation));
    rate_miss = std::max(rate_miss, std::abs(t.at(r, "hinge.angle_rate") - t.at(r, "bob.wy")));
    rate_scale = std::max(rate_scale, std::abs(t.at(r, "bob.wy")));
    swing = std::max(swing, std::abs(t.at(r, "hinge.angle")));
    if (r > 0 && r + 1 < t.rows.size()) {
      const double dt = t.at(r + 1, "t") - t.at(r - 1, "t");
      const double central = (t.at(r + 1, "hinge.angle") - t.at(r - 1, "hinge.angle")) / dt;
      diff_miss = std::max(diff_miss, std::abs(central - t.at(r, "hinge.angle_rate")));
    }
  }
  CHECK(swing > 1.0);  // it swings through the bottom (2 theta0 ~ 2.1 rad peak to peak)
  CHECK(angle_miss < 1e-12);
  CHECK(rate_miss < 1e-12 * rate_scale);
  // Central difference error h^2/6 theta''' with h = 1 ms, |theta'''| < 200 rad/s^3 here.
  CHECK(diff_miss < 1e-4 * rate_scale);
  CHECK(std::abs(t.at(0, "hinge.angle")) < 1e-12);
  CHECK(t.col("hinge.residual_position") >= 0);
  CHECK(t.col("hinge.residual_velocity") >= 0);
  fs::remove_all(dir);
}

TEST_CASE("joint coordinates: a spinning crank's unwrapped angle is omega t, past 2 pi, in both files") {
  Scene s = test::multibody_base(Coordinates::Quaternion, Equations::Euler, "ggl");
  const double omega = 4 * std::numbers::pi;  // two turns a second, for 2 s
  s.time = {0.0, 2.0, 0.01};
  s.solver.rtol = s.solver.atol = 1e-10;
  MultibodySpec& m = *s.multibody;
  m.gravity_W.setZero();
  BodySpec crank;
  crank.name = "crank";
  crank.mass = 0.3;
  crank.inertia_com = Vec3(1e-4, 2e-4, 2.5e-4).asDiagonal();
  crank.omega0_B = Vec3(0, 0, omega);
  m.bodies.push_back(crank);
  m.joints.push_back(test::joint_at(m, &joint_type("revolute"), kGround, 0, Vec3::Zero(), Vec3::UnitZ(),
                                    Vec3::UnitX(), "bearing"));
  const fs::path dir = test::fresh_temp_dir("joint_coordinates_crank");
  const SolveOutcome o = solve_scene(s, dir);
  REQUIRE(o.run.status == RunStatus::Success);
  for (const char* file : {"trajectory.csv", "steps.csv"}) {
    CAPTURE(file);
    const Table t = read_table(dir / file);
    REQUIRE(t.rows.size() > 50);
    double miss = 0.0, rate_miss = 0.0;
    bool monotone = true;
    for (std::size_t r = 0; r < t.rows.size(); ++r) {
      miss = std::max(miss, std::abs(t.at(r, "bearing.angle") - omega * t.at(r, "t")));
      rate_miss = std::max(rate_miss, std::abs(t.at(r, "bearing.angle_rate") - omega));
      if (r > 0 && !(t.at(r, "bearing.angle") > t.at(r - 1, "bearing.angle"))) monotone = false;
    }
    CHECK(monotone);
    CHECK(t.rows.back()[static_cast<std::size_t>(t.col("bearing.angle"))] == doctest::Approx(4 * 2 * std::numbers::pi));
    CHECK(miss < 1e-7);
    CHECK(rate_miss < 1e-7);
  }
  fs::remove_all(dir);
}

TEST_CASE("joint coordinates: the slider-crank's crank angle and the guide's displacement against the bodies' columns") {
  Scene s = io::load_scene(std::string(RIGIDAE_SOURCE_DIR) + "/problems/slider_mechanism.toml");
  const fs::path dir = test::fresh_temp_dir("joint_coordinates_slider");
  const SolveOutcome o = solve_scene(s, dir);
  REQUIRE(o.run.status == RunStatus::Success);
  const Table t = read_table(dir / "trajectory.csv");
  REQUIRE(t.rows.size() > 100);
  // The crank's rotation about z from its orientation, unwrapped here row to
  // row (the crank starts at R = I).
  double unwrapped = 0.0, previous = 0.0, angle_miss = 0.0, displacement_miss = 0.0, travel = 0.0;
  const double x0 = 0.3349509756796393;
  for (std::size_t r = 0; r < t.rows.size(); ++r) {
    const Mat3 R = rotation_of(t, r, "crank");
    const double raw = std::atan2(R(1, 0), R(0, 0));
    unwrapped = r == 0 ? raw : unwrapped + std::remainder(raw - previous, 2 * std::numbers::pi);
    previous = raw;
    angle_miss = std::max(angle_miss, std::abs(t.at(r, "crank_bearing.angle") - unwrapped));
    const double dx = t.at(r, "slider.x") - x0;
    displacement_miss = std::max(displacement_miss, std::abs(t.at(r, "guide.displacement") - dx));
    travel = std::max(travel, std::abs(dx));
  }
  // The crank turns about 0.58 rad and the slider travels about 27 mm in 5 s:
  // enough for a miss in either definition to show.
  CHECK(std::abs(unwrapped) > 0.3);
  CHECK(travel > 0.01);
  CHECK(angle_miss < 1e-9);
  CHECK(displacement_miss < 1e-9);
  fs::remove_all(dir);
}

TEST_SUITE_END();
