// Assembled starts (multibody/assembly.hpp): problems/four_bar_assembled.toml
// gives the crank's angle and rate and rough guesses for the coupler and the
// rocker. Independent truths:
// - four_bar_revolute.toml's start, computed by hand from the loop closure;
// - the planar four-bar's closure in closed form (circle intersection) at
//   other crank angles, and its rate by a central difference of the closure;
// - a loop that cannot close (pivots farther apart than the links reach) is
//   refused at a joint; bad [mechanism] keys are positioned errors;
// - the same four-bar with its rocker held at a pivot (turning about D, no
//   joint D) assembles onto the same closure and moves as the revolute one.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <vector>
#include <string>

#include <fmt/format.h>

#include "cli_runner.hpp"
#include "scene_edit.hpp"
#include "rigidae/core/error.hpp"
#include "rigidae/io/scene_loader.hpp"
#include "rigidae/multibody/assembly.hpp"
#include "rigidae/multibody/multibody_problem.hpp"
#include "rigidae/solver/ida_driver.hpp"
#include "rigidae/so3/rotation.hpp"

TEST_SUITE_BEGIN("unit");

using namespace rigidae;
namespace fs = std::filesystem;

namespace {

std::string problem_text(const std::string& name) {
  return rigidae::test::read_file(fs::path(RIGIDAE_SOURCE_DIR) / "problems" / name);
}

// The four-bar in the x-z plane: pivots A = 0 and D = (0.45, 0, 0), crank
// a = 0.2, coupler b = 0.5, rocker c = 0.4; phi the crank's angle from x
// towards z. C is the intersection of the circles about B (radius b) and D
// (radius c) on the upper branch (the scene's assembly mode).
struct Closure {
  Vec3 B, C;
};

Closure closure(double phi) {
  const double a = 0.2, b = 0.5, c = 0.4;
  const Vec3 D(0.45, 0.0, 0.0);
  const Vec3 B(a * std::cos(phi), 0.0, a * std::sin(phi));
  const Vec3 d = D - B;
  const double L = d.norm();
  const double along = (b * b - c * c + L * L) / (2.0 * L);
  const double h = std::sqrt(b * b - along * along);
  const Vec3 u = d / L;
  const Vec3 n(-u(2), 0.0, u(0));  // u turned 90 degrees towards +z: the upper branch
  return {B, B + along * u + h * n};
}

// Angle of a body's x axis from space x towards z (a rotation about -y).
double planar_angle(const Mat3& R) { return std::atan2(R(2, 0), R(0, 0)); }

// The scene with the crank at angle phi (rate -omega_y about the x-z angle).
std::string at_crank_angle(double phi) {
  std::string text = problem_text("four_bar_assembled.toml");
  const auto replace = [&](const std::string& from, const std::string& to) {
    const std::size_t at = text.find(from);
    REQUIRE(at != std::string::npos);
    text.replace(at, from.size(), to);
  };
  const Vec3 centre(0.1 * std::cos(phi), 0.0, 0.1 * std::sin(phi));
  replace("position = [0.05000000000000002, 0.0, 0.08660254037844387]",
          fmt::format("position = [{:.17g}, 0.0, {:.17g}]", centre(0), centre(2)));
  replace("angle = -1.0471975511965976", fmt::format("angle = {:.17g}", -phi));
  return text;
}

// four_bar_assembled.toml with the rocker held at a pivot at D instead of
// by the revolute D: the revolute C keeps its axis along the coupler's, so
// the mechanism is the same. Its guess turns about D to rocker_angle (the
// lever, the rocker's centre 0.2 m from D along its x axis, is the pose's).
std::string with_pivoted_rocker(std::string text, double rocker_angle = -1.2, double lever = 0.2) {
  const auto replace = [&](const std::string& from, const std::string& to) {
    const std::size_t at = text.find(from);
    REQUIRE(at != std::string::npos);
    text.replace(at, from.size(), to);
  };
  const Vec3 centre = Vec3(0.45, 0, 0) + lever * Vec3(std::cos(rocker_angle), 0.0, -std::sin(rocker_angle));
  replace("position = [0.50, 0.0, 0.20]\naxis_angle = { axis = [0.0, 1.0, 0.0], angle = -1.2 }",
          fmt::format("position = [{:.17g}, 0.0, {:.17g}]\naxis_angle = {{ axis = [0.0, 1.0, 0.0], angle = {:.17g} }}"
                      "\npivot = [0.45, 0.0, 0.0]",
                      centre(0), centre(2), rocker_angle));
  const std::size_t d = text.find("[[joints]]\nname = \"D\"");
  REQUIRE(d != std::string::npos);
  text.erase(d, text.find("[gravity]") - d);
  return text;
}

// The message with which building the problem of scene `text` (file
// "fb.toml") refuses its start; "" when it starts.
std::string start_error(const std::string& text) {
  try {
    multibody::MultibodyProblem p(io::parse_scene(text, "fb.toml"));
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("an assembled four-bar starts where the hand-assembled one does") {
  const Scene hand = io::load_scene((fs::path(RIGIDAE_SOURCE_DIR) / "problems" / "four_bar_revolute.toml").string());
  const Scene guessed =
      io::load_scene((fs::path(RIGIDAE_SOURCE_DIR) / "problems" / "four_bar_assembled.toml").string());
  multibody::MultibodyProblem p(guessed);
  const multibody::AssemblyReport& ar = p.assembly();
  REQUIRE(ar.done);
  CHECK(ar.initial_miss > 0.01);  // the guesses are centimetres off
  CHECK(ar.final_miss < 1e-14);
  CHECK(ar.final_velocity_miss < 1e-13);
  for (int i = 0; i < 3; ++i) {
    const BodySpec& a = p.spec().bodies[i];
    const BodySpec& h = hand.multibody->bodies[i];
    CAPTURE(a.name);
    CHECK((a.x0_W - h.x0_W).norm() < 1e-13);
    CHECK(so3::rotation_distance(a.R0_WB, h.R0_WB) < 1e-13);
    CHECK((a.v0_W - h.v0_W).norm() < 1e-12);
    CHECK((a.R0_WB * a.omega0_B - h.R0_WB * h.omega0_B).norm() < 1e-12);
  }
  // The report: the crank held (not moved), the others moved by what the guesses were off.
  REQUIRE(ar.bodies.size() == 3);
  CHECK(ar.bodies[0].moved_m == 0.0);
  CHECK(ar.bodies[0].turned_rad == 0.0);
  CHECK(ar.bodies[1].moved_m == doctest::Approx((guessed.multibody->bodies[1].x0_W - hand.multibody->bodies[1].x0_W).norm()));
  CHECK(ar.note.find("held crank") != std::string::npos);
}

TEST_CASE("an assembled four-bar matches the closed-form loop closure at other crank angles") {
  for (double deg : {0.0, 100.0, 200.0, 300.0}) {
    CAPTURE(deg);
    const double phi = deg * M_PI / 180.0;
    Scene scene = io::parse_scene(at_crank_angle(phi), "fb.toml");
    MultibodySpec& spec = *scene.multibody;
    // Guesses farther off at the other angles: the coupler and rocker where
    // they were at 60 degrees.
    const multibody::AssemblyReport ar = multibody::assemble_start(spec);
    REQUIRE(ar.done);
    const Closure c = closure(phi);
    const Vec3 D(0.45, 0.0, 0.0);
    CHECK((spec.bodies[1].x0_W - 0.5 * (c.B + c.C)).norm() < 1e-12);
    CHECK((spec.bodies[2].x0_W - 0.5 * (c.C + D)).norm() < 1e-12);
    CHECK(std::abs(std::remainder(planar_angle(spec.bodies[1].R0_WB) - std::atan2((c.C - c.B)(2), (c.C - c.B)(0)),
                                  2 * M_PI)) < 1e-12);
    // Rates: the crank turns at omega_y = 6 about y, i.e. phi' = -6; the
    // rocker's angle psi(phi) by central differences: omega_y = -psi' phi'.
    const double hstep = 1e-5;
    const auto psi = [&](double f) {
      const Closure k = closure(f);
      return std::atan2((k.C - D)(2), (k.C - D)(0));
    };
    const double dpsi = (psi(phi + hstep) - psi(phi - hstep)) / (2 * hstep);
    const Vec3 omega_rocker = spec.bodies[2].R0_WB * spec.bodies[2].omega0_B;
    CHECK(omega_rocker(1) == doctest::Approx(-dpsi * -6.0).epsilon(1e-8));
    CHECK(std::abs(omega_rocker(0)) + std::abs(omega_rocker(2)) < 1e-12);
    // The held crank keeps its pose and rate; its centre's velocity follows A.
    const Vec3 crank_centre(0.1 * std::cos(phi), 0.0, 0.1 * std::sin(phi));
    CHECK((spec.bodies[0].x0_W - crank_centre).norm() < 1e-15);
    CHECK((spec.bodies[0].v0_W - Vec3(0, 6, 0).cross(crank_centre)).norm() < 1e-12);
  }
}

TEST_CASE("a rocker held at a pivot assembles onto the closed-form closure, turning about the pivot only") {
  const Vec3 D(0.45, 0.0, 0.0);
  for (double deg : {60.0, 150.0, 250.0}) {
    CAPTURE(deg);
    const double phi = deg * M_PI / 180.0;
    Scene scene = io::parse_scene(with_pivoted_rocker(at_crank_angle(phi)), "fb.toml");
    MultibodySpec& spec = *scene.multibody;
    REQUIRE(spec.bodies[2].pivot_W);
    REQUIRE(spec.joints.size() == 3);
    const multibody::AssemblyReport ar = multibody::assemble_start(spec);
    REQUIRE(ar.done);
    CHECK(ar.final_miss < 1e-14);
    const Closure c = closure(phi);
    const BodySpec& rocker = spec.bodies[2];
    CHECK((spec.bodies[1].x0_W - 0.5 * (c.B + c.C)).norm() < 1e-12);
    CHECK((rocker.x0_W - 0.5 * (c.C + D)).norm() < 1e-12);
    CHECK(std::abs(std::remainder(planar_angle(rocker.R0_WB) - std::atan2((c.C - D)(2), (c.C - D)(0)), 2 * M_PI)) <
          1e-12);
    // It turned about D: its lever is still 0.2 m along its own x axis.
    REQUIRE(rocker.com_from_pivot_B);
    CHECK((*rocker.com_from_pivot_B - Vec3(0.2, 0.0, 0.0)).norm() < 1e-15);
    CHECK((rocker.x0_W - (D + rocker.R0_WB * *rocker.com_from_pivot_B)).norm() < 1e-15);
    CHECK(ar.bodies[2].turned_rad > 0.1);
    // Rates as in the revolute four-bar (central differences of the
    // closure), the centre's velocity omega x (x - D).
    const double hstep = 1e-5;
    const auto psi = [&](double f) {
      const Closure k = closure(f);
      return std::atan2((k.C - D)(2), (k.C - D)(0));
    };
    const double dpsi = (psi(phi + hstep) - psi(phi - hstep)) / (2 * hstep);
    const Vec3 omega = rocker.R0_WB * rocker.omega0_B;
    CHECK(omega(1) == doctest::Approx(-dpsi * -6.0).epsilon(1e-8));
    CHECK(std::abs(omega(0)) + std::abs(omega(2)) < 1e-12);
    CHECK((rocker.v0_W - omega.cross(rocker.x0_W - D)).norm() < 1e-14);
  }
}

TEST_CASE("a four-bar with its rocker on a pivot moves as the one with the revolute D") {
  // Both assembled from the same crank pose and rate, solved at rtol 1e-10
  // for 1 s (about one crank turn): the rocker's centre over the grid.
  std::vector<std::vector<Vec3>> runs;
  for (const std::string& text : {problem_text("four_bar_assembled.toml"),
                                  with_pivoted_rocker(problem_text("four_bar_assembled.toml"))}) {
    Scene s = io::parse_scene(text, "fb.toml");
    s.time = {0.0, 1.0, 0.05};
    s.solver.rtol = s.solver.atol = 1e-10;
    multibody::MultibodyProblem p(s);
    struct Sink final : StepSink {
      multibody::MultibodyProblem& p;
      std::vector<Vec3> rocker;
      explicit Sink(multibody::MultibodyProblem& pr) : p(pr) {}
      void on_step(double, double, int, const Eigen::VectorXd&) override {}
      void on_output(double, const Eigen::VectorXd& y) override { rocker.push_back(p.body_position(2, y.data())); }
    } sink(p);
    REQUIRE(integrate(p, s.solver, s.time, sink).status == RunStatus::Success);
    runs.push_back(sink.rocker);
  }
  REQUIRE(runs[0].size() == 21);
  REQUIRE(runs[1].size() == 21);
  double worst = 0.0, travel = 0.0;
  for (std::size_t k = 0; k < runs[0].size(); ++k) {
    worst = std::max(worst, (runs[0][k] - runs[1][k]).norm());
    travel = std::max(travel, (runs[0][k] - runs[0][0]).norm());
  }
  MESSAGE("rocker centre: largest difference " << worst << " m, largest travel " << travel << " m");
  CHECK(travel > 0.05);  // it swings
  CHECK(worst < 1e-7);
}

TEST_CASE("a pivoted rocker whose guess gives too long a lever cannot close the loop: the refusal names the pivot") {
  // Lever 0.8 m: C lies 1.0 m from D, farther than crank and coupler reach
  // at 60 degrees (|BD| + 0.5 < 1.0).
  const std::string msg = start_error(with_pivoted_rocker(problem_text("four_bar_assembled.toml"), -1.2, 0.8));
  CAPTURE(msg);
  REQUIRE_MESSAGE(!msg.empty(), "assembled a loop that cannot close");
  CHECK(msg.find("cannot be assembled near the given poses") != std::string::npos);
  CHECK(msg.find("\"rocker\" (lever 0.8 m) only turns about its pivot") != std::string::npos);
  CHECK(msg.find("check that each guessed position and orientation agree") != std::string::npos);
}

TEST_CASE("a held crank that its joints lock keeps no rate: the assembled start refuses, at [mechanism]") {
  // The crank held at a pivot at its own centre and by the revolute A at its
  // end: it cannot turn, so its given 6 rad/s cannot be kept.
  std::string text = problem_text("four_bar_assembled.toml");
  const std::string from = "angular_velocity = [0.0, 6.0, 0.0]";
  const std::size_t at = text.find(from);
  REQUIRE(at != std::string::npos);
  text.replace(at, from.size(), from + "\npivot = [0.05000000000000002, 0.0, 0.08660254037844387]");
  const std::size_t hold = text.find("hold = [\"crank\"]", text.find("[mechanism]\n"));
  REQUIRE(hold != std::string::npos);
  const int line = 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(hold), '\n'));
  const std::string msg = start_error(text);
  CAPTURE(msg);
  REQUIRE_MESSAGE(!msg.empty(), "started a locked crank at 6 rad/s");
  CHECK(msg.find(fmt::format("fb.toml:{}:", line)) == 0);
  CHECK(msg.find("the held bodies' velocities cannot be kept: with \"crank\" as given") != std::string::npos);
}

TEST_CASE("a four-bar whose pivots are farther apart than its links reach cannot be assembled") {
  std::string text = problem_text("four_bar_assembled.toml");
  const std::size_t at = text.find("point_b = [0.45, 0.0, 0.0]");
  REQUIRE(at != std::string::npos);
  text.replace(at, 26, "point_b = [1.25, 0.0, 0.0]");  // |BD| >= 1.05 > b + c = 0.9
  const std::string msg = start_error(text);
  CAPTURE(msg);
  REQUIRE_MESSAGE(!msg.empty(), "assembled a loop that cannot close");
  CHECK(msg.find("fb.toml:") == 0);
  CHECK(msg.find("cannot be assembled near the given poses") != std::string::npos);
  CHECK(msg.find("with \"crank\" held") != std::string::npos);
}

TEST_CASE("[mechanism] assemble and hold: bad values are positioned errors") {
  const std::string text = problem_text("four_bar_assembled.toml");
  const std::string key = "hold = [\"crank\"]";
  const std::size_t at = text.find(key, text.find("[mechanism]\n"));  // not the header's mention
  REQUIRE(at != std::string::npos);
  const int line = 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(at), '\n'));
  const auto error_of = [&](const std::string& replacement) {
    return rigidae::test::parse_error_with(text, at, key.size(), replacement, "fb.toml");
  };
  const struct {
    const char* value;
    const char* says;
  } cases[] = {
      {"hold = [\"crank\", \"crank\"]", "is held twice"},
      {"hold = [\"crnak\"]", "did you mean \"crank\""},
      {"hold = [\"ground\"]", "the ground never moves"},
      {"hold = []", "non-empty array of body names"},
      {"hold = \"crank\"", "non-empty array of body names"},
      {"hold = [\"crank\", \"coupler\", \"rocker\"]", "holds every body"},
      {"hold = [\"crank\"]\nassemble = false", "assemble' = false"},
      {"assemble = 1", "mechanism.assemble"},
  };
  for (const auto& c : cases) {
    CAPTURE(c.value);
    const std::string msg = error_of(c.value);
    CAPTURE(msg);
    CHECK(msg.find(fmt::format("fb.toml:{}:", line)) == 0);
    CHECK(msg.find(c.says) != std::string::npos);
  }
  // assemble = true alone: every body may move (least change in the mass metric).
  std::string t2 = text;
  t2.replace(at, key.size(), "assemble = true");
  multibody::MultibodyProblem p(io::parse_scene(t2, "fb.toml"));
  CHECK(p.assembly().done);
  CHECK(p.assembly().held.empty());
  CHECK(p.assembly().final_miss < 1e-14);
}

TEST_SUITE_END();
