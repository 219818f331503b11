// Schema-2 scenes (bodies, joints, springs, loads): the shipped scenes load,
// the loader's space-to-body conversion is right, the shipped initial states
// satisfy their joints, and the checks across values (bodies named by
// joints, pairs of joints, welds) give positioned messages. The one-line
// hostile files are in tests/bad_scenes/ (mb_*.toml), run through the CLI by
// test_bad_input.cpp.
#include <doctest/doctest.h>
#include <fmt/format.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "rigidae/core/error.hpp"
#include "rigidae/io/scene_loader.hpp"
#include "rigidae/multibody/assembly.hpp"
#include "rigidae/multibody/multibody_problem.hpp"
#include "rigidae/so3/euler_sequence.hpp"
#include "rigidae/so3/rotation.hpp"

TEST_SUITE_BEGIN("system");

using namespace rigidae;
namespace fs = std::filesystem;

namespace {

const fs::path kProblems = fs::path(RIGIDAE_SOURCE_DIR) / "problems";

std::string error_of(const std::string& text) {
  try {
    (void)io::parse_scene(text, "mb.toml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

#define CHECK_MB_ERROR(text, line, ...)                                              \
  do {                                                                               \
    const std::string msg_ = error_of(text);                                         \
    INFO("message: ", msg_);                                                         \
    CHECK(msg_.rfind(fmt::format("mb.toml:{}:", line), 0) == 0);                     \
    CHECK(msg_.find(": error: ") != std::string::npos);                              \
    for (const char* hint_ : std::vector<const char*>{__VA_ARGS__})                  \
      CHECK(msg_.find(hint_) != std::string::npos);                                  \
  } while (0)

struct Pose {
  Mat3 R = Mat3::Identity();
  Vec3 x = Vec3::Zero(), v = Vec3::Zero(), w = Vec3::Zero();  // w in space
};

Pose pose(const MultibodySpec& s, int body) {
  if (body == kGround) return {};
  const BodySpec& b = s.bodies[static_cast<std::size_t>(body)];
  return {b.R0_WB, b.x0_W, b.v0_W, b.R0_WB * b.omega0_B};
}

// Every joint of a loaded scene, checked at the initial pose in space,
// independently of how the loader computed it: the two points coincide, the
// axes are unit and (where one axis serves both bodies) the same line, the
// normals unit, perpendicular to their axes and equal in space -- except
// a revolute joint's normals in a URDF scene (`revolute_at_zero` false),
// which are one vector of the URDF joint frame, so that the angle between
// them is the URDF joint position (test_urdf.cpp checks that).
void check_joint_geometry(const MultibodySpec& s, bool revolute_at_zero = true) {
  for (const JointSpec& j : s.joints) {
    CAPTURE(j.name);
    const Pose a = pose(s, j.body_a), b = pose(s, j.body_b);
    if (j.type->axes == JointAxes::TwoPoints)  // a rod: its ends at its length
      CHECK(std::abs((a.R * j.point_a + a.x - (b.R * j.point_b + b.x)).norm() - j.length) < 1e-12);
    else
      CHECK((a.R * j.point_a + a.x - (b.R * j.point_b + b.x)).norm() < 1e-12);
    CHECK(std::abs(j.axis_a.norm() - 1.0) < 1e-14);
    CHECK(std::abs(j.axis_b.norm() - 1.0) < 1e-14);
    CHECK(std::abs(j.normal_a.norm() - 1.0) < 1e-14);
    CHECK(std::abs(j.normal_b.norm() - 1.0) < 1e-14);
    CHECK(std::abs(j.normal_a.dot(j.axis_a)) < 1e-14);
    CHECK(std::abs(j.normal_b.dot(j.axis_b)) < 1e-14);
    if (j.type == &joint_type("universal")) {
      CHECK(std::abs((a.R * j.axis_a).dot(b.R * j.axis_b)) < 1e-14);
    } else {
      CHECK((a.R * j.axis_a - b.R * j.axis_b).norm() < 1e-14);
      // An assembled start turned the bodies after the loader carried normal_a
      // to b at the guessed pose, and a URDF joint starts at its URDF angle: a
      // hinge's or cylinder's normals (the zero of its angle, no constraint)
      // then differ; a slider's and a weld's (rows) do not.
      const bool angle_zero_at_start = revolute_at_zero && !s.assembly.requested;
      if (angle_zero_at_start || (j.type->name != "revolute" && j.type->name != "cylindrical"))
        CHECK((a.R * j.normal_a - b.R * j.normal_b).norm() < 1e-14);
    }
  }
}

// The initial velocities satisfy each joint's velocity conditions: the
// relative twist of b with respect to a at the joint point lies in the
// motion the joint allows.
void check_joint_velocities(const MultibodySpec& s) {
  for (const JointSpec& j : s.joints) {
    CAPTURE(j.name);
    const Pose a = pose(s, j.body_a), b = pose(s, j.body_b);
    const Vec3 p = a.R * j.point_a + a.x;
    const Vec3 dv = (b.v + b.w.cross(p - b.x)) - (a.v + a.w.cross(p - a.x));
    const Vec3 dw = b.w - a.w;
    const Vec3 u = a.R * j.axis_a;
    const double tol = 1e-12 * (1.0 + a.v.norm() + b.v.norm() + a.w.norm() + b.w.norm());
    // The motion each type allows, written out here independently of its rows.
    const std::string_view t = j.type->name;
    if (t == "spherical") {
      CHECK(dv.norm() < tol);
    } else if (t == "revolute") {
      CHECK(dv.norm() < tol);
      CHECK(dw.cross(u).norm() < tol);
    } else if (t == "universal") {
      CHECK(dv.norm() < tol);
      CHECK(std::abs(dw.dot(u.cross(b.R * j.axis_b))) < tol);
    } else if (t == "prismatic") {
      CHECK(dv.cross(u).norm() < tol);
      CHECK(dw.norm() < tol);
    } else if (t == "cylindrical") {
      CHECK(dv.cross(u).norm() < tol);
      CHECK(dw.cross(u).norm() < tol);
    } else if (t == "fixed") {
      CHECK(dv.norm() < tol);
      CHECK(dw.norm() < tol);
    } else if (t == "distance") {
      // The rod's ends p_a, p_b: no stretching rate along p_b - p_a.
      const Vec3 pb = b.R * j.point_b + b.x;
      const Vec3 rate = (b.v + b.w.cross(pb - b.x)) - (a.v + a.w.cross(p - a.x));
      CHECK(std::abs(rate.dot(pb - p)) < tol * (1.0 + (pb - p).norm()));
    } else {
      FAIL("no velocity check for joint type ", t);
    }
  }
}

std::vector<fs::path> multibody_problems() {
  std::vector<fs::path> out;
  for (const auto& e : fs::directory_iterator(kProblems)) {
    if (e.path().extension() != ".toml") continue;
    std::ifstream in(e.path());
    std::stringstream ss;
    ss << in.rdbuf();
    if (ss.str().find("\nschema_version = 2") != std::string::npos) out.push_back(e.path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

// A two-body scene around one joint block; line numbers: the joint table
// starts on line 13.
std::string two_bodies(const std::string& joint, const std::string& body_b_extra = "") {
  return "schema_version = 2\n"                                     // 1
         "[[bodies]]\n"                                             // 2
         "name = \"arm\"\n"                                         // 3
         "mass = 1.0\n"                                             // 4
         "inertia_principal = [0.1, 0.2, 0.25]\n"                   // 5
         "position = [1.0, 2.0, 3.0]\n"                             // 6
         "euler = { sequence = \"zyx\", angles = [0.3, -0.7, 1.1] }\n"  // 7
         "[[bodies]]\n"                                             // 8
         "name = \"hand\"\n"                                        // 9
         "mass = 2.0\n"                                             // 10
         "inertia = [[0.3, 0.01, 0.0], [0.01, 0.2, 0.02], [0.0, 0.02, 0.25]]\n"  // 11
         "position = [1.5, 2.5, 2.0]\n" +                           // 12
         body_b_extra + joint + "[time]\nend = 1.0\n";
}

}  // namespace

TEST_CASE("schema 2: every shipped multibody scene loads, its joints meet in space and its start is consistent") {
  const auto files = multibody_problems();
  CHECK(files.size() >= 5);
  for (const fs::path& f : files) {
    CAPTURE(f.string());
    Scene s = io::load_scene(f.string());
    REQUIRE(s.multibody.has_value());
    CHECK(!s.multibody->bodies.empty());
    CHECK(s.name == f.stem().string());
    CHECK(s.schema_version == 2);
    std::ifstream in(f);
    std::stringstream text;
    text << in.rdbuf();
    const bool from_urdf = text.str().find("\n[urdf]") != std::string::npos;
    // A scene that asks for an assembled start gives guesses: its start is the assembled one.
    if (s.multibody->assembly.requested) multibody::assemble_start(*s.multibody);
    check_joint_geometry(*s.multibody, !from_urdf);
    check_joint_velocities(*s.multibody);
  }
}

TEST_CASE("schema 2: the absolute heavy top is problems/heavy_top.toml's body on a spherical joint") {
  const Scene top = io::load_scene((kProblems / "heavy_top.toml").string());
  const Scene abs = io::load_scene((kProblems / "heavy_top_absolute.toml").string());
  REQUIRE(abs.multibody.has_value());
  const MultibodySpec& s = *abs.multibody;
  REQUIRE(s.bodies.size() == 1);
  REQUIRE(s.joints.size() == 1);
  const BodySpec& b = s.bodies[0];
  CHECK(b.mass == top.body.mass);
  CHECK(b.inertia_com == top.body.inertia_com);
  CHECK((b.R0_WB - top.R0_WB).norm() == 0.0);
  CHECK(b.omega0_B == top.omega0_B);
  // The centre of mass sits at R c from the pivot and moves at w x (R c).
  const Vec3 r = top.R0_WB * top.body.com_B;
  CHECK((b.x0_W - r).norm() < 1e-15);
  CHECK((b.v0_W - (top.R0_WB * top.omega0_B).cross(r)).norm() < 1e-12);
  const JointSpec& j = s.joints[0];
  CHECK(j.type == &joint_type("spherical"));
  CHECK(j.body_a == kGround);
  CHECK(j.body_b == 0);
  CHECK(j.point_a.norm() == 0.0);
  CHECK((j.point_b + top.body.com_B).norm() < 1e-15);  // the pivot, from the centre of mass
  CHECK(s.gravity_W == top.gravity_W);
  CHECK(abs.formulation.scheme == top.formulation.scheme);
  CHECK(abs.time.end == top.time.end);
}

TEST_CASE("schema 2: points and axes given in space are converted into each body's frame") {
  // A revolute joint at a space point on two rotated, displaced bodies.
  const Vec3 p(1.2, 2.1, 2.6), axis = Vec3(1.0, -2.0, 0.5).normalized();
  const Scene s = io::parse_scene(
      two_bodies("[[joints]]\nname = \"wrist\"\ntype = \"revolute\"\nbodies = [\"arm\", \"hand\"]\n"
                 "point = [1.2, 2.1, 2.6]\naxis = [2.0, -4.0, 1.0]\n",
                 "axis_angle = { axis = [1.0, 1.0, 0.0], angle = 2.0 }\n"),
      "mb.toml");
  const MultibodySpec& m = *s.multibody;
  const Mat3 Ra = so3::euler_to_matrix(so3::parse_euler_sequence("zyx", false, nullptr), Vec3(0.3, -0.7, 1.1));
  const Mat3 Rb = so3::axis_angle_to_matrix(Vec3(1, 1, 0).normalized(), 2.0);
  CHECK((m.bodies[0].R0_WB - Ra).norm() < 1e-15);
  CHECK((m.bodies[1].R0_WB - Rb).norm() < 1e-15);
  const JointSpec& j = m.joints[0];
  CHECK(j.body_a == 0);
  CHECK(j.body_b == 1);
  // Back in space, both body-frame points are the given point, both axes the given axis.
  CHECK((Ra * j.point_a + Vec3(1, 2, 3) - p).norm() < 1e-12);
  CHECK((Rb * j.point_b + Vec3(1.5, 2.5, 2.0) - p).norm() < 1e-12);
  CHECK((Ra * j.axis_a - axis).norm() < 1e-15);
  CHECK((Rb * j.axis_b - axis).norm() < 1e-15);
  // The body-frame values are not the space ones (the bodies are rotated).
  CHECK((j.axis_a - axis).norm() > 0.1);
  check_joint_geometry(m);
  // The full inertia tensor is kept (body axes), symmetric as given.
  CHECK(m.bodies[1].inertia_com(0, 1) == 0.01);
}

TEST_CASE("schema 2: frame = \"body\" keeps the points and axes as given and fills the normals") {
  const Scene s = io::parse_scene(
      two_bodies("[[joints]]\ntype = \"prismatic\"\nbodies = [\"arm\", \"hand\"]\nframe = \"body\"\n"
                 "point_a = [0.1, 0.0, 0.0]\npoint_b = [0.0, -0.2, 0.0]\naxis_a = [0.0, 0.0, 3.0]\n"
                 "axis_b = [1.0, 0.0, 0.0]\nnormal_a = [1.0, 0.0, 0.0]\n"),
      "mb.toml");
  const JointSpec& j = s.multibody->joints[0];
  CHECK(j.name == "joint1");  // the default name
  CHECK(j.point_a == Vec3(0.1, 0.0, 0.0));
  CHECK(j.point_b == Vec3(0.0, -0.2, 0.0));
  CHECK(j.axis_a == Vec3(0.0, 0.0, 1.0));
  CHECK(j.axis_b == Vec3(1.0, 0.0, 0.0));
  CHECK(j.normal_a == Vec3(1.0, 0.0, 0.0));
  CHECK(std::abs(j.normal_b.norm() - 1.0) < 1e-14);
  CHECK(std::abs(j.normal_b.dot(j.axis_b)) < 1e-14);
}

TEST_CASE("schema 2: principal moments along given axes, velocities, frames and overrides") {
  const Scene s = io::load_scene((kProblems / "slider_mechanism.toml").string());
  const MultibodySpec& m = *s.multibody;
  const BodySpec& rod = m.bodies[1];
  const Vec3 e = Vec3(0.8498365855987976, 0.16666666666666669, 0.5);
  // The moment about the rod's own axis is the axial one, about a normal the transverse one.
  CHECK(std::abs(e.dot(rod.inertia_com * e) - 1.6e-05) < 1e-18);
  CHECK(std::abs(Vec3(0, 0, 1).cross(e).normalized().dot(rod.inertia_com * Vec3(0, 0, 1).cross(e).normalized()) -
                 0.003758) < 1e-15);
  REQUIRE(m.springs.size() == 1);
  CHECK(m.springs[0].body_a == kGround);
  CHECK(m.springs[0].point_a == Vec3(0.6, 0.05, 0.15));  // ground: space
  CHECK(m.springs[0].point_b.norm() < 1e-15);            // at the slider's centre of mass
  CHECK(m.springs[0].rest_length == 0.25);
  REQUIRE(m.loads.size() == 1);
  CHECK(m.loads[0].body == 0);
  CHECK(m.loads[0].torque == Vec3(0, 0, 0.05));
  CHECK_FALSE(m.loads[0].body_frame);
  CHECK(m.joints[0].torsion_damping == 0.002);

  // Space-frame angular velocity (the default) becomes body components; a
  // spring's rest length defaults to its initial length; per-body coordinates.
  const Scene t = io::parse_scene(
      two_bodies("[[springs]]\nbodies = [\"arm\", \"ground\"]\npoint_a = [1.0, 2.0, 3.5]\npoint_b = [1.0, 2.0, 6.5]\n"
                 "stiffness = 10.0\n",
                 "angular_velocity = [0.0, 0.0, 2.0]\ncoordinates = \"linear\"\n"),
      "mb.toml");
  const BodySpec& hand = t.multibody->bodies[1];
  CHECK((hand.omega0_B - hand.R0_WB.transpose() * Vec3(0, 0, 2)).norm() < 1e-15);
  CHECK(hand.coordinates == Coordinates::Linear);
  CHECK_FALSE(t.multibody->bodies[0].coordinates.has_value());
  CHECK(t.multibody->springs[0].name == "spring1");
  CHECK(std::abs(t.multibody->springs[0].rest_length - 3.0) < 1e-15);
  CHECK((t.multibody->bodies[0].R0_WB * t.multibody->springs[0].point_a - Vec3(0, 0, 0.5)).norm() < 1e-15);
}

TEST_CASE("schema 2: tools/make_chain.py writes chains that load, up to 1000 links") {
  const fs::path dir = rigidae::test::fresh_temp_dir("make_chain");
  for (const auto& [n, joint] : std::vector<std::pair<int, std::string>>{{3, "revolute"}, {1000, "spherical"}}) {
    CAPTURE(n);
    const fs::path out = dir / fmt::format("chain_{}.toml", n);
    const std::string cmd = fmt::format("/usr/bin/python3 '{}/tools/make_chain.py' {} --joint {} --out '{}' > /dev/null",
                                        RIGIDAE_SOURCE_DIR, n, joint, out.string());
    REQUIRE(std::system(cmd.c_str()) == 0);
    const Scene s = io::load_scene(out.string());
    REQUIRE(s.multibody.has_value());
    CHECK(s.multibody->bodies.size() == static_cast<std::size_t>(n));
    CHECK(s.multibody->joints.size() == static_cast<std::size_t>(n));
    CHECK(s.multibody->bodies.back().name == fmt::format("link{}", n));
    CHECK(s.multibody->joints[0].body_a == kGround);
    check_joint_geometry(*s.multibody);
    check_joint_velocities(*s.multibody);
  }
  // The shipped chain is the generator's output.
  const fs::path again = dir / "chain_10.toml";
  REQUIRE(std::system(fmt::format("/usr/bin/python3 '{}/tools/make_chain.py' 10 --out '{}' > /dev/null",
                                  RIGIDAE_SOURCE_DIR, again.string()).c_str()) == 0);
  CHECK(rigidae::test::read_file(again) == rigidae::test::read_file(kProblems / "chain_10.toml"));
  fs::remove_all(dir);
}

TEST_CASE("schema 2: joints naming missing bodies, zero axes and skew normals are positioned errors") {
  CHECK_MB_ERROR(two_bodies("[[joints]]\ntype = \"spherical\"\nbodies = [\"arm\", \"hnad\"]\npoint = [0.0, 0.0, 0.0]\n"),
                 15, "'joints[0].bodies[1]' = \"hnad\" is not a body of this scene; did you mean \"hand\"?",
                 "'arm', 'hand' or 'ground'");
  CHECK_MB_ERROR(two_bodies("[[joints]]\ntype = \"revolute\"\nbodies = [\"arm\", \"hand\"]\npoint = [0.0, 0.0, 0.0]\n"
                            "axis = [0.0, 0.0, 0.0]\n"),
                 17, "'joints[0].axis' must be a non-zero vector");
  CHECK_MB_ERROR(two_bodies("[[joints]]\ntype = \"revolute\"\nbodies = [\"arm\", \"hand\"]\nframe = \"body\"\n"
                            "point_a = [0.0, 0.0, 0.0]\npoint_b = [0.0, 0.0, 0.0]\naxis_a = [0.0, 0.0, 1.0]\n"
                            "axis_b = [0.0, 0.0, 1.0]\nnormal_a = [1.0, 0.0, 0.1]\n"),
                 21, "'joints[0].normal_a' must be perpendicular to 'joints[0].axis_a'", "84.2894 degrees",
                 "or leave it out");
  CHECK_MB_ERROR(two_bodies("[[joints]]\ntype = \"universal\"\nbodies = [\"arm\", \"hand\"]\npoint = [0.0, 0.0, 0.0]\n"
                            "axis_a = [1.0, 0.0, 0.0]\naxis_b = [1.0, 1.0, 0.0]\n"),
                 18, "'joints[0].axis_b' must be perpendicular to 'joints[0].axis_a'", "45 degrees");
  CHECK_MB_ERROR(two_bodies("[[joints]]\ntype = \"spherical\"\nbodies = [\"hand\", \"hand\"]\npoint = [0.0, 0.0, 0.0]\n"),
                 15, "names \"hand\" twice");
  CHECK_MB_ERROR(two_bodies("[[joints]]\ntype = \"spherical\"\nbodies = [\"arm\", \"hand\"]\naxis = [0.0, 0.0, 1.0]\n"
                            "point = [0.0, 0.0, 0.0]\n"),
                 16, "'joints[0].axis' does not apply to a spherical joint: a spherical joint has no axis",
                 "(its keys: 'name', 'type', 'bodies', 'frame' or 'point')");
  CHECK_MB_ERROR(two_bodies("[[joints]]\ntype = \"hinge\"\n"), 14, "is not valid", "'revolute'");
}

TEST_CASE("schema 2: joints on one pair of bodies that repeat or fight each other are refused") {
  const std::string hinge_z = "[[joints]]\nname = \"h1\"\ntype = \"revolute\"\nbodies = [\"arm\", \"hand\"]\n"
                              "point = [1.0, 2.0, 3.0]\naxis = [0.0, 0.0, 1.0]\n";  // lines 13..18
  // The same hinge twice at the same point: a copy, refused.
  CHECK_MB_ERROR(two_bodies(hinge_z + "[[joints]]\nname = \"h2\"\ntype = \"revolute\"\nbodies = [\"hand\", \"arm\"]\n"
                                      "point = [1.0, 2.0, 3.0]\naxis = [0.0, 0.0, -2.0]\n"),
                 19, "joint \"h2\" repeats what joint \"h1\" (line 13) already imposes between \"hand\" and \"arm\"",
                 "the same joint twice");
  // On the same axis further along (a door's two hinges, a shaft's two
  // bearings): accepted as redundancy (test_minimum_norm_reactions.cpp runs one).
  CHECK_NOTHROW(io::parse_scene(two_bodies(hinge_z + "[[joints]]\nname = \"h2\"\ntype = \"revolute\"\n"
                                                     "bodies = [\"hand\", \"arm\"]\npoint = [1.0, 2.0, 4.0]\n"
                                                     "axis = [0.0, 0.0, -2.0]\n"),
                                "two_hinges.toml"));
  // Two hinges with different axes: no motion left, 4 conditions redundant.
  CHECK_MB_ERROR(two_bodies(hinge_z + "[[joints]]\nname = \"h2\"\ntype = \"revolute\"\nbodies = [\"arm\", \"hand\"]\n"
                                      "point = [1.0, 2.0, 3.0]\naxis = [1.0, 0.0, 0.0]\n"),
                 19, "joint \"h2\" fights \"h1\" (line 13)", "10 conditions", "only 6 are independent",
                 "leaving 0 degrees of freedom", "use one 'fixed' joint");
  // Two ball joints at different points: a hinge about the line through them, one condition redundant.
  CHECK_MB_ERROR(two_bodies("[[joints]]\nname = \"b1\"\ntype = \"spherical\"\nbodies = [\"arm\", \"hand\"]\n"
                            "point = [0.0, 0.0, 0.0]\n[[joints]]\nname = \"b2\"\ntype = \"spherical\"\n"
                            "bodies = [\"arm\", \"hand\"]\npoint = [1.0, 0.0, 0.0]\n"),
                 18, "joint \"b2\" fights \"b1\"", "6 conditions", "only 5 are independent", "leaving 1 degree of freedom");
  // With these six types any two joints on one pair depend on each other (the
  // fewest rows, two ball joints, already leave a hinge: 6 rows of rank 5).
  // Joints on different pairs are never compared.
  const Scene ok = io::parse_scene(
      two_bodies(hinge_z + "[[joints]]\nname = \"c\"\ntype = \"cylindrical\"\nbodies = [\"arm\", \"ground\"]\n"
                           "point = [0.0, 0.0, 0.0]\naxis = [1.0, 0.0, 0.0]\n"),
      "mb.toml");
  CHECK(ok.multibody->joints.size() == 2);
}

TEST_CASE("schema 2: a body welded to the ground, directly or through other welds, is refused") {
  CHECK_MB_ERROR(two_bodies("[[joints]]\nname = \"w\"\ntype = \"fixed\"\nbodies = [\"ground\", \"hand\"]\n"
                            "point = [0.0, 0.0, 0.0]\n"),
                 13, "fixed joint \"w\" welds body \"hand\" to the ground: it cannot move");
  CHECK_MB_ERROR(two_bodies("[[joints]]\nname = \"w1\"\ntype = \"fixed\"\nbodies = [\"arm\", \"hand\"]\n"
                            "point = [0.0, 0.0, 0.0]\n[[joints]]\nname = \"w2\"\ntype = \"fixed\"\n"
                            "bodies = [\"ground\", \"arm\"]\npoint = [1.0, 0.0, 0.0]\n"),
                 18, "fixed joint \"w2\" welds bodies \"arm\" and \"hand\" to the ground (with the fixed joints that "
                 "join them): they cannot move");
  // Two bodies welded together move as one: fine.
  const Scene ok = io::parse_scene(two_bodies("[[joints]]\ntype = \"fixed\"\nbodies = [\"arm\", \"hand\"]\n"
                                              "point = [0.0, 0.0, 0.0]\n"),
                                   "mb.toml");
  check_joint_geometry(*ok.multibody);
}

TEST_CASE("schema 2: names are folder-safe, unique and not 'ground'") {
  CHECK_MB_ERROR(two_bodies("", "[[bodies]]\nname = \"ARM\"\nmass = 1.0\ninertia_principal = [1.0, 1.0, 1.0]\n"
                                "position = [0.0, 0.0, 0.0]\n"),
                 14, "duplicate name \"ARM\": the body \"arm\" (line 2) has it already");
  CHECK_MB_ERROR(two_bodies("[[joints]]\nname = \"hand\"\ntype = \"spherical\"\nbodies = [\"arm\", \"hand\"]\n"
                            "point = [0.0, 0.0, 0.0]\n"),
                 14, "duplicate name \"hand\": the body \"hand\" (line 8)");
  std::string text = two_bodies("");
  text.replace(text.find("\"hand\""), 6, "\"../hand\"");
  CHECK_MB_ERROR(text, 9, "cannot name output columns and folders");
  text = two_bodies("");
  text.replace(text.find("\"hand\""), 6, "\"Ground\"");
  CHECK_MB_ERROR(text, 9, "is reserved");
}

TEST_CASE("schema 2: version, tables and keys") {
  // A file of bodies without its version is told which version it needs.
  std::string text = two_bodies("");
  text.erase(0, text.find('\n') + 1);
  CHECK_MB_ERROR(text, 1, "missing required key 'schema_version'", "schema_version = 2");
  CHECK_MB_ERROR("schema_version = 3\n", 1, "reads schema_version = 1 (one body) or 2 (bodies and joints)");
  CHECK_MB_ERROR("schema_version = 2\n[time]\nend = 1.0\n", 1, "missing [[bodies]]");
  CHECK_MB_ERROR("schema_version = 2\n[bodies]\nname = \"a\"\n", 2, "'bodies' must be an array of tables");
  CHECK_MB_ERROR(two_bodies("", "possition = [0.0, 0.0, 0.0]\n"), 13, "did you mean 'position'?");
  CHECK_MB_ERROR(two_bodies("", "rtol = 1e-6\n"), 13, "'rtol' belongs in [solver]");
  CHECK_MB_ERROR(two_bodies("", "inertia_axes = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]\n"), 13,
                 "'bodies[1].inertia_axes' goes with 'bodies[1].inertia_principal'");
  CHECK_MB_ERROR(two_bodies("", "quaternion = [1.0, 0.0, 0.0, 0.0]\nmatrix = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]\n"),
                 14, "bodies[1] has several orientations ('quaternion' and 'matrix')");
  CHECK_MB_ERROR("reference = \"exact\"\n" + two_bodies(""), 1, "no closed-form solution");
  CHECK_MB_ERROR(two_bodies("[[loads]]\nbody = \"ground\"\nforce = [1.0, 0.0, 0.0]\n"), 14, "the ground does not move");
  CHECK_MB_ERROR(two_bodies("[[loads]]\nbody = \"arm\"\n"), 13, "needs 'force'");
  // The body's inertia obeys the triangle inequality; a flat one (J3 = J1 + J2) is accepted.
  std::string flat = two_bodies("");
  flat.replace(flat.find("[0.1, 0.2, 0.25]"), 16, "[0.1, 0.2, 0.3]");
  CHECK(io::parse_scene(flat, "mb.toml").multibody->bodies[0].inertia_com(2, 2) == 0.3);
  flat.replace(flat.find("[0.1, 0.2, 0.3]"), 15, "[0.1, 0.2, 0.4]");
  CHECK_MB_ERROR(flat, 5, "violate the triangle inequality");
}

TEST_CASE("schema 2: a nearly perpendicular normal or pin is corrected with a warning that says how far off") {
  std::ostringstream captured;
  std::streambuf* old = std::cerr.rdbuf(captured.rdbuf());
  Scene s;
  try {
    s = io::parse_scene(two_bodies("[[joints]]\ntype = \"universal\"\nbodies = [\"arm\", \"hand\"]\npoint = [1.0, 2.0, 3.0]\n"
                                   "axis_a = [1.0, 0.0, 0.0]\naxis_b = [1e-9, 1.0, 0.0]\n"),
                        "mb.toml");
  } catch (...) {
    std::cerr.rdbuf(old);
    throw;
  }
  std::cerr.rdbuf(old);
  INFO(captured.str());
  CHECK(captured.str().rfind("mb.toml:18:10: warning: 'joints[0].axis_b' is 1e-09 rad from perpendicular", 0) == 0);
  const MultibodySpec& m = *s.multibody;
  const JointSpec& j = m.joints[0];
  CHECK(std::abs((m.bodies[0].R0_WB * j.axis_a).dot(m.bodies[1].R0_WB * j.axis_b)) < 1e-16);
  CHECK((m.bodies[1].R0_WB * j.axis_b - Vec3::UnitY()).norm() < 1e-15);
}

TEST_CASE("schema 2: hostile inputs are reported as given (schema 1 with bodies, a velocity of 1e300, a velocity that breaks a joint)") {
  const std::string pendulum = rigidae::test::read_file(kProblems / "double_pendulum.toml");
  // schema_version = 1 in a file of [[bodies]]: told to write 2, at the version's line.
  std::string one = pendulum;
  const std::size_t ver = one.find("schema_version = 2");
  REQUIRE(ver != std::string::npos);
  one.replace(ver, 18, "schema_version = 1");
  const int ver_line = 1 + static_cast<int>(std::count(one.begin(), one.begin() + static_cast<long>(ver), '\n'));
  CHECK_MB_ERROR(one, ver_line, "schema_version = 1 is a scene of one body", "write schema_version = 2");
  // A velocity of 1e300 m/s: its size as given (1e+300), not the overflow of its square.
  std::string huge = pendulum;
  const std::size_t v = huge.find("\nvelocity = [0.0, 0.5, 0.0]");
  REQUIRE(v != std::string::npos);
  huge.replace(v, 27, "\nvelocity = [0.0, 1e300, 0.0]");
  const int v_line = 2 + static_cast<int>(std::count(huge.begin(), huge.begin() + static_cast<long>(v), '\n'));
  CHECK_MB_ERROR(huge, v_line, "= 1e+300 m/s is too large");
  CHECK(error_of(huge).find("inf") == std::string::npos);
  // A velocity the joints forbid: projected, and the warning names the body and its table's line.
  std::string off = pendulum;
  off.replace(v, 27, "\nvelocity = [0.0, 0.5, 0.3]");
  multibody::MultibodyProblem p(io::parse_scene(off, "mb.toml"));
  bool named = false;
  for (const std::string& w : p.warnings())
    if (w.find("the initial velocities violated the joints") != std::string::npos) {
      CAPTURE(w);
      named = w.rfind("mb.toml:", 0) == 0 && w.find("body '") != std::string::npos;
    }
  CHECK(named);
}

TEST_SUITE_END();
