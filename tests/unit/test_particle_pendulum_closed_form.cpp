// exact/particle_pendulum.hpp: the simple pendulum's closed form that the
// accuracy verdict and compare use for a mechanism that is one. Independent
// truth: the pendulum equation theta'' = -(g/L) sin(theta) integrated by a
// classical Runge-Kutta of 4th order with a fine fixed step (no elliptic
// function involved), the energy, and the scene's own geometry.
#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include "cli_runner.hpp"
#include "rigidae/exact/particle_pendulum.hpp"
#include "rigidae/io/scene_loader.hpp"

TEST_SUITE_BEGIN("unit");

using namespace rigidae;

namespace {

Scene pendulum_scene() {
  return io::load_scene(std::string(RIGIDAE_SOURCE_DIR) + "/problems/particle_pendulum.toml");
}

// theta(t) of theta'' = -(g/L) sin(theta) from (theta0, 0), RK4 with step h.
double rk4_angle(double theta0, double w2, double t, int steps) {
  const double h = t / steps;
  double th = theta0, om = 0.0;
  for (int i = 0; i < steps; ++i) {
    const double k1t = om, k1o = -w2 * std::sin(th);
    const double k2t = om + 0.5 * h * k1o, k2o = -w2 * std::sin(th + 0.5 * h * k1t);
    const double k3t = om + 0.5 * h * k2o, k3o = -w2 * std::sin(th + 0.5 * h * k2t);
    const double k4t = om + h * k3o, k4o = -w2 * std::sin(th + h * k3t);
    th += h / 6.0 * (k1t + 2 * k2t + 2 * k3t + k4t);
    om += h / 6.0 * (k1o + 2 * k2o + 2 * k3o + k4o);
  }
  return th;
}

}  // namespace

TEST_CASE("simple pendulum closed form: the shipped scene's, against Runge-Kutta on theta'' = -(g/L) sin(theta)") {
  const Scene s = pendulum_scene();
  std::string why;
  const auto p = exact::ParticlePendulum::of(s, &why);
  REQUIRE_MESSAGE(p, why);
  CHECK(p->body() == "bob");
  CHECK(p->period() == doctest::Approx(2.3678419475762374).epsilon(1e-14));
  CHECK((p->position(0.0) - Vec3(1, 0, 0)).norm() < 1e-15);
  const double w2 = 9.81, theta0 = M_PI / 2;
  for (double t : {0.1, 0.59, 1.0, 1.7, 2.3}) {
    CAPTURE(t);
    // The scene swings in the x-z plane from +x, gravity along -z: theta
    // from the downward vertical towards +x.
    const double th = rk4_angle(theta0, w2, t, 20000);
    const Vec3 expected(std::sin(th), 0.0, -std::cos(th));
    CHECK((p->position(t) - expected).norm() < 1e-11);
  }
  // Energy (per unit mass): v^2 / 2 + g z, constant; v by a central difference.
  const double h = 1e-5;
  for (double t : {0.3, 1.1, 7.9}) {
    const Vec3 v = (p->position(t + h) - p->position(t - h)) / (2 * h);
    CHECK(0.5 * v.squaredNorm() + 9.81 * p->position(t)(2) == doctest::Approx(0.0).epsilon(1e-8).scale(9.81));
    CHECK(std::abs(p->position(t).norm() - 1.0) < 1e-14);  // on the rod's sphere
  }
}

TEST_CASE("simple pendulum closed form: covered only as released from rest, swinging, alone on a distance joint") {
  std::string text = test::read_file(std::string(RIGIDAE_SOURCE_DIR) + "/problems/particle_pendulum.toml");
  const auto edited = [&](const std::string& from, const std::string& to) {
    std::string t = text;
    const std::size_t at = t.find(from);
    REQUIRE(at != std::string::npos);
    t.replace(at, from.size(), to);
    return io::parse_scene(t, "pp.toml");
  };
  std::string why;
  const std::string moving = "position = [1.0, 0.0, 0.0]\nvelocity = [0.0, 0.0, 1.0]";
  CHECK(!exact::ParticlePendulum::of(edited("position = [1.0, 0.0, 0.0]", moving), &why));
  CHECK(why.find("started in motion") != std::string::npos);
  CHECK(!exact::ParticlePendulum::of(edited("position = [1.0, 0.0, 0.0]", "position = [0.0, 0.0, -1.0]"), &why));
  CHECK(why.find("on the vertical") != std::string::npos);
  const Scene weightless = edited("acceleration = [0.0, 0.0, -9.81]", "acceleration = [0.0, 0.0, 0.0]");
  CHECK(!exact::ParticlePendulum::of(weightless, &why));
  CHECK(why.find("without gravity") != std::string::npos);
  // Another amplitude and a tilted anchor: the same formulas, checked against RK4.
  const Scene tilted = edited("position = [1.0, 0.0, 0.0]", "position = [0.5, 0.0, -0.8660254037844386]");
  const auto p = exact::ParticlePendulum::of(tilted, &why);
  REQUIRE(p);
  const double th = rk4_angle(M_PI / 6, 9.81, 0.77, 20000);
  CHECK((p->position(0.77) - Vec3(std::sin(th), 0.0, -std::cos(th))).norm() < 1e-11);
}

TEST_SUITE_END();
