// Time-dependent loads ([[loads]] profile) and the energy check's work:
//   - a free body (no gravity) pushed by a space force and twisted by a
//     torque about a principal axis, both scaled by s(t) = 1 + 2 t - t^2/2:
//     x(t) = x0 + (F/m)(t^2/2 + t^3/3 - t^4/24) and the angle about z
//     (tau/I)(the same), in closed form; the energy check (with the loads'
//     work) applies and passes;
//   - the driven crank-slider's energy check: the recorded states of a tight
//     run pass it, and the same states with the slider's velocity off by 1e-6
//     (a real error) fail it;
//   - bad [[drivers]] and profile tables are positioned errors naming what is valid.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "rigidae/core/error.hpp"
#include "rigidae/app/multibody_accuracy_check.hpp"
#include "rigidae/app/solve.hpp"
#include "rigidae/io/scene_loader.hpp"
#include "rigidae/multibody/multibody_problem.hpp"
#include "rigidae/solver/ida_driver.hpp"
#include "rigidae/so3/rotation.hpp"
#include "test_multibody_scenes.hpp"

TEST_SUITE_BEGIN("system");

using namespace rigidae;
namespace fs = std::filesystem;

namespace {

std::string error_of(const std::string& text) {
  try {
    (void)io::parse_scene(text, "mb.toml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// trajectory.csv as rows of numbers under the header (its first line is the units).
std::vector<std::map<std::string, double>> read_trajectory(const fs::path& csv) {
  std::ifstream in(csv);
  REQUIRE(in);
  const auto split = [](const std::string& line) {
    std::vector<std::string> out;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) out.push_back(cell);
    return out;
  };
  std::string line;
  std::getline(in, line);
  std::getline(in, line);
  const std::vector<std::string> names = split(line);
  std::vector<std::map<std::string, double>> rows;
  while (std::getline(in, line)) {
    const std::vector<std::string> cells = split(line);
    std::map<std::string, double> row;
    for (std::size_t k = 0; k < names.size() && k < cells.size(); ++k) row[names[k]] = std::strtod(cells[k].c_str(), nullptr);
    rows.push_back(row);
  }
  return rows;
}

// Keeps the start and every accepted step's state.
struct StateLog final : StepSink {
  std::vector<double> t;
  std::vector<Eigen::VectorXd> y;
  void on_step(double ts, double, int, const Eigen::VectorXd& ys) override {
    t.push_back(ts);
    y.push_back(ys);
  }
  void on_output(double ts, const Eigen::VectorXd& ys) override {
    if (t.empty()) {
      t.push_back(ts);
      y.push_back(ys);
    }
  }
};

}  // namespace

TEST_CASE("time-dependent loads: a force and a torque with a polynomial profile against the closed form") {
  Scene s = test::multibody_base(Coordinates::Quaternion, Equations::Euler, "ggl");
  s.time = {0.0, 1.0, 0.01};
  s.solver.rtol = s.solver.atol = 1e-10;
  MultibodySpec& m = *s.multibody;
  m.gravity_W = Vec3::Zero();
  BodySpec b;
  b.name = "block";
  b.mass = 2.0;
  b.inertia_com = Vec3(0.1, 0.2, 0.25).asDiagonal();
  m.bodies.push_back(b);
  BodyLoadSpec l;
  l.body = 0;
  l.force = Vec3(3.0, 0.0, 0.0);
  l.torque = Vec3(0.0, 0.0, 0.5);
  l.profile = polynomial_function({1.0, 2.0, -0.5});
  m.loads.push_back(l);
  const fs::path dir = test::fresh_temp_dir("time_loads_polynomial");
  const SolveOutcome o = solve_scene(s, dir);
  REQUIRE(o.run.status == RunStatus::Success);
  const auto rows = read_trajectory(dir / "trajectory.csv");
  REQUIRE(rows.size() == 101);
  double x_miss = 0.0, angle_miss = 0.0;
  for (const auto& r : rows) {
    const double t = r.at("t");
    const double shape = t * t / 2 + t * t * t / 3 - t * t * t * t / 24;  // double integral of s
    x_miss = std::max(x_miss, std::abs(r.at("block.x") - 1.5 * shape));
    const Vec4 q(r.at("block.qw"), r.at("block.qx"), r.at("block.qy"), r.at("block.qz"));
    const Mat3 R = so3::quaternion_to_matrix(q.normalized());
    angle_miss = std::max(angle_miss, std::abs(std::atan2(R(1, 0), R(0, 0)) - 2.0 * shape));
  }
  MESSAGE("x " << x_miss << " m, angle " << angle_miss << " rad");
  CHECK(x_miss < 1e-8);
  CHECK(angle_miss < 1e-8);
  // The loads have no potential; their work is counted and the check applies
  // and passes (no warning: within 2 tau sqrt(N)).
  REQUIRE(o.drifts.energy == o.drifts.energy);
  MESSAGE("energy " << o.drifts.energy << ", tolerance " << o.drifts.tolerance);
  for (const AccuracyWarning& w : o.warnings) CHECK(w.quantity != "energy");
}

// The energy balance H - H0 - W counts each load's work once: a constant
// space force's work is its potential's change (-F . x is part of H), so W
// holds only what H does not (the torque's power; a profiled force's power
// at the centre of mass, which on a pivoted body moves as W_c v). Before the
// fix the constant force with a torque was counted twice (|H - H0 - W| = 9 J
// on a 0.18 J motion) and the pivoted body's profiled force read its
// rotation velocities as a translation.
TEST_CASE("energy balance: a load's work is counted once, on a free and on a pivoted body") {
  for (const bool pivoted : {false, true}) {
    CAPTURE(pivoted);
    Scene s = test::multibody_base(Coordinates::Quaternion, Equations::Euler, "ggl");
    s.time = {0.0, 2.0, 0.02};
    s.solver.rtol = s.solver.atol = 1e-10;
    MultibodySpec& m = *s.multibody;
    m.gravity_W = pivoted ? Vec3(0.0, 0.0, -9.81) : Vec3::Zero();
    BodySpec b;
    b.name = "block";
    b.mass = 2.0;
    b.inertia_com = Vec3(0.1, 0.2, 0.3).asDiagonal();
    b.omega0_B = Vec3(0.1, 0.5, 1.0);
    if (pivoted) {
      b.x0_W = Vec3(0.3, 0.0, 0.1);
      b.pivot_W = Vec3::Zero();
    }
    m.bodies.push_back(b);
    BodyLoadSpec l;
    l.body = 0;
    l.force = Vec3(3.0, 0.0, 1.0);
    l.torque = Vec3(0.0, 0.0, 0.2);
    if (pivoted) l.profile = polynomial_function({1.0, -0.5});
    m.loads.push_back(l);
    const fs::path dir = test::fresh_temp_dir(pivoted ? "energy_load_pivoted" : "energy_load_free");
    const SolveOutcome o = solve_scene(s, dir);
    REQUIRE(o.run.status == RunStatus::Success);
    REQUIRE(o.drifts.energy == o.drifts.energy);
    MESSAGE("energy " << o.drifts.energy << ", tolerance " << o.drifts.tolerance);
    CHECK(o.drifts.energy < 10.0 * o.drifts.tolerance);
    for (const AccuracyWarning& w : o.warnings) CHECK(w.quantity != "energy");
  }
}

TEST_CASE("energy check with drivers: passes on a tight run, catches a state that is off") {
  const Scene s = io::load_scene(std::string(RIGIDAE_SOURCE_DIR) + "/problems/crank_slider_driven.toml");
  multibody::MultibodyProblem p(s);
  StateLog log;
  const RunResult r = integrate(p, s.solver, s.time, log);
  REQUIRE(r.status == RunStatus::Success);
  REQUIRE(log.y.size() > 20);
  const auto check = [&](double slider_error) {
    MultibodyInvariantMonitor monitor(p, s, nullptr);
    const int slider_v = p.groups()[p.bodies()[2].v_group].offset;
    for (std::size_t k = 0; k < log.y.size(); ++k) {
      Eigen::VectorXd y = log.y[k];
      if (log.t[k] > 0.5) y(slider_v) *= 1.0 + slider_error;
      if (k == 0)
        monitor.on_output(log.t[k], y);
      else
        monitor.on_step(log.t[k], log.t[k] - log.t[k - 1], 5, y);
    }
    int energy_warnings = 0;
    for (const AccuracyWarning& w : monitor.warnings()) energy_warnings += w.quantity == "energy";
    return std::pair{monitor.drifts(), energy_warnings};
  };
  const auto [good, good_warnings] = check(0.0);
  MESSAGE("energy " << good.energy << " against the tolerance " << good.tolerance);
  CHECK(good.energy < 10.0 * good.tolerance);
  CHECK(good_warnings == 0);
  const auto [bad, bad_warnings] = check(1e-6);
  MESSAGE("with the slider's velocity off by 1e-6: energy " << bad.energy);
  CHECK(bad.energy > 100.0 * bad.tolerance);
  CHECK(bad_warnings == 1);
}

TEST_CASE("drivers and profiles: bad tables are positioned errors naming what is valid") {
  const std::string head =
      "schema_version = 2\n"                                   // 1
      "[[bodies]]\n"                                           // 2
      "name = \"arm\"\n"                                       // 3
      "mass = 1.0\n"                                           // 4
      "inertia_principal = [0.1, 0.2, 0.25]\n"                 // 5
      "position = [1.0, 0.0, 0.0]\n"                           // 6
      "[[bodies]]\n"                                           // 7
      "name = \"hand\"\n"                                      // 8
      "mass = 1.0\n"                                           // 9
      "inertia_principal = [0.1, 0.2, 0.25]\n"                 // 10
      "position = [3.0, 0.0, 0.0]\n"                           // 11
      "[[joints]]\n"                                           // 12
      "name = \"hinge\"\n"                                     // 13
      "type = \"revolute\"\n"                                  // 14
      "bodies = [\"ground\", \"arm\"]\n"                       // 15
      "point = [0.0, 0.0, 0.0]\n"                              // 16
      "axis = [0.0, 0.0, 1.0]\n"                               // 17
      "[[joints]]\n"                                           // 18
      "name = \"ball\"\n"                                      // 19
      "type = \"spherical\"\n"                                 // 20
      "bodies = [\"arm\", \"hand\"]\n"                         // 21
      "point = [2.0, 0.0, 0.0]\n"                              // 22
      "[time]\nend = 1.0\n"                                    // 23, 24
      "[[drivers]]\n";                                         // 25
  const auto expect = [&](const std::string& tail, int line, std::vector<std::string> hints) {
    const std::string msg = error_of(head + tail);
    INFO("message: " << msg);
    CHECK(msg.rfind("mb.toml:" + std::to_string(line) + ":", 0) == 0);
    for (const std::string& h : hints) CHECK(msg.find(h) != std::string::npos);
  };
  expect("joint = \"hing\"\nmotion = { type = \"rate\", rate = 1.0 }\n", 26, {"did you mean \"hinge\"", "joints with coordinates"});
  expect("joint = \"ball\"\nmotion = { type = \"rate\", rate = 1.0 }\n", 26, {"spherical", "no coordinate to drive"});
  expect("joint = \"hinge\"\ncoordinate = \"angel\"\nmotion = { type = \"rate\", rate = 1.0 }\n", 27, {"\"angle\""});
  expect("joint = \"hinge\"\n", 25, {"missing required key 'motion'"});
  expect("joint = \"hinge\"\nmotion = { type = \"ramp\", rate = 1.0 }\n", 27, {"'rate'", "'polynomial'", "'harmonic'", "'table'"});
  expect("joint = \"hinge\"\nmotion = { type = \"rate\", speed = 1.0 }\n", 27, {"unknown key 'speed'", "'rate'"});
  expect("joint = \"hinge\"\nmotion = { type = \"harmonic\", amplitude = 1.0 }\n", 27, {"needs 'omega'"});
  expect("joint = \"hinge\"\nmotion = { type = \"table\", times = [0.0, 1.0, 1.0], values = [0, 1, 2] }\n", 27,
         {"drivers[0].motion.times[2]", "increase strictly"});
  expect("joint = \"hinge\"\nmotion = { type = \"table\", times = [0.0, 1.0], values = [0, 1, 2] }\n", 27,
         {"one value per time"});
  expect("joint = \"hinge\"\nmotion = { type = \"table\", times = [0.0, 1.0], values = [0, 1], interpolation = \"linear\" }\n",
         27, {"\"spline\""});
  expect("joint = \"hinge\"\nmotion = { type = \"rate\", rate = 1.0 }\n[[drivers]]\njoint = \"hinge\"\nmotion = { type = "
         "\"rate\", rate = 2.0 }\n",
         29, {"driven twice"});
  // A driver that misses the initial pose is an error naming it and f(t0).
  const std::string far = head + "joint = \"hinge\"\nmotion = { type = \"rate\", value = 0.5, rate = 1.0 }\n";
  std::string msg;
  try {
    const Scene sc = io::parse_scene(far, "mb.toml");
    multibody::MultibodyProblem p(sc);
  } catch (const InputError& e) {
    msg = e.what();
  }
  INFO("message: " << msg);
  CHECK(msg.rfind("mb.toml:25:", 0) == 0);
  CHECK(msg.find("prescribes 0.5") != std::string::npos);
}

TEST_SUITE_END();
