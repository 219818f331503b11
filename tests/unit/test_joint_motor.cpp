// A motor in a revolute joint (keys motor_torque, motor_profile): the torque
// tau(t) = tau_m s(t) on b about the axis and -tau(t) on a.
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
// both forms.
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

double exact_angle(double t) { return kTau * (1.0 / kIa + 1.0 / kIb) * (t * t / 2 + t * t * t / 3 - t * t * t * t / 24); }

}  // namespace

TEST_CASE("joint motor: two bodies driven against each other turn by the closed form, every representation and form") {
  for (const char* coords : {"quaternion", "linear", "euler"})
    for (const char* eq : {"euler", "lagrange"}) {
      CAPTURE(coords);
      CAPTURE(eq);
      const Scene s = io::parse_scene(motor_scene(coords, eq), "motor_pair.toml");
      const auto dir = test::fresh_temp_dir(std::string("joint_motor_") + coords + "_" + eq);
      const SolveOutcome o = solve_scene(s, dir);
      REQUIRE(o.run.status == RunStatus::Success);
      const auto rows = test::read_csv_rows(dir / "trajectory.csv");
      REQUIRE(rows.size() == 41);
      double angle_miss = 0.0, momentum = 0.0;
      for (const auto& r : rows) {
        const double t = std::stod(r.at("t"));
        angle_miss = std::max(angle_miss, std::abs(std::stod(r.at("hinge.angle")) - exact_angle(t)));
        momentum = std::max(momentum, std::abs(std::stod(r.at("L_z"))));
      }
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
}

TEST_SUITE_END();
