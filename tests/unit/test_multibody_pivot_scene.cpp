// The scene key `pivot` of a schema-2 body: what the loader makes of it, the
// inputs it refuses (with file:line), and the support force the CLI records
// in trajectory.csv and steps.csv (against the closed form at t = 0 and the
// free body + spherical joint of problems/heavy_top_absolute.toml).
#include <doctest/doctest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <string>

#include "cli_runner.hpp"
#include "rigidae/core/error.hpp"
#include "rigidae/io/scene_loader.hpp"
#include "rigidae/multibody/assembly.hpp"

TEST_SUITE_BEGIN("system");

using namespace rigidae;

namespace {

// heavy_top_absolute.toml's top held at the origin by `pivot` instead of a joint.
std::string pivoted_top(const std::string& extra_body_keys = "", const std::string& extra = "") {
  return R"(schema_version = 2
name = "heavy_top_pivoted"

[[bodies]]
name = "top"
mass = 15.0
inertia_principal = [0.234375, 0.46875, 0.234375]
position = [0.0, 1.0, 0.0]
quaternion = [1.0, 0.0, 0.0, 0.0]
angular_velocity = [0.0, 150.0, -4.61538]
angular_velocity_frame = "body"
pivot = [0.0, 0.0, 0.0]
)" + extra_body_keys + R"(
[gravity]
acceleration = [0.0, 0.0, -9.81]

[time]
start = 0.0
end = 0.2
output_step = 0.01
)" + extra;
}

std::string error_of(const std::string& text) {
  try {
    (void)io::parse_scene(text, "pivot.toml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("pivot scene: the loader keeps the centre of mass and derives its velocity") {
  const Scene s = io::parse_scene(pivoted_top(), "pivot.toml");
  REQUIRE(s.multibody);
  const BodySpec& b = s.multibody->bodies.at(0);
  REQUIRE(b.pivot_W);
  CHECK(b.pivot_W->norm() == 0.0);
  CHECK((b.x0_W - Vec3(0, 1, 0)).norm() == 0.0);
  // omega x (x - pivot) = (0, 150, -4.61538) x (0, 1, 0) = (4.61538, 0, 0)
  CHECK((b.v0_W - Vec3(4.61538, 0, 0)).norm() < 1e-12);
}

TEST_CASE("pivot scene: an assembled start with no joint keeps the pivoted top as given") {
  Scene s = io::parse_scene(pivoted_top("", "\n[mechanism]\nassemble = true\n"), "pivot.toml");
  const BodySpec given = s.multibody->bodies.at(0);
  const multibody::AssemblyReport ar = multibody::assemble_start(*s.multibody);
  REQUIRE(ar.done);
  CHECK(ar.iterations == 0);
  CHECK(ar.final_miss == 0.0);
  const BodySpec& b = s.multibody->bodies.at(0);
  CHECK((b.x0_W - given.x0_W).norm() == 0.0);
  CHECK((b.R0_WB - given.R0_WB).norm() == 0.0);
  CHECK((b.omega0_B - given.omega0_B).norm() == 0.0);
  CHECK((b.v0_W - given.v0_W).norm() < 1e-13);
  REQUIRE(b.com_from_pivot_B);
  CHECK((*b.com_from_pivot_B - Vec3(0, 1, 0)).norm() == 0.0);
}

TEST_CASE("pivot scene: velocity and a short pivot are refused at their lines") {
  const std::string v = error_of(pivoted_top("velocity = [1.0, 0.0, 0.0]\n"));
  INFO(v);
  CHECK(v.rfind("pivot.toml:13:", 0) == 0);
  CHECK(v.find("'bodies[0].velocity'") != std::string::npos);
  CHECK(v.find("leave 'velocity' out") != std::string::npos);
  const std::string p = error_of(pivoted_top().replace(pivoted_top().find("pivot = [0.0, 0.0, 0.0]"), 23, "pivot = [0.0, 0.0]"));
  INFO(p);
  CHECK(p.find("pivot.toml:12:") == 0);
  CHECK(p.find("bodies[0].pivot") != std::string::npos);
}

TEST_CASE("pivot scene: rigidae solve records the support force, equal to the spherical joint's reaction") {
  const auto dir = test::fresh_temp_dir("pivot-scene");
  const auto scene = dir / "pivoted.toml";
  {
    std::ofstream out(scene);
    out << pivoted_top();
  }
  const auto r = test::run_cli("solve " + scene.string() + " --quiet --rtol 1e-10 --atol 1e-10 --out " + (dir / "p").string());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const auto abs = test::run_cli("solve " + std::string(RIGIDAE_SOURCE_DIR) +
                                 "/problems/heavy_top_absolute.toml --quiet --t-end 0.2 --rtol 1e-10 --atol 1e-10 --out " +
                                 (dir / "a").string());
  INFO(abs.output);
  REQUIRE(abs.exit_code == 0);
  const auto traj = test::read_csv_rows(dir / "p" / "trajectory.csv");
  const auto ref = test::read_csv_rows(dir / "a" / "trajectory.csv");
  REQUIRE(traj.size() == ref.size());
  const auto force = [](const std::map<std::string, std::string>& row, const std::string& prefix) {
    return Vec3(std::stod(row.at(prefix + "_x")), std::stod(row.at(prefix + "_y")), std::stod(row.at(prefix + "_z")));
  };
  // t = 0: m (a_c - g) = (0, -319.526, -317.262) N, |F| = 450.28 N (heavy_top_absolute.toml's header).
  CHECK(force(traj.front(), "top.pivot_force").norm() == doctest::Approx(450.28).epsilon(1e-5));
  for (std::size_t i = 0; i < traj.size(); ++i) {
    const Vec3 F = force(traj[i], "top.pivot_force"), R = force(ref[i], "pivot.force");
    CHECK((F - R).norm() < 1e-5 * R.norm());
  }
  // Per step too.
  const auto steps = test::read_csv_rows(dir / "p" / "steps.csv");
  REQUIRE(!steps.empty());
  CHECK(steps.front().count("top.pivot_force_x") == 1);
  CHECK(force(steps.back(), "top.pivot_force").norm() > 0.0);
}

TEST_CASE("pivot scene: the ODE integrators run a pivoted body and end where IDA does") {
  const auto dir = test::fresh_temp_dir("pivot-ode");
  const auto scene = dir / "pivoted.toml";
  {
    std::ofstream out(scene);
    out << pivoted_top();
  }
  const auto quaternion = [](const std::map<std::string, std::string>& row) {
    return Vec4(std::stod(row.at("top.qw")), std::stod(row.at("top.qx")), std::stod(row.at("top.qy")),
                std::stod(row.at("top.qz")));
  };
  const auto ida = test::run_cli("solve " + scene.string() + " --quiet --rtol 1e-11 --atol 1e-11 --out " +
                                 (dir / "ida").string());
  INFO(ida.output);
  REQUIRE(ida.exit_code == 0);
  const Vec4 q_ida = quaternion(test::read_csv_rows(dir / "ida" / "trajectory.csv").back());
  for (const std::string integrator : {"arkode-erk", "cvode-adams"}) {
    CAPTURE(integrator);
    const auto r = test::run_cli("solve " + scene.string() + " --quiet --integrator " + integrator +
                                 " --scheme index1 --rtol 1e-10 --atol 1e-10 --out " + (dir / integrator).string());
    INFO(r.output);
    REQUIRE(r.exit_code == 0);
    const Vec4 q = quaternion(test::read_csv_rows(dir / integrator / "trajectory.csv").back());
    // Measured by hand: 5e-8 (both) against IDA at rtol 1e-10 over 0.2 s.
    CHECK(std::min((q - q_ida).norm(), (q + q_ida).norm()) < 1e-6);
  }
}

TEST_SUITE_END();
