// The viewer's geometry (app/scene_geometry.cpp; docs/viewer.md, "Geometry"):
// one path for every scene, over the system it runs as. A one-body top is
// its body drawn about the fixed point (the frame the scene file writes its
// shapes in) with the fixed point as a pivot joint; a mechanism's bodies in
// their centre-of-mass frames with the BODY. column prefix; a schema-2 body
// on a pivot in its pivot's frame, where the hinge through the pivot has its
// point at the origin. Expected values from the scene files by hand.
#include <doctest/doctest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <string>

#include "rigidae/app/scene_geometry.hpp"
#include "rigidae/io/scene_loader.hpp"

TEST_SUITE_BEGIN("unit");

using namespace rigidae;
using nlohmann::json;

namespace {

json geometry_of(const std::string& problem) {
  return json::parse(scene_geometry_json(io::load_scene(std::string(RIGIDAE_SOURCE_DIR) + "/problems/" + problem)));
}

void check_vec(const json& v, double x, double y, double z, double tol = 0.0) {
  REQUIRE(v.size() == 3);
  CHECK(std::abs(v[0].get<double>() - x) <= tol);
  CHECK(std::abs(v[1].get<double>() - y) <= tol);
  CHECK(std::abs(v[2].get<double>() - z) <= tol);
}

}  // namespace

TEST_CASE("scene geometry: the heavy top is its body about the fixed point, a pivot joint there") {
  const json g = geometry_of("heavy_top.toml");
  CHECK(g["schema_version"] == 1);
  REQUIRE(g["bodies"].size() == 1);
  const json& b = g["bodies"][0];
  CHECK(b["name"] == "body");
  CHECK(b["columns"] == "");  // trajectory.csv's qw..qz
  check_vec(b["pivot"], 0, 0, 0);
  check_vec(b["center_of_mass"], 0, 1, 0);  // [body] center_of_mass, from the fixed point
  CHECK(b["inertia_ellipsoid"] == true);
  check_vec(b["visuals"][0]["position"], 0, 1, 0);
  REQUIRE(g["joints"].size() == 1);
  const json& j = g["joints"][0];
  CHECK(j["type"] == "spherical");
  CHECK(j["body"] == 0);
  check_vec(j["point"], 0, 0, 0);
  CHECK(j["other"] == -1);
  check_vec(j["other_point"], 0, 0, 0);
  CHECK(j["reaction"] == "pivot_");  // no such columns in a one-body file: drawn without an arrow
  // A thin disk of 15 kg, J = (0.234375, 0.46875, 0.234375): largest semi-axis
  // a = sqrt(5 (J2 + J3 - J1) / (2 m)); the body sweeps a ball of radius
  // |c| + a about the fixed point.
  const double a = std::sqrt(5.0 * 0.46875 / 30.0);
  CHECK(g["extent"].get<double>() == doctest::Approx(2.0 * (1.0 + a)).epsilon(1e-15));
  CHECK(g["markers"].empty());
}

TEST_CASE("scene geometry: the absolute heavy top has BODY. columns, its centre-of-mass frame and its joint") {
  const json g = geometry_of("heavy_top_absolute.toml");
  CHECK(g["schema_version"] == 2);
  const json& b = g["bodies"][0];
  CHECK(b["columns"] == b["name"].get<std::string>() + ".");
  CHECK_FALSE(b.contains("pivot"));
  check_vec(b["center_of_mass"], 0, 0, 0);
  REQUIRE(g["joints"].size() == 1);
  // The spherical joint at the fixed point, 1 m from the centre of mass along -y (body axes = space).
  check_vec(g["joints"][0]["point"], 0, -1, 0, 1e-15);
  CHECK(g["joints"][0]["reaction"] == g["joints"][0]["name"].get<std::string>() + ".");
}

TEST_CASE("scene geometry: a schema-2 body on a pivot is drawn about it, its pivot a joint after the joints") {
  const json g = geometry_of("pendulum_1000_pivot.toml");
  const json& b = g["bodies"][0];
  CHECK(b["columns"] == "bob.");
  check_vec(b["pivot"], 0, 0, 0);
  check_vec(b["center_of_mass"], 1, 0, 0, 1e-15);  // position [1, 0, 0], pivot at the origin
  REQUIRE(g["joints"].size() == 2);
  // The hinge's point is the pivot: the drawing frame's origin.
  CHECK(g["joints"][0]["name"] == "hinge");
  check_vec(g["joints"][0]["point"], 0, 0, 0, 1e-15);
  CHECK(g["joints"][1]["name"] == "bob.pivot");
  CHECK(g["joints"][1]["body"] == 0);
  CHECK(g["joints"][1]["reaction"] == "bob.pivot_");  // trajectory.csv's bob.pivot_force_x..z
}

TEST_CASE("scene geometry: a one-body scene's shapes stay where its file puts them, about the body origin") {
  const std::string head =
      "schema_version = 1\n[body]\nmass = 2.0\ninertia_principal = [2.0, 3.0, 4.0]\n"
      "center_of_mass = [0.3, -0.2, 0.7]\n"
      "visual = { shape = \"box\", size = [0.1, 0.2, 0.3], position = [0.1, 0.25, -0.4] }\n";
  const std::string tail = "[initial]\nquaternion = [1.0, 0.0, 0.0, 0.0]\nangular_velocity = [0.0, 0.0, 1.0]\n"
                           "[time]\nend = 1.0\noutput_step = 0.1\n";
  // A top: the frame is the body origin, the fixed point.
  const json top = json::parse(
      scene_geometry_json(io::parse_scene(head + "[support]\ntype = \"fixed_point\"\n" + tail, "top.toml")));
  check_vec(top["bodies"][0]["visuals"][0]["position"], 0.1, 0.25, -0.4, 1e-15);
  check_vec(top["bodies"][0]["center_of_mass"], 0.3, -0.2, 0.7);
  // A free body turns about its centre of mass, held at the origin: drawn in
  // the frame there, the shape's offset from the centre of mass.
  const json free =
      json::parse(scene_geometry_json(io::parse_scene(head + "[support]\ntype = \"free\"\n" + tail, "free.toml")));
  check_vec(free["bodies"][0]["pivot"], 0, 0, 0);
  check_vec(free["bodies"][0]["center_of_mass"], 0, 0, 0);
  check_vec(free["bodies"][0]["visuals"][0]["position"], 0.1 - 0.3, 0.25 + 0.2, -0.4 - 0.7, 1e-15);
  check_vec(free["joints"][0]["point"], 0, 0, 0);
}

TEST_SUITE_END();
