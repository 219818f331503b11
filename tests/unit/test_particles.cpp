// Point masses ([[bodies]] kind = "particle", multibody/point_mass.hpp) and
// the distance joint, at the loader and in the assembler's reports: what a
// particle accepts and refuses (positioned errors naming the key and what is
// valid), its columns, its mobility count. The exact matrix is checked in
// test_multibody_jacobians.cpp, the motion in test_particle_pendulum.cpp.
#include <doctest/doctest.h>

#include <string>
#include <tuple>

#include "cli_runner.hpp"
#include "rigidae/app/compare.hpp"
#include "rigidae/app/solve.hpp"
#include "rigidae/core/error.hpp"
#include "rigidae/io/scene_loader.hpp"
#include "rigidae/multibody/multibody_problem.hpp"

TEST_SUITE_BEGIN("system");

using namespace rigidae;

namespace {

// A particle "p" at (1, 0, 0) and a rigid body "r" at (0, 0, -1), with the
// given joints and extra text.
std::string scene(const std::string& particle_extra, const std::string& rest) {
  return "schema_version = 2\nname = \"t\"\n"
         "[[bodies]]\nname = \"p\"\nkind = \"particle\"\nmass = 0.5\nposition = [1.0, 0.0, 0.0]\n" +
         particle_extra +
         "\n[[bodies]]\nname = \"r\"\nmass = 1.0\ninertia_principal = [0.1, 0.1, 0.1]\nposition = [0.0, 0.0, -1.0]\n" +
         rest + "\n[time]\nend = 0.1\noutput_step = 0.05\n";
}

std::string error_of(const std::string& text) {
  try {
    io::parse_scene(text, "p.toml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

const std::string kRod = "\n[[joints]]\nname = \"rod\"\ntype = \"distance\"\nbodies = [\"ground\", \"p\"]\npoint_a = [0, 0, 0]\n";

}  // namespace

TEST_CASE("particles: the loader keeps mass, position, velocity, and a distance joint's length defaults to the initial distance") {
  const Scene s = io::parse_scene(scene("velocity = [0.0, 0.3, 0.0]", kRod), "p.toml");
  const MultibodySpec& m = *s.multibody;
  CHECK(m.bodies[0].particle);
  CHECK_FALSE(m.bodies[1].particle);
  CHECK(m.bodies[0].inertia_com.isZero(0.0));
  CHECK(m.bodies[0].v0_W == Vec3(0.0, 0.3, 0.0));
  CHECK(m.joints[0].length == 1.0);
  CHECK(m.joints[0].point_b == Vec3::Zero());  // the particle's position
  const Scene l = io::parse_scene(scene("", kRod + "length = 1.0\n"), "p.toml");
  CHECK(l.multibody->joints[0].length == 1.0);
}

TEST_CASE("particles: what a particle refuses, positioned and naming what is valid") {
  const std::string inertia = error_of(scene("inertia_principal = [1, 1, 1]", ""));
  CHECK(inertia.find("p.toml:") == 0);
  CHECK(inertia.find("does not apply to a particle") != std::string::npos);
  CHECK(inertia.find("'mass', 'position', 'velocity'") != std::string::npos);
  CHECK(error_of(scene("angular_velocity = [0, 0, 1]", "")).find("does not apply to a particle") != std::string::npos);
  CHECK(error_of(scene("kind = \"point\"", "")).find("kind") != std::string::npos);
  // A joint that needs an axis on the particle.
  const std::string hinge = error_of(scene("", "\n[[joints]]\nname = \"h\"\ntype = \"revolute\"\nbodies = [\"ground\", "
                                               "\"p\"]\npoint = [1, 0, 0]\naxis = [0, 1, 0]\n"));
  CHECK(hinge.find("p.toml:") == 0);
  CHECK(hinge.find("joint \"h\" (revolute) needs an orientation of \"p\", which is a particle") != std::string::npos);
  CHECK(hinge.find("joints that can hold a particle: 'spherical' or 'distance'") != std::string::npos);
  CHECK(error_of(scene("", "\n[[joints]]\nname = \"w\"\ntype = \"fixed\"\nbodies = [\"r\", \"p\"]\npoint = [1, 0, 0]\n"))
            .find("needs an orientation") != std::string::npos);
  // A spherical joint away from the particle's position.
  const std::string ball = error_of(scene("", "\n[[joints]]\nname = \"b\"\ntype = \"spherical\"\nbodies = [\"r\", "
                                              "\"p\"]\npoint = [0.5, 0, 0]\n"));
  CHECK(ball.find("a point mass has no extent") != std::string::npos);
  // Loads: no torque, no body frame.
  CHECK(error_of(scene("", "\n[[loads]]\nbody = \"p\"\ntorque = [0, 0, 1]\n")).find("no rotation for a torque") !=
        std::string::npos);
  CHECK(error_of(scene("", "\n[[loads]]\nbody = \"p\"\nforce = [0, 0, 1]\nframe = \"body\"\n")).find("no body frame") !=
        std::string::npos);
  // A spring off the particle's position.
  CHECK(error_of(scene("", "\n[[springs]]\nbodies = [\"ground\", \"p\"]\npoint_a = [0, 0, 0]\npoint_b = [1, 0.5, 0]\n"
                           "stiffness = 10\n"))
            .find("a point mass has no extent") != std::string::npos);
  // Distance joints: no 'point', no zero length, 'length' only on them.
  CHECK(error_of(scene("", kRod + "point = [0, 0, 0]\n")).find("does not apply to a distance joint") != std::string::npos);
  CHECK(error_of(scene("", "\n[[joints]]\ntype = \"distance\"\nbodies = [\"ground\", \"p\"]\npoint_a = [1, 0, 0]\n"))
            .find("coincide at the initial pose") != std::string::npos);
  CHECK(error_of(scene("", "\n[[joints]]\ntype = \"spherical\"\nbodies = [\"ground\", \"r\"]\npoint = [0, 0, 0]\n"
                           "length = 1\n"))
            .find("'length' is a distance joint's") != std::string::npos);
  // A rigid body's end of a rod is required.
  CHECK(error_of(scene("", "\n[[joints]]\ntype = \"distance\"\nbodies = [\"r\", \"p\"]\n")).find("point_a") !=
        std::string::npos);
}

TEST_CASE("particles: 3 velocities each in the mobility, position and velocity columns only") {
  // p on a rod to the ground; r on a rod from p to r's centre of mass.
  const Scene s = io::parse_scene(
      scene("", kRod + "\n[[joints]]\nname = \"rod2\"\ntype = \"distance\"\nbodies = [\"p\", \"r\"]\npoint_b = [0, 0, -1]\n"),
      "p.toml");
  multibody::MultibodyProblem p(s);
  // Gruebler-Kutzbach: 3 (p) + 6 (r) - 1 - 1 = 7 = velocities - rank.
  CHECK(p.redundancy().velocities == 3 + 3 + p.bodies()[1].nvr);
  CHECK(p.redundancy().gruebler_dof == 7);
  CHECK(p.redundancy().rank_dof == 7);
  const std::vector<std::string> names = p.output_names();
  CHECK(names[0] == "p.x");
  CHECK(names[5] == "p.vz");
  CHECK(names[6] == "r.qw");
  CHECK(names.size() == 6 + 13 + 2 * 8 + 7);
  CHECK(p.output_units().size() == names.size());
}

TEST_CASE("particles: rigidae export --mjcf refuses a particle, naming it") {
  const auto dir = test::fresh_temp_dir("particle-mjcf");
  const auto r = test::run_cli("export --mjcf " + std::string(RIGIDAE_SOURCE_DIR) + "/problems/particle_pendulum.toml -o " +
                               (dir / "x.xml").string());
  CHECK(r.exit_code != 0);
  CHECK(r.output.find("body \"bob\" is a particle") != std::string::npos);
}

// compare runs a mechanism of particles alone once per scheme and
// integrator: without rotation coordinates the coordinates and the form do
// not enter its equations. Checked where it matters: two runs that compare
// leaves out are the kept run bit for bit (steps and final state).
TEST_CASE("particles: compare runs a particles-only mechanism once per scheme and integrator, the runs it leaves out being identical") {
  const Scene s = io::load_scene(std::string(RIGIDAE_SOURCE_DIR) + "/problems/particle_pendulum.toml");
  const std::vector<Combination> combos = combinations_for(s, default_integrators(s));
  Scene rigid = s;
  rigid.multibody->bodies[0].particle = false;
  const std::size_t all = combinations_for(rigid, default_integrators(rigid)).size();
  CHECK(combos.size() * 6 == all);  // 3 coordinate sets x 2 forms
  for (const Combination& c : combos) {
    CHECK(c.coordinates == s.formulation.coordinates);
    CHECK(c.equations == s.formulation.equations);
  }
  const auto run = [&](Coordinates c, Equations e, const std::string& name) {
    Scene x = s;
    x.time.end = 3.0;
    x.formulation.coordinates = c;
    x.formulation.equations = e;
    return solve_scene(x, test::fresh_temp_dir("particle_combination_" + name));
  };
  const SolveOutcome kept = run(s.formulation.coordinates, s.formulation.equations, "kept");
  for (const auto& [c, e, name] : {std::tuple{Coordinates::EulerAngles, Equations::Lagrange, "euler_lagrange"},
                                   std::tuple{Coordinates::Linear, Equations::Euler, "linear_euler"}}) {
    CAPTURE(name);
    const SolveOutcome other = run(c, e, name);
    REQUIRE(other.run.status == RunStatus::Success);
    CHECK(other.run.counters.steps == kept.run.counters.steps);
    CHECK(other.run.counters.residual_evals == kept.run.counters.residual_evals);
    // Every output row, every digit (bodies, the rod's reaction, energy, momenta).
    CHECK(test::read_file(other.out_dir / "trajectory.csv") == test::read_file(kept.out_dir / "trajectory.csv"));
  }
}

TEST_SUITE_END();
