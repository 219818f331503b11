// The driven crank-slider (problems/crank_slider_driven.toml) against its
// closed form (the scene's header): crank and rod angles about z, the
// centres of mass and the slider's position, and the driving torque from the
// power balance tau omega = dT/dt + dV/dt, over the output grid, at rtol =
// atol = 1e-10, in every Euler-form combination (index3 runs and is flagged
// by the energy check; its accuracy is not asserted), and in the ODE form
// (CVODE BDF, index1). The mobility is 0.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "cli_runner.hpp"
#include "rigidae/core/error.hpp"
#include "rigidae/app/solve.hpp"
#include "rigidae/coords/representation.hpp"
#include "rigidae/io/scene_loader.hpp"
#include "rigidae/multibody/multibody_problem.hpp"
#include "rigidae/schemes/scheme.hpp"
#include "rigidae/so3/rotation.hpp"

TEST_SUITE_BEGIN("system");

using namespace rigidae;
namespace fs = std::filesystem;

namespace {

struct Table {
  std::vector<std::string> names;
  std::vector<std::vector<double>> rows;
  double at(std::size_t row, const std::string& name) const {
    for (std::size_t k = 0; k < names.size(); ++k)
      if (names[k] == name) return rows[row][k];
    FAIL("no column " << name);
    return 0.0;
  }
};

Table read_trajectory(const fs::path& csv) {
  std::ifstream in(csv);
  REQUIRE(in);
  const auto split = [](const std::string& line) {
    std::vector<std::string> out;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) out.push_back(cell);
    return out;
  };
  Table t;
  std::string line;
  std::getline(in, line);  // units
  std::getline(in, line);
  t.names = split(line);
  while (std::getline(in, line)) {
    std::vector<double> row;
    for (const std::string& c : split(line)) row.push_back(std::strtod(c.c_str(), nullptr));
    t.rows.push_back(row);
  }
  return t;
}

// The closed form at time t (header of the scene).
struct Reference {
  double theta, phi, crank_x, crank_y, rod_x, rod_y, slider_x, torque;
};

Reference closed_form(const MultibodySpec& m, double t) {
  const double r = 0.1, l = 0.35, w = 2.0 * std::numbers::pi, g = 9.81;
  const double m1 = m.bodies[0].mass, m2 = m.bodies[1].mass, m3 = m.bodies[2].mass;
  const double I2 = m.bodies[1].inertia_com(2, 2);
  Reference ref;
  const double th = 0.3 + w * t, st = std::sin(th), ct = std::cos(th);
  const double sp = -(r / l) * st, cp = std::sqrt(1.0 - sp * sp);
  ref.theta = th;
  ref.phi = std::atan2(sp, cp);
  ref.crank_x = 0.5 * r * ct;
  ref.crank_y = 0.5 * r * st;
  ref.rod_x = r * ct + 0.5 * l * cp;
  ref.rod_y = r * st + 0.5 * l * sp;
  ref.slider_x = r * ct + l * cp;
  const double pd = -(r / l) * ct * w / cp;
  const double pdd = ((r / l) * st * w * w + sp * pd * pd) / cp;
  const double v1x = -0.5 * r * w * st, v1y = 0.5 * r * w * ct;
  const double a1x = -0.5 * r * w * w * ct, a1y = -0.5 * r * w * w * st;
  const double v2x = -r * w * st - 0.5 * l * pd * sp, v2y = r * w * ct + 0.5 * l * pd * cp;
  const double a2x = -r * w * w * ct + 0.5 * l * (-pdd * sp - pd * pd * cp);
  const double a2y = -r * w * w * st + 0.5 * l * (pdd * cp - pd * pd * sp);
  const double xd = -r * st * w - l * sp * pd;
  const double xdd = -r * ct * w * w - l * (cp * pd * pd + sp * pdd);
  const double power = m1 * (v1x * a1x + v1y * a1y) + m2 * (v2x * a2x + v2y * a2y) + I2 * pd * pdd +
                       m3 * xd * xdd + g * (m1 * v1y + m2 * v2y);
  ref.torque = power / w;
  return ref;
}

double angle_about_z(const Table& t, std::size_t row, const std::string& body) {
  const Vec4 q(t.at(row, body + ".qw"), t.at(row, body + ".qx"), t.at(row, body + ".qy"), t.at(row, body + ".qz"));
  const Mat3 R = so3::quaternion_to_matrix(q.normalized());
  return std::atan2(R(1, 0), R(0, 0));
}

struct Errors {
  double angle = 0.0, position = 0.0, torque = 0.0;
};

Errors compare(const Scene& s, const fs::path& dir) {
  const Table t = read_trajectory(dir / "trajectory.csv");
  REQUIRE(t.rows.size() == 101);
  Errors e;
  double torque_scale = 0.0;
  for (std::size_t k = 0; k < t.rows.size(); ++k)
    torque_scale = std::max(torque_scale, std::abs(closed_form(*s.multibody, t.at(k, "t")).torque));
  for (std::size_t k = 0; k < t.rows.size(); ++k) {
    const Reference ref = closed_form(*s.multibody, t.at(k, "t"));
    const auto angle_miss = [](double a, double b) { return std::abs(std::remainder(a - b, 2.0 * std::numbers::pi)); };
    e.angle = std::max({e.angle, angle_miss(angle_about_z(t, k, "crank"), ref.theta),
                        angle_miss(angle_about_z(t, k, "rod"), ref.phi),
                        angle_miss(t.at(k, "crank_bearing.angle"), ref.theta - 0.3)});
    e.position = std::max({e.position, std::abs(t.at(k, "crank.x") - ref.crank_x),
                           std::abs(t.at(k, "crank.y") - ref.crank_y), std::abs(t.at(k, "rod.x") - ref.rod_x),
                           std::abs(t.at(k, "rod.y") - ref.rod_y), std::abs(t.at(k, "slider.x") - ref.slider_x),
                           std::abs(t.at(k, "slider.y")), std::abs(t.at(k, "rod.z"))});
    e.torque = std::max(e.torque, std::abs(t.at(k, "crank_bearing.drive_torque") - ref.torque) / torque_scale);
  }
  return e;
}

Scene driven_scene() { return io::load_scene(std::string(RIGIDAE_SOURCE_DIR) + "/problems/crank_slider_driven.toml"); }

}  // namespace

TEST_CASE("crank-slider driven: the mobility is 0 and the start is the closed form's") {
  const Scene s = driven_scene();
  multibody::MultibodyProblem p(s);
  CHECK(p.redundancy().rank_dof == 0);
  CHECK(p.redundancy().gruebler_dof == 18 - 20 - 1);
  CHECK(p.redundancy().dropped.size() == 3);
  CHECK(p.warnings().size() == 1);  // the redundant rows only: no projected miss or velocity
}

TEST_CASE("crank-slider driven: a driver half a turn off the pose is refused, whole turns are the same pose") {
  // The row r sin(theta - f) vanishes at theta - f = pi too, where the
  // driving torque would come out with the wrong sign: the start compares
  // the angle, theta - f wrapped to [-pi, pi].
  const std::string text = rigidae::test::read_file(std::string(RIGIDAE_SOURCE_DIR) +
                                                    "/problems/crank_slider_driven.toml");
  const std::string key = "value = 0.0, rate";
  const std::size_t at = text.find(key);
  REQUIRE(at != std::string::npos);
  const auto with_value = [&](double v) {
    std::string t = text;
    t.replace(at, key.size(), fmt::format("value = {:.17g}, rate", v));
    return t;
  };
  for (double v : {std::numbers::pi, 0.5, -3.0}) {
    CAPTURE(v);
    try {
      multibody::MultibodyProblem p(io::parse_scene(with_value(v), "cs.toml"));
      FAIL("started half a turn off the prescribed angle");
    } catch (const InputError& e) {
      const std::string msg = e.what();
      CAPTURE(msg);
      CHECK(msg.find("cs.toml:") == 0);
      CHECK(msg.find("driver of joint 'crank_bearing'") != std::string::npos);
      // The miss is the angle itself (3.14, 0.5, 3.0 rad), not r sin of it.
      const double miss = std::abs(std::remainder(v, 2.0 * std::numbers::pi));
      CHECK(msg.find(fmt::format("miss the prescribed motion by {:.3g} rad", miss)) != std::string::npos);
      CHECK(msg.find("the joint reads 0 rad") != std::string::npos);
    }
  }
  // f(t0) = 2 pi: the same pose, run, with a warning that the angle columns count from the pose.
  multibody::MultibodyProblem p(io::parse_scene(with_value(2.0 * std::numbers::pi), "cs.toml"));
  REQUIRE(p.warnings().size() == 2);
  CHECK(p.warnings()[1].find("1 whole turn from the pose's angle 0 rad") != std::string::npos);
}

TEST_CASE("crank-slider driven: quaternion/euler/index1 against the closed form") {
  const Scene s = driven_scene();
  const fs::path dir = test::fresh_temp_dir("crank_slider_driven_default");
  const SolveOutcome o = solve_scene(s, dir);
  REQUIRE(o.run.status == RunStatus::Success);
  const Errors e = compare(s, dir);
  MESSAGE("angle " << e.angle << " rad, position " << e.position << " m, torque " << e.torque << " relative");
  CHECK(e.angle <= 1e-6);
  CHECK(e.position <= 1e-6);
  CHECK(e.torque <= 1e-6);
  // The energy check counts the driver's work: it applies (not NaN) and
  // passes (no warning: within 2 tau sqrt(N) of the accepted steps).
  REQUIRE(o.drifts.energy == o.drifts.energy);
  MESSAGE("energy " << o.drifts.energy << ", tolerance " << o.drifts.tolerance);
  CHECK(o.drifts.energy < 10.0 * o.drifts.tolerance);
  for (const AccuracyWarning& w : o.warnings) CHECK(w.quantity != "energy");
  // The step file's energy_rel_error, (H - H0 - W) / max(|H0|, 1 J), and the
  // summary's maximum of it count the work too (without W: about 0.7 here).
  MESSAGE("max |energy_rel_error| " << o.extremes.max_abs_energy_error);
  CHECK(o.extremes.max_abs_energy_error < 1e-8);
}

TEST_CASE("crank-slider driven: GGL starts on the driver's motion (mu = 0) and runs at rtol 1e-12") {
  // GGL's q' = N v - Phi_q^T mu: the start's mu solved Phi_q q' = 0, which
  // held the driven crank still (mu = (P P^T)^-1 G v, with G v = -Phi_t != 0)
  // and IDA's error test failed at t0 for rtol <= 1e-11. Phi_q q' = -Phi_t
  // gives mu = 0 and q' = N v: the first step follows the driver.
  for (const char* tol : {"1e-11", "1e-12"}) {
    Scene s = driven_scene();
    s.formulation.scheme = "ggl";
    s.solver.rtol = s.solver.atol = std::stod(tol);
    CAPTURE(tol);
    const fs::path dir = test::fresh_temp_dir("crank_slider_driven_ggl");
    const SolveOutcome o = solve_scene(s, dir);
    REQUIRE_MESSAGE(o.run.status == RunStatus::Success, o.run.message);
    const Errors e = compare(s, dir);
    MESSAGE("ggl at " << std::string(tol) << ": angle " << e.angle << " rad, position " << e.position << " m, torque "
                      << e.torque);
    CHECK(e.angle <= 1e-8);
    CHECK(e.position <= 1e-8);
    CHECK(e.torque <= 1e-6);
  }
  // The start itself: every mu of the consistent start is 0 (to round-off)
  // and q' = N v, the residual zero.
  Scene s = driven_scene();
  s.formulation.scheme = "ggl";
  multibody::MultibodyProblem p(s);
  Eigen::VectorXd y, yp;
  p.initial_state(s.time.start, y, yp);
  Eigen::VectorXd F(p.size());
  p.residual(s.time.start, y.data(), yp.data(), F.data());
  CHECK(F.cwiseAbs().maxCoeff() < 1e-12);
  double largest_mu = 0.0;
  int driver_blocks = 0;
  for (const multibody::ConstraintBlock& b : p.blocks()) {
    if (b.mu_group < 0) continue;
    const multibody::UnknownGroup& g = p.groups()[static_cast<std::size_t>(b.mu_group)];
    largest_mu = std::max(largest_mu, y.segment(g.offset, g.size).cwiseAbs().maxCoeff());
    driver_blocks += b.driver >= 0;
  }
  CHECK(driver_blocks == 1);
  MESSAGE("largest |mu| at the start " << largest_mu);
  CHECK(largest_mu < 1e-12);
}

TEST_CASE("crank-slider driven: on ARKODE the driver's work is integrated with the state (no false energy alarm)") {
  // H - H0 - W with W = integral of tau theta': a quadrature of the power
  // over ARKODE's 31 order-8 steps (degree 5 through the steps) left 2.2e-4
  // of the energy and a warning on a run 1e-13 from the closed form; W as a
  // state (W' = P at the stages, outside the error test) leaves round-off.
  for (const char* integrator : {"arkode-erk", "cvode-bdf"}) {
    Scene s = driven_scene();
    s.solver.integrator = integrator;
    s.solver.integrator_named = true;
    s.formulation.scheme = "projection";
    CAPTURE(std::string(integrator));
    const fs::path dir = test::fresh_temp_dir("crank_slider_driven_work");
    const SolveOutcome o = solve_scene(s, dir);
    REQUIRE_MESSAGE(o.run.status == RunStatus::Success, o.run.message);
    const Errors e = compare(s, dir);
    MESSAGE(std::string(integrator) << ": angle " << e.angle << " rad, torque " << e.torque
                                    << ", max |energy_rel_error| "
                       << o.extremes.max_abs_energy_error << ", energy drift " << o.drifts.energy << " (tolerance "
                       << o.drifts.tolerance << ")");
    CHECK(e.angle <= 1e-6);
    CHECK(o.extremes.max_abs_energy_error < 1e-6);
    // ARKODE's run is 2e-13 rad from the closed form: its balance is within
    // the tolerance itself (measured 1.2e-13 of 3.3e-10); CVODE's 4e-9 rad
    // shows as 3.8e-9, inside the warning's allowance for its steps.
    if (std::string(integrator) == "arkode-erk") CHECK(o.drifts.energy < o.drifts.tolerance);
    for (const AccuracyWarning& w : o.warnings) CHECK(w.quantity != "energy");
  }
}

TEST_CASE("crank-slider driven: every Euler-form combination and the ODE form") {
  const Scene base = driven_scene();
  for (const Coordinates& c : all_coordinates())
    for (const std::string& scheme : scheme_names()) {
      const std::string coords = c.name();
      Scene s = base;
      s.formulation.coordinates = c;
      s.formulation.equations = Equations::Euler;
      s.formulation.scheme = scheme;
      CAPTURE(coords + "/euler/" + scheme);
      const fs::path dir = test::fresh_temp_dir("crank_slider_driven_" + coords + "_" + scheme);
      const SolveOutcome o = solve_scene(s, dir);
      CHECK_MESSAGE(o.run.status == RunStatus::Success, o.run.message);
      if (o.run.status != RunStatus::Success) continue;
      if (scheme == "index3") {
        // It runs, and warns: its velocities are not error-controlled, and
        // the energy balance (with the driver's work) catches the error.
        bool energy_warning = false;
        for (const AccuracyWarning& w : o.warnings)
          if (w.quantity == "energy") {
            energy_warning = true;
            // The balance's W is the driver's effort, a multiplier: the message says so.
            CHECK(w.message.find("multipliers that IDA's error test leaves out") != std::string::npos);
          }
        CHECK(energy_warning);
        continue;
      }
      const Errors e = compare(s, dir);
      MESSAGE(coords << "/euler/" << scheme << ": angle " << e.angle << " rad, position " << e.position
                     << " m, torque " << e.torque);
      CHECK(e.angle <= 1e-6);
      CHECK(e.position <= 1e-6);
      // Linear coordinates (the nine entries of R) with the acceleration-level
      // schemes reach 2.05e-6 at rtol 1e-10: isolated points where the
      // multiplier, which IDA leaves out of its error test, is off (at rtol
      // 1e-11 one grid point is 9.7e-6 off, its neighbours 1e-10; the
      // accepted steps' values too: 1.2e-6 and 4.8e-6; open). Euler angles
      // with ggl likewise: 2.2e-6 at t = 0.47 s (its multipliers are outside
      // IDA's error test; angle 2.5e-12 rad), since GGL's start follows the
      // driver (mu = 0, a first step of 6e-6 s instead of 3e-10 s: another
      // step sequence). Their measured bound is asserted, every other
      // combination's is 1e-6.
      const bool isolated_multiplier_misses = (coords == "linear" && (scheme == "index1" || scheme == "projection")) ||
                                              (coords == "euler" && scheme == "ggl");
      CHECK(e.torque <= (isolated_multiplier_misses ? 3e-6 : 1e-6));
    }
  Scene s = base;
  s.solver.integrator = "cvode-bdf";
  const fs::path dir = test::fresh_temp_dir("crank_slider_driven_cvode");
  const SolveOutcome o = solve_scene(s, dir);
  REQUIRE_MESSAGE(o.run.status == RunStatus::Success, o.run.message);
  const Errors e = compare(s, dir);
  MESSAGE("cvode-bdf/index1: angle " << e.angle << " rad, position " << e.position << " m, torque " << e.torque);
  CHECK(e.angle <= 1e-6);
  CHECK(e.position <= 1e-6);
  CHECK(e.torque <= 1e-6);
}

// The multipliers of the Lagrange forms, which IDA's error test leaves out:
// until its Newton iteration checked their first corrections
// (src/solver/ida_newton_test.hpp), quaternion/lagrange/index1 reported a
// driving torque of up to 2.2e12 N m here (the closed form: 0.925 N m at
// most) while the motion stayed within 2e-8 of a tight run, and linear
// coordinates, baumgarte and projection did the same. Every accepted step
// (steps.csv) and every grid row, against the closed form.
TEST_CASE("crank-slider driven: the Lagrange forms' driving torque at every step, against the closed form") {
  const Scene base = driven_scene();
  double worst = 0.0;
  for (const Coordinates c : {Coordinates::Quaternion, Coordinates::Linear})
    for (const std::string scheme : {"index1", "baumgarte", "projection"}) {
      Scene s = base;
      s.formulation.coordinates = c;
      s.formulation.equations = Equations::Lagrange;
      s.formulation.scheme = scheme;
      const std::string name = s.formulation.coordinates.name() + "/lagrange/" + scheme;
      CAPTURE(name);
      const fs::path dir = test::fresh_temp_dir("crank_slider_lagrange_" + scheme);
      const SolveOutcome o = solve_scene(s, dir);
      REQUIRE_MESSAGE(o.run.status == RunStatus::Success, o.run.message);
      const Table steps = read_trajectory(dir / "steps.csv");
      REQUIRE(steps.rows.size() > 100);
      double on_steps = 0.0;
      for (std::size_t k = 0; k < steps.rows.size(); ++k)
        on_steps = std::max(on_steps, std::abs(steps.at(k, "crank_bearing.drive_torque") -
                                               closed_form(*s.multibody, steps.at(k, "t")).torque));
      const Errors e = compare(s, dir);
      MESSAGE(name << ": torque off by " << on_steps << " N m on the steps, " << e.torque
                   << " of the largest on the grid; angle " << e.angle << " rad");
      worst = std::max(worst, on_steps);
      CHECK(on_steps < 1e-4);  // measured 1.1e-5 to 4.3e-5 N m (of 0.925)
      CHECK(e.torque < 1e-4);
      CHECK(e.angle < 1e-6);
    }
  MESSAGE("largest driving-torque error over the steps: " << worst << " N m");
}

TEST_SUITE_END();
