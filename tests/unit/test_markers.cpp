// Markers ([[markers]], src/multibody/markers.cpp): named points on bodies
// with position, velocity and acceleration columns, against independent
// truth:
// - closed forms: a marker on the particle pendulum's bob (acceleration
//   g - T u / m, T = 3 m g cos(theta), position from the Jacobi elliptic
//   solution) and on a rigid body turning steadily about a principal axis
//   (position R(w t) s, velocity w x p, acceleration -w^2 p);
// - the recorded acceleration against central differences of the recorded
//   velocity on a fine grid;
// - the step file has the same columns; bad markers are positioned errors.
#include <doctest/doctest.h>

#include <cmath>
#include <fstream>
#include <string>

#include "cli_runner.hpp"
#include "rigidae/core/error.hpp"
#include "rigidae/exact/jacobi_elliptic.hpp"
#include "rigidae/io/scene_loader.hpp"

TEST_SUITE_BEGIN("system");

using namespace rigidae;

namespace {

constexpr double kG = 9.81;

std::string pendulum_with_marker() {
  std::string s = test::read_file(std::string(RIGIDAE_SOURCE_DIR) + "/problems/particle_pendulum.toml");
  s += "\n[[markers]]\nname = \"tip\"\nbody = \"bob\"\n";
  return s;
}

std::filesystem::path write_scene(const std::filesystem::path& dir, const std::string& text) {
  const auto p = dir / "scene.toml";
  std::ofstream(p) << text;
  return p;
}

Vec3 col3(const std::map<std::string, std::string>& r, const std::string& prefix) {
  return Vec3(std::stod(r.at(prefix + "x")), std::stod(r.at(prefix + "y")), std::stod(r.at(prefix + "z")));
}

double period() { return 4.0 * exact::complete_elliptic_k(0.5) / std::sqrt(kG); }

}  // namespace

TEST_CASE("markers: on the particle pendulum, position and acceleration = the closed form, and a = dv/dt by differences") {
  const auto dir = test::fresh_temp_dir("markers-pendulum");
  // One period on a fine grid (T/400) for the differences.
  const auto scene = write_scene(dir, pendulum_with_marker());
  const auto r = test::run_cli("solve " + scene.string() + " --t-end " + std::to_string(period()) +
                               " --output-step " + std::to_string(period() / 400) + " --quiet --out " +
                               (dir / "run").string());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const auto rows = test::read_csv_rows(dir / "run" / "trajectory.csv");
  REQUIRE(rows.size() >= 400);
  const double k = std::sqrt(0.5), K = exact::complete_elliptic_k(0.5), w0 = std::sqrt(kG);
  double pos = 0.0, acc = 0.0, acc_scale = 0.0, fd = 0.0;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const double t = std::stod(rows[i].at("t"));
    const exact::SnCnDn f = exact::jacobi_sn_cn_dn(K - w0 * t, 0.5, 0.5);
    const double c = 1.0 - 2.0 * k * k * f.sn * f.sn;  // cos(theta)
    const Vec3 p(2.0 * k * f.sn * f.dn, 0.0, -c);      // L = 1 m
    // Newton: m a = m g - T u, u = p / L, T = 3 m g cos(theta) (released at 90 degrees).
    const Vec3 a = Vec3(0, 0, -kG) - 3.0 * kG * c * p;
    pos = std::max(pos, (col3(rows[i], "tip.") - p).norm());
    acc = std::max(acc, (col3(rows[i], "tip.a") - a).norm());
    acc_scale = std::max(acc_scale, a.norm());
    // The marker is the bob: its columns repeat the body's.
    CHECK(col3(rows[i], "tip.") == col3(rows[i], "bob."));
    CHECK(col3(rows[i], "tip.v") == col3(rows[i], "bob.v"));
    if (i > 0 && i + 1 < rows.size()) {
      const double h = std::stod(rows[i + 1].at("t")) - std::stod(rows[i - 1].at("t"));
      const Vec3 dv = (col3(rows[i + 1], "tip.v") - col3(rows[i - 1], "tip.v")) / h;
      fd = std::max(fd, (dv - col3(rows[i], "tip.a")).norm());
    }
  }
  MESSAGE("pendulum marker: position " << pos << " m, acceleration " << acc << " m/s^2 (of " << acc_scale
                                       << "), central differences of the velocity " << fd << " m/s^2");
  CHECK(pos < 1e-7);
  CHECK(acc < 1e-5 * acc_scale);
  // Differences over 2h = T/200: their own error h^2/6 |a'''| is what this
  // measures (3.4e-4 of |a|max measured); a wrong acceleration would be O(1).
  CHECK(fd < 1e-3 * acc_scale);
  // The step file carries the marker's columns too.
  const std::string steps = test::read_file(dir / "run" / "steps.csv");
  CHECK(steps.find("tip.ax") != std::string::npos);
}

TEST_CASE("markers: on a rigid body turning steadily, p = R(w t) s, v = w x p, a = -w^2 p, both equation forms") {
  // A free body (no gravity, no joints) turning at w = 2 rad/s about its
  // principal axis z; the marker at s = (0.5, 0.2, 0.3) in the body frame.
  const std::string text = R"(schema_version = 2
name = "spinner"
[[bodies]]
name = "disc"
mass = 2.0
inertia_principal = [1.0, 2.0, 3.0]
position = [0.0, 0.0, 0.0]
angular_velocity = [0.0, 0.0, 2.0]
[[markers]]
name = "rim"
body = "disc"
point = [0.5, 0.2, 0.3]
[gravity]
acceleration = [0.0, 0.0, 0.0]
[time]
end = 2.0
output_step = 0.05
[solver]
rtol = 1e-10
atol = 1e-10
)";
  for (const char* form : {"euler", "lagrange"}) {
    CAPTURE(std::string(form));
    const auto dir = test::fresh_temp_dir("markers-spinner");
    const auto scene = write_scene(dir, text);
    const auto r = test::run_cli("solve " + scene.string() + " --equations " + form + " --quiet --out " +
                                 (dir / "run").string());
    INFO(r.output);
    REQUIRE(r.exit_code == 0);
    const auto rows = test::read_csv_rows(dir / "run" / "trajectory.csv");
    REQUIRE(rows.size() == 41);
    double worst = 0.0;
    for (const auto& row : rows) {
      const double t = std::stod(row.at("t")), w = 2.0;
      const Vec3 p(0.5 * std::cos(w * t) - 0.2 * std::sin(w * t), 0.5 * std::sin(w * t) + 0.2 * std::cos(w * t), 0.3);
      const Vec3 v = Vec3(0, 0, w).cross(p);
      const Vec3 a(-w * w * p.x(), -w * w * p.y(), 0.0);
      worst = std::max({worst, (col3(row, "rim.") - p).norm(), (col3(row, "rim.v") - v).norm(),
                        (col3(row, "rim.a") - a).norm()});
    }
    MESSAGE(form << ": largest marker error " << worst);
    CHECK(worst < 1e-7);
  }
}

TEST_CASE("markers: bad markers are positioned errors naming the key") {
  const auto error_of = [](const std::string& marker) {
    try {
      io::parse_scene(pendulum_with_marker() + marker, "m.toml");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  CHECK(error_of("\n[[markers]]\nname = \"g\"\nbody = \"ground\"\npoint = [0, 0, 0]\n").find("a marker is on a body") !=
        std::string::npos);
  const std::string off = error_of("\n[[markers]]\nname = \"off\"\nbody = \"bob\"\npoint = [1.2, 0, 0]\n");
  CHECK(off.find("m.toml:") == 0);
  CHECK(off.find("a point mass has no extent") != std::string::npos);
  CHECK(error_of("\n[[markers]]\nname = \"x\"\nbody = \"bob\"\naxis = [1, 0, 0]\n").find("axis") != std::string::npos);
  CHECK(error_of("\n[[markers]]\nname = \"tip\"\nbody = \"bob\"\n").find("duplicate name") != std::string::npos);
}

TEST_SUITE_END();
