// The table of representations is the one list of coordinates: every row is
// accepted, under its own name, by the scene loader (single-body and a
// multibody body's override), by the command line and by compare, and
// nothing else is. A registry row missing from any of them fails here.
#include <doctest/doctest.h>

#include <fstream>
#include <iterator>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "rigidae/app/command_line.hpp"
#include "rigidae/app/compare.hpp"
#include "rigidae/coords/representation.hpp"
#include "rigidae/core/error.hpp"
#include "rigidae/io/scene_loader.hpp"
#include "rigidae/model/rigid_body.hpp"
#include "rigidae/schemes/scheme.hpp"
#include "rigidae/settings/settings.hpp"
#include "test_scenes.hpp"

TEST_SUITE_BEGIN("unit");

using namespace rigidae;

namespace {

std::string one_body_scene(const std::string& coordinates) {
  return "schema_version = 1\n"
         "[body]\nmass = 2.0\ninertia_principal = [2.0, 3.0, 4.0]\n"
         "[initial]\nquaternion = [1.0, 0.0, 0.0, 0.0]\nangular_velocity = [0.0, 0.0, 1.0]\n"
         "[time]\nend = 1.0\n"
         "[formulation]\ncoordinates = \"" +
         coordinates + "\"\n";
}

// problems/double_pendulum.toml with `coordinates = <name>` on its first body.
std::string pendulum_with_body_coordinates(const std::string& coordinates) {
  std::ifstream in(std::string(RIGIDAE_SOURCE_DIR) + "/problems/double_pendulum.toml");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string anchor = "name = \"upper\"\n";
  const std::size_t at = text.find(anchor);
  REQUIRE(at != std::string::npos);
  text.insert(at + anchor.size(), "coordinates = \"" + coordinates + "\"\n");
  return text;
}

std::string error_of(const std::string& scene_text) {
  try {
    io::parse_scene(scene_text, "t.toml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

std::string joined(const std::vector<std::string>& names, const std::string& sep) {
  std::string s;
  for (const std::string& n : names) s += (s.empty() ? "" : sep) + n;
  return s;
}

}  // namespace

TEST_CASE("coordinates registry: the names, the representations and the constraint flag agree") {
  const std::vector<std::string> names = coordinates_names();
  REQUIRE(names.size() >= 3);
  CHECK(std::set<std::string>(names.begin(), names.end()).size() == names.size());

  const std::vector<Coordinates> all = all_coordinates();
  REQUIRE(all.size() == names.size());
  std::vector<std::string> expected_representations;
  const Scene top = test::asymmetric_top_scene(Coordinates::Quaternion, Equations::Euler);
  const RigidBodyModel body = make_rigid_body_model(top);
  for (std::size_t i = 0; i < names.size(); ++i) {
    CHECK(all[i].name() == names[i]);
    CHECK(to_string(all[i]) == names[i]);
    for (Equations e : {Equations::Lagrange, Equations::Euler}) {
      const std::string rep_name = names[i] + "/" + to_string(e);
      expected_representations.push_back(rep_name);
      CHECK(representation_name(all[i], e) == rep_name);
      const auto rep = make_representation(rep_name, body, so3::EulerSequence{});
      CAPTURE(rep_name);
      CHECK(rep->name() == rep_name);
      // The row's flag is what the representation itself reports.
      CHECK(has_constraints(all[i]) == (rep->nc() > 0));
    }
  }
  CHECK(representation_names() == expected_representations);

  // The coordinates code names on purpose are registry rows.
  for (const Coordinates& c : {Coordinates::EulerAngles, Coordinates::Quaternion, Coordinates::Linear})
    CHECK(std::find(names.begin(), names.end(), c.name()) != names.end());

  // Unknown names are refused with the valid ones listed.
  CHECK_THROWS_WITH_AS(has_constraints(Coordinates("quat")),
                       ("unknown coordinates 'quat'; valid coordinates: " + joined(names, ", ")).c_str(), InputError);
  CHECK_THROWS_AS(make_representation("quat/euler", body, so3::EulerSequence{}), InputError);
}

TEST_CASE("coordinates registry: every row is accepted by scene files, multibody bodies and the command line") {
  const settings::Setting& setting = settings::scene_setting("formulation.coordinates");
  CHECK(setting.choices() == coordinates_names());
  CHECK(settings::domain_text(setting) == joined(coordinates_names(), "|"));
  for (const std::string& name : coordinates_names()) {
    CAPTURE(name);
    // Scene file, single body.
    const Scene s = io::parse_scene(one_body_scene(name), "t.toml");
    CHECK(s.formulation.coordinates == Coordinates(name));
    // Command line.
    const cli::CommandLine cl = cli::parse_arguments({"--coordinates", name}, cli::command_info("solve"));
    Scene overridden = test::asymmetric_top_scene(Coordinates::Quaternion, Equations::Euler);
    for (const auto& [row, v] : cl.options)
      if (row->set) row->set(overridden, v);
    CHECK(overridden.formulation.coordinates == Coordinates(name));
    // A multibody body's override.
    const Scene mb = io::parse_scene(pendulum_with_body_coordinates(name), "t.toml");
    REQUIRE(mb.multibody);
    REQUIRE(mb.multibody->bodies.at(0).coordinates);
    CHECK(*mb.multibody->bodies.at(0).coordinates == Coordinates(name));
    CHECK_FALSE(mb.multibody->bodies.at(1).coordinates);
  }
  // A name not in the registry: refused in both places with every registry name listed.
  const std::string file_error = error_of(one_body_scene("quaternions"));
  CHECK(file_error.find("did you mean \"quaternion\"?") != std::string::npos);
  const std::string body_error = error_of(pendulum_with_body_coordinates("quaternions"));
  CHECK(body_error.find("did you mean \"quaternion\"?") != std::string::npos);
  for (const std::string& name : coordinates_names()) {
    CHECK(file_error.find("'" + name + "'") != std::string::npos);
    CHECK(body_error.find("'" + name + "'") != std::string::npos);
  }
  CHECK_THROWS_AS(cli::parse_arguments({"--coordinates", "quaternions"}, cli::command_info("solve")), InputError);
}

TEST_CASE("coordinates registry: compare's combinations are the registry's coordinates x forms x schemes") {
  const std::vector<Combination> combos = all_combinations();
  std::vector<std::string> expected;
  for (const Coordinates& c : all_coordinates())
    for (Equations e : {Equations::Lagrange, Equations::Euler}) {
      if (!has_constraints(c)) {
        expected.push_back(representation_name(c, e) + "/any");
        continue;
      }
      for (const std::string& s : scheme_names()) expected.push_back(representation_name(c, e) + "/" + s);
    }
  std::vector<std::string> got;
  for (const Combination& c : combos) got.push_back(c.name());
  CHECK(got == expected);
  // The 26 of the heavy top's guard: 2 forms x (1 + 6 + 6).
  CHECK(got.size() == 26);
}

TEST_SUITE_END();
