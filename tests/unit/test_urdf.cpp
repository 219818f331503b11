// URDF import (rigidae/io/urdf.hpp) and MJCF export (rigidae/io/mjcf_export.hpp):
// the merging of fixed and massless links against a hand computation, the
// initial pose and rates against hand forward kinematics, the ground and
// floating-base rules, positioned errors for bad files, and the export's
// refusals. The MuJoCo comparison is tests/mujoco/mujoco_check.cpp.
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "rigidae/core/error.hpp"
#include "rigidae/io/mjcf_export.hpp"
#include "rigidae/io/scene_loader.hpp"
#include "rigidae/io/urdf.hpp"
#include "rigidae/so3/rotation.hpp"

TEST_SUITE_BEGIN("unit");

using namespace rigidae;

namespace {

MultibodySpec from_text(const std::string& urdf, const io::UrdfOptions& options = {}) {
  return io::urdf_to_multibody(io::parse_urdf(urdf, "test.urdf"), options);
}

// The message of the InputError that `f` throws ("" if none).
template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

std::string inertial(double mass, const char* xyz, const char* rpy, const char* inertia) {
  return std::string("<inertial><origin xyz=\"") + xyz + "\" rpy=\"" + rpy + "\"/><mass value=\"" +
         std::to_string(mass) + "\"/><inertia " + inertia + "/></inertial>";
}

// base (fixed to the ground) -j-> a -fixed-> b -fixed-> c (massless).
const std::string kMerge = std::string(R"(<robot name="merge">
  <link name="base"/>
  <joint name="j" type="continuous"><parent link="base"/><child link="a"/><axis xyz="0 0 1"/></joint>
  <link name="a">)") + inertial(2.0, "0.1 0 0", "0 0 0", R"(ixx="0.01" iyy="0.02" izz="0.03")") + R"(</link>
  <joint name="weld" type="fixed"><parent link="a"/><child link="b"/>
    <origin xyz="0.5 0.1 0" rpy="0 0 1.5707963267948966"/></joint>
  <link name="b">)" + inertial(1.0, "0 0.2 0", "0 0 0", R"(ixx="0.004" iyy="0.005" izz="0.006")") + R"(</link>
  <joint name="tip" type="fixed"><parent link="b"/><child link="c"/><origin xyz="0 0 1"/></joint>
  <link name="c"/>
</robot>)";

}  // namespace

TEST_CASE("urdf: links joined by fixed joints merge into one body (mass, centre of mass, inertia by hand)") {
  const MultibodySpec s = from_text(kMerge);
  REQUIRE(s.bodies.size() == 1);
  REQUIRE(s.joints.size() == 1);
  const BodySpec& b = s.bodies[0];
  CHECK(b.name == "a");
  // By hand, in a's frame: a's centre at (0.1, 0, 0), b's at (0.5, 0.1, 0) +
  // Rz(90 deg) (0, 0.2, 0) = (0.3, 0.1, 0); b's moments turn to (0.005, 0.004, 0.006).
  // m = 3, c = (0.5 / 3, 0.1 / 3, 0); d_a = (-1/15, -1/30, 0), d_b = (2/15, 1/15, 0);
  // sum m dx^2 = 6/225, sum m dy^2 = 1/150, sum m dx dy = 1/75.
  CHECK(b.mass == doctest::Approx(3.0).epsilon(1e-15));
  CHECK((b.x0_W - Vec3(0.5 / 3.0, 0.1 / 3.0, 0.0)).norm() < 1e-15);
  Mat3 I;
  I << 0.015 + 1.0 / 150.0, -1.0 / 75.0, 0.0,  //
      -1.0 / 75.0, 0.024 + 6.0 / 225.0, 0.0,   //
      0.0, 0.0, 0.036 + 6.0 / 225.0 + 1.0 / 150.0;
  CHECK((b.inertia_com - I).norm() < 1e-15);
  CHECK((b.R0_WB - Mat3::Identity()).norm() == 0.0);
  // The joint: at the ground's origin, about z, on a at -c from its centre of mass.
  const JointSpec& j = s.joints[0];
  CHECK(j.type->name == "revolute");
  CHECK(j.body_a == kGround);
  CHECK(j.body_b == 0);
  CHECK(j.point_a.norm() == 0.0);
  CHECK((j.point_b + Vec3(0.5 / 3.0, 0.1 / 3.0, 0.0)).norm() < 1e-15);
  CHECK((j.axis_a - Vec3::UnitZ()).norm() == 0.0);
  CHECK(!j.limits.has_value());  // continuous: no range
  CHECK(s.expected_dof == 1);
}

TEST_CASE("urdf: combine_mass_parts is the parallel-axis theorem (two point masses on a line)") {
  // Two point masses m at +-L on x: I = diag(0, 2 m L^2, 2 m L^2) about the middle.
  const auto c = io::combine_mass_parts({{1.5, Vec3(0.4, 0, 0), Mat3::Zero()}, {1.5, Vec3(-0.4, 0, 0), Mat3::Zero()}});
  CHECK(c.mass == 3.0);
  CHECK(c.com.norm() == 0.0);
  CHECK(c.inertia(0, 0) == 0.0);
  CHECK(c.inertia(1, 1) == doctest::Approx(2 * 1.5 * 0.16).epsilon(1e-15));
  CHECK(c.inertia(2, 2) == doctest::Approx(2 * 1.5 * 0.16).epsilon(1e-15));
}

TEST_CASE("urdf: initial joint positions and rates by forward kinematics (revolute then prismatic)") {
  // Ground -shoulder (about z at (0,0,1))-> arm (centre 0.3 along x)
  //        -slide (along the arm's x, from x = 0.5)-> slider (centre at its origin).
  const std::string urdf = std::string(R"(<robot name="fk"><link name="base"/>
    <joint name="shoulder" type="revolute"><parent link="base"/><child link="arm"/><origin xyz="0 0 1"/>
      <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="10" velocity="2"/></joint>
    <link name="arm">)") + inertial(1.0, "0.3 0 0", "0 0 0", R"(ixx="0.01" iyy="0.01" izz="0.01")") +
                           R"(</link>
    <joint name="slide" type="prismatic"><parent link="arm"/><child link="slider"/><origin xyz="0.5 0 0"/>
      <axis xyz="1 0 0"/><limit lower="0" upper="0.2" effort="10" velocity="1"/></joint>
    <link name="slider">)" + inertial(0.5, "0 0 0", "0 0 0", R"(ixx="0.001" iyy="0.001" izz="0.001")") +
                           "</link></robot>";
  io::UrdfOptions o;
  const double q = 0.4, qd = 2.0, s = 0.1, sd = -0.3;
  o.positions = {{"shoulder", q, ""}, {"slide", s, ""}};
  o.velocities = {{"shoulder", qd, ""}, {"slide", sd, ""}};
  const MultibodySpec m = from_text(urdf, o);
  REQUIRE(m.bodies.size() == 2);
  const Vec3 ex(std::cos(q), std::sin(q), 0.0), ey(-std::sin(q), std::cos(q), 0.0);
  CHECK((m.bodies[0].x0_W - (Vec3(0, 0, 1) + 0.3 * ex)).norm() < 1e-15);
  CHECK((m.bodies[1].x0_W - (Vec3(0, 0, 1) + (0.5 + s) * ex)).norm() < 1e-15);
  CHECK((m.bodies[0].v0_W - 0.3 * qd * ey).norm() < 1e-15);
  CHECK((m.bodies[1].v0_W - ((0.5 + s) * qd * ey + sd * ex)).norm() < 1e-15);
  CHECK((m.bodies[1].omega0_B - Vec3(0, 0, qd)).norm() < 1e-15);
  CHECK(so3::rotation_distance(m.bodies[1].R0_WB, so3::axis_rotation(2, q)) < 1e-15);
  // Limits kept as data; the prismatic joint's points are s apart along the axis.
  REQUIRE(m.joints[1].limits.has_value());
  CHECK(*m.joints[1].limits->upper == 0.2);
  const Vec3 pa = m.bodies[0].R0_WB * m.joints[1].point_a + m.bodies[0].x0_W;
  const Vec3 pb = m.bodies[1].R0_WB * m.joints[1].point_b + m.bodies[1].x0_W;
  CHECK(((pb - pa) - s * ex).norm() < 1e-15);
  // The revolute joint's angle (atan2 of the normals, as torsion.cpp measures it) is q.
  const JointSpec& j = m.joints[0];
  const Vec3 na = j.normal_a, nb = m.bodies[0].R0_WB * j.normal_b, za = j.axis_a;
  CHECK(std::atan2(za.cross(na).dot(nb), na.dot(nb)) == doctest::Approx(q).epsilon(1e-14));
}

TEST_CASE("urdf: the ground and floating-base rules") {
  const std::string link = inertial(1.0, "0 0 0.1", "0 0 0", R"(ixx="0.01" iyy="0.01" izz="0.01")");
  const std::string body = "<link name=\"body\">" + link + "</link>";
  // No `world` link: the root is fixed to the ground (nothing moves) unless base = floating.
  CHECK(error_of([&] { from_text("<robot name=\"r\">" + body + "</robot>"); }).find("nothing moves") !=
        std::string::npos);
  io::UrdfOptions floating;
  floating.base = io::UrdfBase::Floating;
  const MultibodySpec free = from_text("<robot name=\"r\">" + body + "</robot>", floating);
  CHECK(free.bodies.size() == 1);
  CHECK(free.joints.empty());
  CHECK(free.expected_dof == 6);
  // A `world` link decides: a floating joint out of it frees the base at its origin.
  const MultibodySpec w = from_text(R"(<robot name="r"><link name="world"/>
      <joint name="free" type="floating"><parent link="world"/><child link="body"/><origin xyz="1 2 3"/></joint>)" +
                                    body + "</robot>");
  CHECK(w.joints.empty());
  CHECK((w.bodies[0].x0_W - Vec3(1, 2, 3.1)).norm() < 1e-15);
  // ...and then 'base' is refused: the file says already.
  CHECK(error_of([&] {
          from_text("<robot name=\"r\"><link name=\"world\"/>" + body +
                        "<joint name=\"f\" type=\"floating\"><parent link=\"world\"/><child link=\"body\"/></joint></robot>",
                    floating);
        }).find("remove 'base'") != std::string::npos);
  // A fixed joint to `world` welds the base to the ground: a link hinged to it moves.
  const MultibodySpec fixed = from_text(R"(<robot name="r"><link name="world"/>
      <joint name="bolt" type="fixed"><parent link="world"/><child link="base"/></joint><link name="base"/>
      <joint name="hinge" type="continuous"><parent link="base"/><child link="body"/><axis xyz="1 0 0"/></joint>)" +
                                        body + "</robot>");
  REQUIRE(fixed.joints.size() == 1);
  CHECK(fixed.joints[0].body_a == kGround);
}

TEST_CASE("urdf: a massless leaf on a joint is dropped, a massless link carrying mass is refused") {
  const std::string heavy = inertial(1.0, "0 0 0.1", "0 0 0", R"(ixx="0.01" iyy="0.01" izz="0.01")");
  const MultibodySpec s = from_text(R"(<robot name="r"><link name="base"/>
      <joint name="j1" type="continuous"><parent link="base"/><child link="arm"/></joint><link name="arm">)" +
                                    heavy + R"(</link>
      <joint name="j2" type="continuous"><parent link="arm"/><child link="frame"/></joint><link name="frame"/></robot>)");
  CHECK(s.bodies.size() == 1);
  CHECK(s.joints.size() == 1);
  const std::string e = error_of([&] {
    from_text(R"(<robot name="r"><link name="base"/>
      <joint name="j1" type="continuous"><parent link="base"/><child link="ghost"/></joint><link name="ghost"/>
      <joint name="j2" type="continuous"><parent link="ghost"/><child link="arm"/></joint><link name="arm">)" +
              heavy + "</link></robot>");
  });
  CHECK(e.find("test.urdf:2: error: <link name=\"ghost\"> has no mass") == 0);
}

TEST_CASE("urdf: bad files give file, line, element and what would be valid") {
  struct Case {
    std::string urdf, expected;
  };
  const std::string ok_link = "<link name=\"b\">" +
                              inertial(1.0, "0 0 0", "0 0 0", R"(ixx="0.01" iyy="0.01" izz="0.01")") + "</link>";
  const std::vector<Case> cases{
      {"<robot name=\"r\"><link name=\"a\"/>\n<joint name=\"j\" type=\"revolut\"><parent link=\"a\"/><child "
       "link=\"b\"/></joint>" + ok_link + "</robot>",
       "test.urdf:2: error: <joint name=\"j\">: type=\"revolut\" is not a URDF joint type; did you mean \"revolute\"?"},
      {"<robot name=\"r\"><link name=\"a\"/>\n<joint name=\"j\" type=\"continuous\"><parent link=\"aa\"/><child "
       "link=\"b\"/></joint>" + ok_link + "</robot>",
       "test.urdf:2: error: <joint name=\"j\">: <parent link=\"aa\"> names no link of this robot; did you mean \"a\"?"},
      {"<robot name=\"r\">\n<link name=\"a\"><inertial>\n<mass value=\"-1\"/><inertia ixx=\"1\" iyy=\"1\" izz=\"1\"/>"
       "</inertial></link></robot>",
       "test.urdf:3: error: <mass> in <link name=\"a\">: value=\"-1\": a mass must lie in [0, "},
      {"<robot name=\"r\">\n<link name=\"a\"><inertial><mass value=\"1\"/>\n<inertia ixx=\"1\" iyy=\"1\" "
       "izz=\"3\"/></inertial></link></robot>",
       "test.urdf:3: error: <inertia> in <link name=\"a\">: no mass distribution has this inertia"},
      {"<robot name=\"r\"><link name=\"a\"/>\n<joint name=\"j\" type=\"continuous\"><parent link=\"a\"/><child "
       "link=\"b\"/>\n<axis xyz=\"0 0 0\"/></joint>" + ok_link + "</robot>",
       "test.urdf:3: error: <axis> in <joint name=\"j\">: xyz=\"0 0 0\" is no direction"},
      {"<robot name=\"r\"><link name=\"a\"/>\n<joint name=\"j\" type=\"revolute\"><parent link=\"a\"/><child "
       "link=\"b\"/></joint>" + ok_link + "</robot>",
       "test.urdf:2: error: <joint name=\"j\">: a revolute joint needs <limit"},
      {"<robot name=\"r\"><link name=\"a\"/>\n<joint name=\"j\" type=\"planar\"><parent link=\"a\"/><child "
       "link=\"b\"/></joint>" + ok_link + "</robot>",
       "test.urdf:2: error: <joint name=\"j\">: type=\"planar\" is not supported"},
      {"<robot name=\"r\"><link name=\"a\"/><link name=\"c\"/>" + ok_link +
           "\n<joint name=\"j\" type=\"continuous\"><parent link=\"a\"/><child link=\"b\"/></joint>"
           "\n<joint name=\"k\" type=\"continuous\"><parent link=\"c\"/><child link=\"b\"/></joint></robot>",
       "test.urdf:3: error: <joint name=\"k\">: link \"b\" is already the child of <joint name=\"j\"> (line 2)"},
      {"<robot name=\"r\"><link name=\"a\"/>\n<link name=\"a\"/></robot>",
       "test.urdf:2: error: <link name=\"a\">: a second link named \"a\" (the first is on line 1)"},
      {"<robot name=\"r\">\n<link name=\"a\">\n<inertial><mass value=\"1\"/></link></robot>",
       "test.urdf:3: error: not well-formed XML"},
      {"<robot name=\"r\"><link name=\"a\"/>\n<joint name=\"j\" type=\"continuous\"><parent link=\"a\"/><child "
       "link=\"b\"/><origin xyz=\"0 0\"/></joint>" + ok_link + "</robot>",
       "test.urdf:2: error: <origin> in <joint name=\"j\">: xyz=\"0 0\" must be three numbers"},
  };
  for (const Case& c : cases) {
    CAPTURE(c.urdf);
    const std::string e = error_of([&] { from_text(c.urdf); });
    CHECK(e.substr(0, c.expected.size()) == c.expected);
  }
}

TEST_CASE("urdf: a TOML scene with [urdf]: joint names checked at their position") {
  const std::string dir = std::string(RIGIDAE_SOURCE_DIR) + "/problems/";
  const Scene ok = io::load_scene(dir + "arm6.toml");
  REQUIRE(ok.multibody.has_value());
  CHECK(ok.multibody->bodies.size() == 6);  // the tool merged into link6
  CHECK(ok.multibody->joints.size() == 6);
  CHECK(ok.time.end == 1.0);
  CHECK(ok.schema_version == 2);  // as the [urdf] scene file says
  const std::string text = "schema_version = 2\n[urdf]\nfile = \"arm6.urdf\"\npositions = { elbw = 0.1 }\n"
                           "[time]\nend = 1.0\n";
  const std::string e = error_of([&] { io::parse_scene(text, dir + "bad_arm.toml"); });
  CHECK(e.find("bad_arm.toml:4:") != std::string::npos);
  CHECK(e.find("did you mean \"elbow\"?") != std::string::npos);
  // The .urdf file alone is a scene with default run settings.
  const Scene direct = io::load_scene(dir + "arm6.urdf");
  CHECK(direct.multibody->bodies.size() == 6);
  CHECK(direct.schema_version == 2);  // no version of its own: read as a scene of bodies and joints
  CHECK(direct.name == "arm6");
}

TEST_CASE("mjcf export: trees only, refusals named") {
  const std::string dir = std::string(RIGIDAE_SOURCE_DIR) + "/problems/";
  const std::string loop = error_of([&] { io::mjcf_files(io::load_scene(dir + "four_bar.toml"), {}, "m.xml"); });
  CHECK(loop.find("closes a loop") != std::string::npos);
  // A one-body scene is written as the system it runs as: the top on a ball
  // joint at the fixed point, the body frame at its centre of mass (0, 1, 0),
  // the joint 1 m below it along -y, the start the scene's (tests/mujoco/
  // runs the model against rigidae's run).
  const auto top = io::mjcf_files(io::load_scene(dir + "heavy_top.toml"), {}, "m.xml");
  REQUIRE(top.size() == 1);
  const std::string& xml = top[0].second;
  CHECK(xml.find("<body name=\"body\" pos=\"0 1 0\" quat=\"1 0 0 0\">") != std::string::npos);
  CHECK(xml.find("<joint name=\"body_pivot\" type=\"ball\" pos=\"0 -1 0\"/>") != std::string::npos);
  CHECK(xml.find("mass=\"15\" diaginertia=") != std::string::npos);
  CHECK(xml.find("qpos=\"1 0 0 0\" qvel=\"0 150 -4.61538") != std::string::npos);
  CHECK(xml.find("freejoint") == std::string::npos);
  // A free body: the ball joint at its centre of mass.
  const auto free = io::mjcf_files(io::load_scene(dir + "free_body.toml"), {}, "m.xml");
  CHECK(free[0].second.find("<joint name=\"body_pivot\" type=\"ball\" pos=\"0 0 0\"/>") != std::string::npos);
  // A pivoted body that a joint also holds to the ground closes a loop.
  const std::string pivot_loop =
      error_of([&] { io::mjcf_files(io::load_scene(dir + "pendulum_1000_pivot.toml"), {}, "m.xml"); });
  CHECK(pivot_loop.find("closes a loop") != std::string::npos);
  // A 100-link chain continues in <include>d files (MuJoCo's XML nesting limit):
  // 40 bodies in the model file, 40 in part 1, 20 in part 2.
  Scene chain;
  chain.name = "chain";
  chain.multibody = MultibodySpec{};
  for (int k = 0; k < 100; ++k) {
    BodySpec b;
    b.name = "link" + std::to_string(k + 1);
    b.inertia_com = 0.01 * Mat3::Identity();
    b.x0_W = Vec3(0.1 * k + 0.05, 0, 0);
    chain.multibody->bodies.push_back(b);
    JointSpec j;
    j.name = "joint" + std::to_string(k + 1);
    j.body_a = k - 1;
    j.body_b = k;
    j.type = &joint_type("spherical");
    j.point_a = k == 0 ? Vec3::Zero() : Vec3(0.05, 0, 0);
    j.point_b = Vec3(-0.05, 0, 0);
    chain.multibody->joints.push_back(j);
  }
  const auto files = io::mjcf_files(chain, {}, "chain.xml");
  REQUIRE(files.size() == 3);
  const auto count = [](const std::string& text) {
    std::size_t n = 0;
    for (std::size_t k = text.find("<body "); k != std::string::npos; k = text.find("<body ", k + 1)) ++n;
    return n;
  };
  CHECK(count(files[0].second) == 40);
  CHECK(count(files[1].second) == 40);
  CHECK(count(files[2].second) == 20);
  CHECK(files[0].first == "chain.xml");
  CHECK(files[1].first == "chain.part1.xml");
  CHECK(files[0].second.find("<include file=\"chain.part1.xml\"/>") != std::string::npos);
  CHECK(files[1].second.find("<include file=\"chain.part2.xml\"/>") != std::string::npos);
  // Drivers and motors are functions of time that MJCF does not state:
  // refused at their table, not dropped (the export would move otherwise).
  Scene driven = chain;
  DriverSpec d;
  d.joint = 2;
  d.where = {"chain.toml", 41, 1};
  driven.multibody->drivers.push_back(d);
  const std::string driver = error_of([&] { io::mjcf_files(driven, {}, "m.xml"); });
  CHECK(driver.find("chain.toml:41:1: error: [[drivers]] on joint \"joint3\"") == 0);
  Scene motored = chain;
  motored.multibody->joints[4].motor_torque = 0.5;
  motored.multibody->joints[4].where = {"chain.toml", 57, 1};
  const std::string motor = error_of([&] { io::mjcf_files(motored, {}, "m.xml"); });
  CHECK(motor.find("chain.toml:57:1: error: joint \"joint5\" has a motor (motor_torque)") == 0);
}

TEST_SUITE_END();
