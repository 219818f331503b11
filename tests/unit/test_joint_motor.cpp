// Motors in joints: a revolute joint's torque (keys motor_torque,
// motor_profile) tau(t) = tau_m s(t) on b about the axis and -tau(t) on a; a
// prismatic joint's force (motor_force, motor_profile) F(t) = F_m s(t) on b
// along the axis and -F(t) on a.
//
// Truth: two free bodies in space (no gravity), their centres of mass on the
// hinge's axis z and z a principal axis of both, at rest, driven against
// each other by tau(t) with s(t) = 1 + 2 t - t^2/2. Each turns about z
// alone (the hinge's rows hold without a reaction), so
//   I_a theta_a'' = -tau,  I_b theta_b'' = tau,
//   theta(t) = theta_b - theta_a = tau_m (1/I_a + 1/I_b) (t^2/2 + t^3/3 - t^4/24)
// (the double integral of s), the joint's recorded angle (10.97 rad at the
// end: turns counted even where one step turns the joint by more than pi);
// the total angular momentum stays zero (action and reaction) and the energy
// balance, with the motor's work integrated, holds. Every representation in
// both forms. The linear motor likewise: the same bodies on a prismatic
// joint along z, pushed apart by F(t),
//   d(t) = F_m (1/m_a + 1/m_b) (t^2/2 + t^3/3 - t^4/24),
// the joint's recorded displacement, with the total linear momentum zero.
#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include "cli_runner.hpp"
#include "rigidae/app/solve.hpp"
#include "rigidae/core/error.hpp"
#include "rigidae/io/scene_loader.hpp"

TEST_SUITE_BEGIN("system");

using namespace rigidae;

namespace {

constexpr double kTau = 0.8, kIa = 0.5, kIb = 0.7;  // N m, kg m^2 about z

std::string motor_scene(const std::string& coordinates, const std::string& equations) {
  return R"(schema_version = 2
name = "motor_pair"

[[bodies]]
name = "a"
mass = 2.0
inertia = [[0.3, 0.0, 0.0], [0.0, 0.4, 0.0], [0.0, 0.0, 0.5]]
position = [0.0, 0.0, 0.0]

[[bodies]]
name = "b"
mass = 1.5
inertia = [[0.4, 0.0, 0.0], [0.0, 0.45, 0.0], [0.0, 0.0, 0.7]]
position = [0.0, 0.0, 1.0]

[[joints]]
name = "hinge"
type = "revolute"
bodies = ["a", "b"]
point = [0.0, 0.0, 0.5]
axis = [0.0, 0.0, 1.0]
motor_torque = 0.8
motor_profile = { type = "polynomial", coefficients = [1.0, 2.0, -0.5] }

[gravity]
acceleration = [0.0, 0.0, 0.0]

[time]
end = 2.0
output_step = 0.05

[formulation]
coordinates = ")" + coordinates + R"("
equations = ")" + equations + R"("
scheme = "ggl"

[solver]
rtol = 1e-10
atol = 1e-10
)";
}

// The pair on a slider along z instead, pushed apart by 1.2 N x s(t).
std::string slider_scene(const std::string& coordinates, const std::string& equations) {
  std::string text = motor_scene(coordinates, equations);
  const auto replace = [&](const std::string& from, const std::string& to) {
    REQUIRE(text.find(from) != std::string::npos);
    text.replace(text.find(from), from.size(), to);
  };
  replace("name = \"hinge\"\ntype = \"revolute\"", "name = \"slider\"\ntype = \"prismatic\"");
  replace("motor_torque = 0.8", "motor_force = 1.2");
  return text;
}

constexpr double kForce = 1.2, kMa = 2.0, kMb = 1.5;  // N, kg

// The double integral of the profile s(t) = 1 + 2 t - t^2/2 from rest.
double profile_twice_integrated(double t) { return t * t / 2 + t * t * t / 3 - t * t * t * t / 24; }
double exact_displacement(double t) { return kForce * (1.0 / kMa + 1.0 / kMb) * profile_twice_integrated(t); }
double exact_angle(double t) { return kTau * (1.0 / kIa + 1.0 / kIb) * profile_twice_integrated(t); }

// One run of the pair: the largest miss of the joint's coordinate column
// against its closed form over the grid, and the largest |momentum column|.
struct PairRun {
  SolveOutcome outcome;
  double miss = 0.0, momentum = 0.0;
};

PairRun run_pair(const std::string& text, const std::string& folder, const std::string& coordinate,
                 double (*exact)(double), const std::string& momentum_column) {
  const Scene s = io::parse_scene(text, "motor_pair.toml");
  const auto dir = test::fresh_temp_dir(folder);
  PairRun r{solve_scene(s, dir)};
  REQUIRE(r.outcome.run.status == RunStatus::Success);
  const auto rows = test::read_csv_rows(dir / "trajectory.csv");
  REQUIRE(rows.size() == 41);
  for (const auto& row : rows) {
    const double t = std::stod(row.at("t"));
    r.miss = std::max(r.miss, std::abs(std::stod(row.at(coordinate)) - exact(t)));
    r.momentum = std::max(r.momentum, std::abs(std::stod(row.at(momentum_column))));
  }
  return r;
}

}  // namespace

TEST_CASE("joint motor: two bodies driven against each other turn by the closed form, every representation and form") {
  for (const char* coords : {"quaternion", "linear", "euler"})
    for (const char* eq : {"euler", "lagrange"}) {
      CAPTURE(coords);
      CAPTURE(eq);
      const PairRun r = run_pair(motor_scene(coords, eq), std::string("joint_motor_") + coords + "_" + eq,
                                 "hinge.angle", exact_angle, "L_z");
      const SolveOutcome& o = r.outcome;
      const double angle_miss = r.miss, momentum = r.momentum;
      MESSAGE("angle off by " << angle_miss << " rad (of " << exact_angle(2.0) << "), |L_z| <= " << momentum
                              << " N m s, energy balance " << o.drifts.energy << " (tolerance " << o.drifts.tolerance
                              << ")");
      CHECK(angle_miss < 1e-7);
      CHECK(momentum < 1e-7);  // of |L_b| = 3.7 N m s at the end
      // The motor's work is counted: the energy balance applies (without W it
      // would be off by the kinetic energy, ~20 J). In the Euler form the
      // rates are polynomials in t, which BDF integrates exactly, so the
      // balance holds to round-off; the Lagrange form's quaternion or matrix
      // entries are not, and its balance is the integration error (measured
      // 4e-8 at rtol 1e-10, 1e-9 at 1e-12: it scales with rtol), which the
      // check rightly reports past its 2 tau sqrt(N) limit.
      REQUIRE(o.drifts.energy == o.drifts.energy);
      if (std::string(eq) == "euler") {
        CHECK(o.drifts.energy < 10.0 * o.drifts.tolerance);
        for (const AccuracyWarning& w : o.warnings) CHECK(w.quantity != "energy");
      } else {
        CHECK(o.drifts.energy < 1e3 * o.drifts.tolerance);
      }
    }
}

TEST_CASE("linear motor: two bodies pushed apart along a slider move by the closed form, every representation and form") {
  for (const char* coords : {"quaternion", "linear", "euler"})
    for (const char* eq : {"euler", "lagrange"}) {
      CAPTURE(coords);
      CAPTURE(eq);
      const PairRun r = run_pair(slider_scene(coords, eq), std::string("linear_motor_") + coords + "_" + eq,
                                 "slider.displacement", exact_displacement, "p_z");
      const SolveOutcome& o = r.outcome;
      const double miss = r.miss, momentum = r.momentum;
      MESSAGE("displacement off by " << miss << " m (of " << exact_displacement(2.0) << "), |p_z| <= " << momentum
                                     << " N s, energy balance " << o.drifts.energy << " (tolerance "
                                     << o.drifts.tolerance << ")");
      CHECK(miss < 1e-8);
      CHECK(momentum < 1e-8);
      // The motor's work is counted: the balance applies and holds (the
      // bodies only translate, at rates polynomial in t).
      REQUIRE(o.drifts.energy == o.drifts.energy);
      CHECK(o.drifts.energy < 10.0 * o.drifts.tolerance);
      for (const AccuracyWarning& w : o.warnings) CHECK(w.quantity != "energy");
    }
}

TEST_CASE("joint motor: misplaced keys are positioned errors naming what is valid") {
  const std::string base = motor_scene("quaternion", "euler");
  const auto error_of = [](const std::string& text) {
    try {
      (void)io::parse_scene(text, "motor_pair.toml");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  // A profile without the torque it scales.
  std::string no_torque = base;
  no_torque.erase(no_torque.find("motor_torque = 0.8\n"), std::string("motor_torque = 0.8\n").size());
  const std::string e1 = error_of(no_torque);
  CHECK(e1.find("motor_pair.toml:22:") != std::string::npos);
  CHECK(e1.find("'joints[0].motor_profile' scales 'motor_torque'") != std::string::npos);
  // A motor on a joint type that does not carry one.
  std::string prismatic = base;
  prismatic.replace(prismatic.find("\"revolute\""), 10, "\"prismatic\"");
  const std::string e2 = error_of(prismatic);
  CHECK(e2.find("motor_pair.toml:22:") != std::string::npos);
  CHECK(e2.find("only 'revolute' joints carry") != std::string::npos);
  // A torque on a slider: it carries a force.
  CHECK(e2.find("'joints[0].motor_torque'") != std::string::npos);
  const std::string e3 = error_of(slider_scene("quaternion", "euler").replace(
      slider_scene("quaternion", "euler").find("motor_force = 1.2"), 17, "motor_force = \"strong\""));
  CHECK(e3.find("motor_pair.toml:22:") != std::string::npos);
  CHECK(e3.find("'joints[0].motor_force'") != std::string::npos);
}

TEST_SUITE_END();
