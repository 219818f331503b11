// Scene files: parsing, defaults, orientation forms and every class of error.
#include <doctest/doctest.h>
#include <fmt/format.h>

#include <cmath>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "rigidae/core/error.hpp"
#include "rigidae/io/scene_loader.hpp"

TEST_SUITE_BEGIN("unit");

using namespace rigidae;

namespace {

// The message of the InputError that parsing `text` throws ("" if none).
std::string error_of(const std::string& text) {
  try {
    (void)io::parse_scene(text, "scene.toml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// Checks the message starts with "scene.toml:LINE:COL: error: " and contains every hint.
#define CHECK_SCENE_ERROR(text, line, col, ...)                                          \
  do {                                                                                   \
    const std::string msg_ = error_of(text);                                             \
    INFO("message: ", msg_);                                                             \
    CHECK(msg_.rfind(fmt::format("scene.toml:{}:{}: error: ", line, col), 0) == 0);      \
    for (const char* hint_ : std::vector<const char*>{__VA_ARGS__})                      \
      CHECK(msg_.find(hint_) != std::string::npos);                                      \
  } while (0)

// Redirects std::cerr for the lifetime of the object.
struct CerrCapture {
  std::ostringstream buf;
  std::streambuf* old;
  CerrCapture() : old(std::cerr.rdbuf(buf.rdbuf())) {}
  ~CerrCapture() { std::cerr.rdbuf(old); }
  std::string text() const { return buf.str(); }
};

// A minimal valid scene; line numbers are used by the tests below:
//  1 schema_version      5 [initial]              8 [time]
//  2 [body]              6 quaternion             9 end
//  3 mass                7 angular_velocity
//  4 inertia_principal
const std::string kBody = "[body]\nmass = 2.0\ninertia_principal = [2.0, 3.0, 4.0]\n";
const std::string kInitial = "[initial]\nquaternion = [1.0, 0.0, 0.0, 0.0]\nangular_velocity = [0.0, 0.0, 1.0]\n";
const std::string kTime = "[time]\nend = 1.0\n";
const std::string kMinimal = "schema_version = 1\n" + kBody + kInitial + kTime;

// Scene with the given [initial] orientation line(s) and a space-frame option.
std::string with_orientation(const std::string& orientation_lines) {
  return "schema_version = 1\n" + kBody + "[initial]\n" + orientation_lines +
         "\nangular_velocity = [0.0, 0.0, 1.0]\n" + kTime;
}

std::string g17(double x) { return fmt::format("{:.17g}", x); }

const char* kHeavyTop = R"(schema_version = 1
name = "heavy_top"
description = "heavy top"
[body]
mass = 15.0
inertia_principal = [0.234375, 0.46875, 0.234375]
center_of_mass = [0.0, 1.0, 0.0]
[support]
type = "fixed_point"
[gravity]
acceleration = [0.0, 0.0, -9.81]
[initial]
quaternion = [1.0, 0.0, 0.0, 0.0]
angular_velocity = [0.0, 150.0, -4.61538]
angular_velocity_frame = "body"
[time]
start = 0.0
end = 2.0
output_step = 0.01
[formulation]
coordinates = "quaternion"
equations = "euler"
scheme = "ggl"
[solver]
rtol = 1e-8
atol = 1e-8
)";

void check_heavy_top(const Scene& s) {
  CHECK(s.name == "heavy_top");
  CHECK(s.body.mass == 15.0);
  CHECK(s.body.inertia_com.isApprox(Vec3(0.234375, 0.46875, 0.234375).asDiagonal().toDenseMatrix()));
  CHECK(s.body.com_B == Vec3(0, 1, 0));
  CHECK(s.support == Support::FixedPoint);
  CHECK(s.gravity_W == Vec3(0, 0, -9.81));
  CHECK(s.R0_WB.isApprox(Mat3::Identity(), 1e-15));
  CHECK(s.omega0_B == Vec3(0, 150, -4.61538));
  CHECK(s.time.start == 0.0);
  CHECK(s.time.end == 2.0);
  CHECK(s.time.output_step == 0.01);
  CHECK(s.formulation.coordinates == Coordinates::Quaternion);
  CHECK(s.formulation.equations == Equations::Euler);
  CHECK(s.formulation.scheme == "ggl");
  CHECK(s.solver.rtol == 1e-8);
  CHECK(s.solver.atol == 1e-8);
}

}  // namespace

TEST_CASE("scene loader: the heavy top loads with the right values") {
  const Scene s = io::parse_scene(kHeavyTop, "mem.toml");
  CHECK(s.source == "mem.toml");
  CHECK(s.description == "heavy top");
  check_heavy_top(s);
}

TEST_CASE("scene loader: problems/heavy_top.toml and problems/free_body.toml load from disk") {
  const std::string dir = std::string(RIGIDAE_SOURCE_DIR) + "/problems/";
  const Scene top = io::load_scene(dir + "heavy_top.toml");
  CHECK(top.source == dir + "heavy_top.toml");
  CHECK(top.schema_version == 1);  // the loader records the file's version (summary.json says it)
  check_heavy_top(top);

  const Scene free = io::load_scene(dir + "free_body.toml");
  CHECK(free.name == "free_body");
  CHECK(free.support == Support::Free);
  CHECK(free.body.inertia_com.diagonal() == Vec3(2, 3, 4));
  CHECK(free.time.end == 20.0);
}

TEST_CASE("scene loader: a missing scene file is reported by name") {
  try {
    (void)io::load_scene("/nonexistent/dir/no_scene.toml");
    FAIL("expected an InputError");
  } catch (const InputError& e) {
    const std::string msg = e.what();
    CHECK(msg.find("/nonexistent/dir/no_scene.toml") == 0);
    CHECK(msg.find("cannot open") != std::string::npos);
  }
}

TEST_CASE("scene loader: defaults of optional keys") {
  const Scene s = io::parse_scene(kMinimal, "dir/minimal.toml");
  CHECK(s.name == "minimal");
  CHECK(s.description.empty());
  CHECK(s.body.com_B == Vec3::Zero());
  CHECK(s.support == Support::FixedPoint);
  CHECK(s.gravity_W == Vec3(0, 0, -9.81));
  CHECK(s.time.start == 0.0);
  CHECK(s.time.output_step == doctest::Approx(0.01));
  CHECK(s.formulation.coordinates == Coordinates::Quaternion);
  CHECK(s.formulation.equations == Equations::Lagrange);
  CHECK(s.formulation.scheme == "ggl");
  CHECK_FALSE(s.formulation.euler.sequence.has_value());
  CHECK(s.formulation.euler.switching);
  CHECK(s.formulation.euler.switch_threshold == 0.1);
  CHECK(s.solver.rtol == 1e-8);
  CHECK(s.solver.atol == 1e-8);
  CHECK(s.solver.max_steps == 10'000'000);
  CHECK(s.solver.max_order == 5);
  CHECK(s.solver.initial_step == 0.0);
  CHECK(s.omega0_B == Vec3(0, 0, 1));
}

TEST_CASE("scene loader: formulation and solver keys are read") {
  const std::string text = kMinimal + R"([formulation]
coordinates = "euler"
equations = "lagrange"
scheme = "index1"
[formulation.euler_angles]
sequence = "zyx"
convention = "extrinsic"
switching = false
switch_threshold = 0.25
[solver]
rtol = 1e-6
atol = 1e-9
max_steps = 5000
max_order = 3
initial_step = 1e-5
)";
  const Scene s = io::parse_scene(text, "scene.toml");
  CHECK(s.formulation.coordinates == Coordinates::EulerAngles);
  CHECK(s.formulation.scheme == "index1");
  REQUIRE(s.formulation.euler.sequence.has_value());
  CHECK(s.formulation.euler.sequence->name() == "xyz");  // extrinsic z-y-x = intrinsic x-y-z
  CHECK_FALSE(s.formulation.euler.switching);
  CHECK(s.formulation.euler.switch_threshold == 0.25);
  CHECK(s.solver.rtol == 1e-6);
  CHECK(s.solver.atol == 1e-9);
  CHECK(s.solver.max_steps == 5000);
  CHECK(s.solver.max_order == 3);
  CHECK(s.solver.initial_step == 1e-5);

  const Scene a = io::parse_scene(kMinimal + "[formulation.euler_angles]\nsequence = \"auto\"\n", "scene.toml");
  CHECK_FALSE(a.formulation.euler.sequence.has_value());
}

TEST_CASE("scene loader: a TOML syntax error names its line and column") {
  CHECK_SCENE_ERROR("schema_version = 1\n[body]\nmass = = 2.0\n", 3, 8, "invalid TOML");
  CHECK_SCENE_ERROR("schema_version = 1\n[body\n", 2, 6, "invalid TOML");
}

TEST_CASE("scene loader: a scene with an unknown key names its line and suggests the right key") {
  CHECK_SCENE_ERROR("schema_version = 1\n[body]\nmas = 2.0\ninertia_principal = [2.0, 3.0, 4.0]\n" + kInitial + kTime,
                    3, 1, "unknown key 'mas' in [body]", "did you mean 'mass'?");
  CHECK_SCENE_ERROR(kMinimal + "[solvr]\nrtol = 1e-6\n", 10, 2, "unknown key 'solvr'",
                    "did you mean 'solver'?");
  CHECK_SCENE_ERROR(kMinimal + "rtol = 1e-6\n", 10, 1, "unknown key 'rtol' in [time]",
                    "'rtol' belongs in [solver]");
  CHECK_SCENE_ERROR(kMinimal + "[formulation.euler_angle]\nsequence = \"zxz\"\n", 10, 14,
                    "unknown key 'euler_angle' in [formulation]", "did you mean 'euler_angles'?");
  CHECK_SCENE_ERROR(with_orientation("euler = { sequence = \"zxz\", angels = [0.1, 0.2, 0.3] }"), 6, 29,
                    "unknown key 'angels' in [initial.euler]", "did you mean 'angles'?");
  CHECK_SCENE_ERROR("schema_versoin = 1\n" + kBody + kInitial + kTime, 1, 1,
                    "did you mean 'schema_version'?");
}

TEST_CASE("scene loader: missing required keys point at the enclosing table") {
  CHECK_SCENE_ERROR("schema_version = 1\n" + kBody + kInitial, 1, 1, "missing required table [time]");
  CHECK_SCENE_ERROR("schema_version = 1\n" + kBody + kInitial + "[time]\nstart = 0.0\n", 8, 1,
                    "missing required key 'end' in [time]");
  CHECK_SCENE_ERROR("schema_version = 1\n[body]\ninertia_principal = [2.0, 3.0, 4.0]\n" + kInitial + kTime, 2, 1,
                    "missing required key 'mass' in [body]", "kg");
  CHECK_SCENE_ERROR("schema_version = 1\n[body]\nmass = 2.0\n" + kInitial + kTime, 2, 1,
                    "inertia_principal", "inertia =");
  CHECK_SCENE_ERROR("schema_version = 1\n" + kBody + "[initial]\nangular_velocity = [0.0, 0.0, 1.0]\n" + kTime, 5, 1,
                    "needs an orientation", "'quaternion', 'euler', 'matrix' or 'axis_angle'");
  CHECK_SCENE_ERROR("schema_version = 1\n" + kBody + "[initial]\nquaternion = [1.0, 0.0, 0.0, 0.0]\n" + kTime, 5, 1,
                    "missing required key 'angular_velocity'");
  CHECK_SCENE_ERROR(kBody + kInitial + kTime, 1, 1, "missing required key 'schema_version'");
}

TEST_CASE("scene loader: schema_version must be the integer 1 (or 2, for bodies and joints)") {
  CHECK_SCENE_ERROR("schema_version = 3\n" + kBody + kInitial + kTime, 1, 18, "unsupported schema_version 3",
                    "schema_version = 1 (one body) or 2 (bodies and joints)");
  CHECK_SCENE_ERROR("schema_version = 2\n" + kBody + kInitial + kTime, 1, 18, "this file has schema 1's [body]",
                    "write schema_version = 1");
  CHECK_SCENE_ERROR("schema_version = 1.0\n" + kBody + kInitial + kTime, 1, 18, "must be an integer");
}

TEST_CASE("scene loader: wrong types and array lengths are rejected") {
  CHECK_SCENE_ERROR("schema_version = 1\n[body]\nmass = \"2.0\"\ninertia_principal = [2.0, 3.0, 4.0]\n" + kInitial + kTime,
                    3, 8, "'body.mass' must be a number, not a string");
  // An integer where a float is expected is fine.
  CHECK(io::parse_scene("schema_version = 1\n[body]\nmass = 2\ninertia_principal = [2, 3, 4]\n" + kInitial + kTime,
                        "scene.toml").body.mass == 2.0);
  // A float where an integer is expected is not.
  CHECK_SCENE_ERROR(kMinimal + "[solver]\nmax_steps = 1e6\n", 11, 13, "'solver.max_steps' must be an integer");
  CHECK_SCENE_ERROR(kMinimal + "[formulation.euler_angles]\nswitching = 1\n", 11, 13, "must be a boolean");
  CHECK_SCENE_ERROR("schema_version = 1\n" + kBody + "center_of_mass = [0.0, 1.0]\n" + kInitial + kTime, 5, 18,
                    "'body.center_of_mass' must have exactly 3 numbers, it has 2");
  CHECK_SCENE_ERROR("schema_version = 1\n" + kBody + "center_of_mass = [0.0, \"1\", 0.0]\n" + kInitial + kTime, 5, 24,
                    "'body.center_of_mass[1]' must be a number");
  CHECK_SCENE_ERROR("schema_version = 1\nbody = 3\n" + kInitial + kTime, 2, 8, "'body' must be a table");
  CHECK_SCENE_ERROR(with_orientation("quaternion = [1.0, 0.0, 0.0]"), 6, 14, "exactly 4 numbers");
  CHECK_SCENE_ERROR(kMinimal + "[support]\ntype = \"fixed\"\n", 11, 8, "'support.type'", "'fixed_point' or 'free'");
}

TEST_CASE("scene loader: NaN and infinity are rejected anywhere numeric") {
  CHECK_SCENE_ERROR("schema_version = 1\n[body]\nmass = nan\ninertia_principal = [2.0, 3.0, 4.0]\n" + kInitial + kTime,
                    3, 8, "finite");
  CHECK_SCENE_ERROR("schema_version = 1\n" + kBody + "[initial]\nquaternion = [1.0, 0.0, 0.0, 0.0]\n"
                    "angular_velocity = [0.0, inf, 0.0]\n" + kTime, 7, 26, "'initial.angular_velocity[1]'", "finite");
  CHECK_SCENE_ERROR(kMinimal + "[gravity]\nacceleration = [0.0, 0.0, -inf]\n", 11, 27, "finite");
  CHECK_SCENE_ERROR(kMinimal + "[solver]\nrtol = nan\n", 11, 8, "finite");
}

TEST_CASE("scene loader: mass must be positive and not absurd") {
  for (const char* m : {"0.0", "-1.0", "2e9"})
    CHECK_SCENE_ERROR(fmt::format("schema_version = 1\n[body]\nmass = {}\ninertia_principal = [2.0, 3.0, 4.0]\n", m) +
                          kInitial + kTime,
                      3, 8, "'body.mass' must be > 0 and < 1e+09 kg");
}

TEST_CASE("scene loader: inertia must be symmetric, positive definite and obey the triangle inequality") {
  const std::string head = "schema_version = 1\n[body]\nmass = 2.0\n";
  // Asymmetric: element [1][0] differs from [0][1].
  CHECK_SCENE_ERROR(head + "inertia = [[2.0, 0.1, 0.0],\n  [0.2, 3.0, 0.0],\n  [0.0, 0.0, 4.0]]\n" + kInitial + kTime,
                    5, 4, "must be symmetric", "[1][0]");
  // Not positive definite.
  CHECK_SCENE_ERROR(head + "inertia = [[2.0, 0.0, 0.0], [0.0, -3.0, 0.0], [0.0, 0.0, 4.0]]\n" + kInitial + kTime,
                    4, 11, "positive definite", "eigenvalues");
  CHECK_SCENE_ERROR(head + "inertia_principal = [2.0, 0.0, 4.0]\n" + kInitial + kTime, 4, 27, "must be > 0");
  // Violated triangle inequality: not a mass distribution at all.
  CHECK_SCENE_ERROR(head + "inertia_principal = [1.0, 2.0, 4.0]\n" + kInitial + kTime, 4, 21,
                    "triangle inequality", "J3 = 4");
  // A symmetric off-diagonal inertia is accepted and kept as given.
  const Scene s = io::parse_scene(
      head + "inertia = [[3.0, 0.5, 0.0], [0.5, 3.0, 0.0], [0.0, 0.0, 4.0]]\n" + kInitial + kTime, "scene.toml");
  CHECK(s.body.inertia_com(0, 1) == 0.5);
}

TEST_CASE("scene loader: a flat inertia (J3 = J1 + J2, a lamina) is accepted, beyond it refused") {
  const std::string head = "schema_version = 1\n[body]\nmass = 2.0\n";
  const Scene lamina = io::parse_scene(head + "inertia_principal = [2.0, 3.0, 5.0]\n" + kInitial + kTime, "scene.toml");
  CHECK(lamina.body.inertia_com.diagonal() == Vec3(2, 3, 5));
  // As a full matrix (J1 = J2 + J3), free, and about a fixed point in its plane.
  CHECK_NOTHROW(io::parse_scene(head + "inertia = [[1.0, 0.0, 0.0], [0.0, 0.5, 0.0], [0.0, 0.0, 0.5]]\n" + kInitial +
                                kTime, "scene.toml"));
  CHECK_NOTHROW(io::parse_scene(head + "inertia_principal = [2.0, 3.0, 5.0]\ncenter_of_mass = [0.0, 1.0, 0.0]\n"
                                "[support]\ntype = \"free\"\n" + kInitial + kTime, "scene.toml"));
  CHECK_NOTHROW(io::parse_scene(head + "inertia_principal = [2.0, 3.0, 5.0]\ncenter_of_mass = [1.0, 0.0, 0.0]\n" +
                                kInitial + kTime, "scene.toml"));
  // Past the lamina by more than round-off: no mass distribution.
  CHECK_SCENE_ERROR(head + "inertia_principal = [2.0, 3.0, 5.00000001]\n" + kInitial + kTime, 4, 21,
                    "violate the triangle inequality", "equality is a lamina");
}

TEST_CASE("scene loader: the four orientation forms give the same R0_WB") {
  // Intrinsic z-x-z with angles (a, b, c): R = Rz(a) Rx(b) Rz(c).
  const double a = 0.3, b = 0.5, c = -0.2;
  const Mat3 R = (Eigen::AngleAxisd(a, Vec3::UnitZ()) * Eigen::AngleAxisd(b, Vec3::UnitX()) *
                  Eigen::AngleAxisd(c, Vec3::UnitZ()))
                     .toRotationMatrix();
  const Eigen::Quaterniond q(R);
  const Eigen::AngleAxisd aa(R);

  const std::string quat = fmt::format("quaternion = [{}, {}, {}, {}]", g17(q.w()), g17(q.x()), g17(q.y()), g17(q.z()));
  const std::string mat = fmt::format("matrix = [[{}, {}, {}], [{}, {}, {}], [{}, {}, {}]]", g17(R(0, 0)), g17(R(0, 1)),
                                      g17(R(0, 2)), g17(R(1, 0)), g17(R(1, 1)), g17(R(1, 2)), g17(R(2, 0)),
                                      g17(R(2, 1)), g17(R(2, 2)));
  const std::string euler_in =
      fmt::format("euler = {{ sequence = \"zxz\", angles = [{}, {}, {}] }}", g17(a), g17(b), g17(c));
  // Extrinsic: about the fixed z by c, then fixed x by b, then fixed z by a.
  const std::string euler_ex = fmt::format(
      "euler = {{ sequence = \"ZXZ\", convention = \"extrinsic\", angles = [{}, {}, {}] }}", g17(c), g17(b), g17(a));
  // Axis not normalised: the loader normalises it.
  const Vec3 axis = 2.5 * aa.axis();
  const std::string axis_angle = fmt::format("axis_angle = {{ axis = [{}, {}, {}], angle = {} }}", g17(axis[0]),
                                             g17(axis[1]), g17(axis[2]), g17(aa.angle()));

  for (const std::string& form : {quat, mat, euler_in, euler_ex, axis_angle}) {
    INFO(form);
    const Scene s = io::parse_scene(with_orientation(form), "scene.toml");
    CHECK((s.R0_WB - R).norm() < 1e-14);
    CHECK((s.R0_WB.transpose() * s.R0_WB - Mat3::Identity()).norm() < 1e-14);
  }
  // A table header works as well as an inline table.
  const Scene t = io::parse_scene(
      "schema_version = 1\n" + kBody + "[initial]\nangular_velocity = [0.0, 0.0, 1.0]\n" +
          fmt::format("[initial.euler]\nsequence = \"zxz\"\nangles = [{}, {}, {}]\n", g17(a), g17(b), g17(c)) + kTime,
      "scene.toml");
  CHECK((t.R0_WB - R).norm() < 1e-14);
}

TEST_CASE("scene loader: several orientation forms or bad euler / axis-angle input are rejected") {
  CHECK_SCENE_ERROR(with_orientation("quaternion = [1.0, 0.0, 0.0, 0.0]\nmatrix = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]"),
                    7, 10, "several orientations", "'quaternion' and 'matrix'", "exactly one");
  CHECK_SCENE_ERROR(with_orientation("euler = { sequence = \"zzx\", angles = [0.1, 0.2, 0.3] }"), 6, 22,
                    "'initial.euler.sequence' = \"zzx\"");
  CHECK_SCENE_ERROR(with_orientation("euler = { sequence = \"abc\", angles = [0.1, 0.2, 0.3] }"), 6, 22,
                    "'initial.euler.sequence' = \"abc\"");
  CHECK_SCENE_ERROR(with_orientation("euler = { sequence = \"zxz\", convention = \"intrinsik\", angles = [0.1, 0.2, 0.3] }"),
                    6, 42, "did you mean \"intrinsic\"?");
  CHECK_SCENE_ERROR(with_orientation("euler = { sequence = \"zxz\" }"), 6, 9, "missing required key 'angles'");
  CHECK_SCENE_ERROR(with_orientation("euler = [0.1, 0.2, 0.3]"), 6, 9, "'initial.euler' must be a table");
  CHECK_SCENE_ERROR(with_orientation("axis_angle = { axis = [0.0, 0.0, 0.0], angle = 0.5 }"), 6, 23, "non-zero");
  CHECK_SCENE_ERROR(kMinimal + "[formulation.euler_angles]\nsequence = \"xx\"\n", 11, 12,
                    "'formulation.euler_angles.sequence' = \"xx\"");
  CHECK_SCENE_ERROR(kMinimal + "[formulation.euler_angles]\nswitch_threshold = 1.0\n", 11, 20, "(0, 1)");
}

TEST_CASE("scene loader: a near-unit quaternion is normalised with a warning, a far one rejected") {
  {
    CerrCapture cap;
    const Scene s = io::parse_scene(with_orientation("quaternion = [1.000000001, 0.0, 0.0, 0.0]"), "scene.toml");
    CHECK((s.R0_WB - Mat3::Identity()).norm() < 1e-15);
    CHECK(cap.text().find("scene.toml:6:14: warning:") != std::string::npos);
    CHECK(cap.text().find("normalised") != std::string::npos);
    CHECK(cap.text().find("1e-09") != std::string::npos);
  }
  {
    CerrCapture cap;  // within 1e-12: silently exact
    (void)io::parse_scene(with_orientation("quaternion = [1.0, 0.0, 0.0, 0.0]"), "scene.toml");
    CHECK(cap.text().empty());
  }
  CHECK_SCENE_ERROR(with_orientation("quaternion = [1.001, 0.0, 0.0, 0.0]"), 6, 14, "normalise it");
  CHECK_SCENE_ERROR(with_orientation("quaternion = [0.0, 0.0, 0.0, 0.0]"), 6, 14, "zero norm");
}

TEST_CASE("scene loader: a rotation matrix is checked, and a near-rotation replaced with a warning") {
  CHECK_SCENE_ERROR(with_orientation("matrix = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1.0]]"), 6, 10,
                    "a reflection, not a rotation");
  CHECK_SCENE_ERROR(with_orientation("matrix = [[1.0, 0.1, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]"), 6, 10,
                    "not orthogonal");
  CerrCapture cap;
  const Scene s = io::parse_scene(
      with_orientation("matrix = [[1.0, 1e-8, 0.0], [-1e-8, 1.0, 0.0], [0.0, 0.0, 1.0000001]]"), "scene.toml");
  CHECK((s.R0_WB.transpose() * s.R0_WB - Mat3::Identity()).norm() < 1e-14);
  CHECK(s.R0_WB.determinant() == doctest::Approx(1.0));
  CHECK(cap.text().find("scene.toml:6:10: warning:") != std::string::npos);
  CHECK(cap.text().find("nearest rotation") != std::string::npos);
}

TEST_CASE("scene loader: a space-frame angular velocity is converted to body components") {
  // R0 = rotation by 90 deg about z: body x = space y, body y = -space x.
  const std::string text = "schema_version = 1\n" + kBody +
                           "[initial]\naxis_angle = { axis = [0.0, 0.0, 1.0], angle = 1.5707963267948966 }\n"
                           "angular_velocity = [1.0, 2.0, 3.0]\nangular_velocity_frame = \"space\"\n" + kTime;
  const Scene s = io::parse_scene(text, "scene.toml");
  CHECK((s.omega0_B - Vec3(2.0, -1.0, 3.0)).norm() < 1e-14);
  CHECK((s.R0_WB * s.omega0_B - Vec3(1.0, 2.0, 3.0)).norm() < 1e-14);

  CHECK_SCENE_ERROR("schema_version = 1\n" + kBody + kInitial + "angular_velocity_frame = \"world\"\n" + kTime, 8, 26,
                    "'body' or 'space'");
}

TEST_CASE("scene loader: time grid, tolerances and scheme names are validated") {
  const std::string pre = "schema_version = 1\n" + kBody + kInitial;
  CHECK_SCENE_ERROR(pre + "[time]\nstart = 1.0\nend = 1.0\n", 10, 7, "greater than 'time.start'");
  CHECK_SCENE_ERROR(pre + "[time]\nend = 1.0\noutput_step = 0.0\n", 10, 15, "'time.output_step' = 0 must be > 0");
  CHECK_SCENE_ERROR(pre + "[time]\nend = 1.0\noutput_step = 2.0\n", 10, 15, "must be > 0 and <= end - start");
  CHECK(io::parse_scene(pre + "[time]\nstart = 1\nend = 3\n", "scene.toml").time.output_step == doctest::Approx(0.02));
  CHECK_SCENE_ERROR(kMinimal + "[solver]\nrtol = 1.5\n", 11, 8, "'solver.rtol' = 1.5 must lie in [1e-14, 1)");
  CHECK_SCENE_ERROR(kMinimal + "[solver]\natol = 0.0\n", 11, 8, "'solver.atol'", "[1e-100, 1)");
  CHECK_SCENE_ERROR(kMinimal + "[solver]\nmax_order = 6\n", 11, 13, "from 1 to 5");
  CHECK_SCENE_ERROR(kMinimal + "[solver]\nmax_steps = 0\n", 11, 13, "must be an integer from 1 to 1e+15");
  CHECK_SCENE_ERROR(kMinimal + "[solver]\ninitial_step = -1.0\n", 11, 16, ">= 0");
  CHECK_SCENE_ERROR(kMinimal + "[formulation]\nscheme = \"gll\"\n", 11, 10, "did you mean \"ggl\"?", "'index1'");
  CHECK_SCENE_ERROR(kMinimal + "[formulation]\ncoordinates = \"quaternions\"\n", 11, 15,
                    "did you mean \"quaternion\"?");
}

TEST_CASE("scene loader: absurd magnitudes are rejected") {
  CHECK_SCENE_ERROR("schema_version = 1\n" + kBody + "[initial]\nquaternion = [1.0, 0.0, 0.0, 0.0]\n"
                    "angular_velocity = [0.0, 2e6, 0.0]\n" + kTime, 7, 20, "rad/s");
  CHECK_SCENE_ERROR(kMinimal + "[gravity]\nacceleration = [0.0, 0.0, -2e4]\n", 11, 16, "m/s^2");
  CHECK_SCENE_ERROR("schema_version = 1\n" + kBody + "center_of_mass = [2e6, 0.0, 0.0]\n" + kInitial + kTime, 5, 18,
                    "'body.center_of_mass'", "metres");
}

TEST_SUITE_END();
