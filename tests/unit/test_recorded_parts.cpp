// Which parts a mechanism records ([output] bodies / joints), as a user
// meets it: unknown names are refused with the file, line and the valid
// names; a selection narrows steps.csv and trajectory.csv to the parts
// named; a mechanism of more than 50 joints records per step only the
// global columns unless the scene names parts, and summary.json says so.
#include <doctest/doctest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "rigidae/app/solve.hpp"
#include "rigidae/model/recorded_parts.hpp"
#include "test_multibody_scenes.hpp"

TEST_SUITE_BEGIN("system");

using namespace rigidae;
namespace fs = std::filesystem;

namespace {

const std::string kProblems = std::string(RIGIDAE_SOURCE_DIR) + "/problems/";

// double_pendulum.toml with `extra` appended; returns the file and the line
// number of extra's first line.
std::pair<fs::path, int> pendulum_with(const fs::path& dir, const std::string& extra) {
  std::string text = test::read_file(kProblems + "double_pendulum.toml");
  if (text.back() != '\n') text += '\n';
  const int line = static_cast<int>(std::count(text.begin(), text.end(), '\n')) + 1;
  const fs::path p = dir / "scene.toml";
  std::ofstream(p) << text << extra;
  return {p, line};
}

std::vector<std::string> header_of(const fs::path& csv) {
  std::ifstream in(csv);
  std::string units, header;
  std::getline(in, units);
  std::getline(in, header);
  std::vector<std::string> out;
  std::stringstream ss(header);
  for (std::string c; std::getline(ss, c, ',');) out.push_back(c);
  return out;
}

bool has(const std::vector<std::string>& v, const std::string& s) { return std::find(v.begin(), v.end(), s) != v.end(); }

}  // namespace

TEST_CASE("recorded parts: an unknown joint or body name is exit 2 at its file:line with the valid names") {
  const fs::path dir = test::fresh_temp_dir("parts_unknown");
  {
    const auto [scene, line] = pendulum_with(dir, "\n[output]\njoints = [\"shoulder\", \"elbw\"]\n");
    const test::CliResult r = test::run_cli("solve " + scene.string() + " --quiet --out " + (dir / "o").string());
    CHECK(r.exit_code == 2);
    CHECK_MESSAGE(r.output.find(scene.string() + ":" + std::to_string(line + 2) + ":") != std::string::npos, r.output);
    CHECK_MESSAGE(r.output.find("did you mean \"elbow\"") != std::string::npos, r.output);
    CHECK_MESSAGE(r.output.find("'shoulder' or 'elbow'") != std::string::npos, r.output);
  }
  {
    const auto [scene, line] = pendulum_with(dir, "\n[output]\nbodies = [\"torso\"]\n");
    const test::CliResult r = test::run_cli("solve " + scene.string() + " --quiet --out " + (dir / "o").string());
    CHECK(r.exit_code == 2);
    CHECK_MESSAGE(r.output.find(scene.string() + ":" + std::to_string(line + 2) + ":") != std::string::npos, r.output);
    CHECK_MESSAGE(r.output.find("'upper' or 'lower'") != std::string::npos, r.output);
  }
  {
    const auto [scene, line] = pendulum_with(dir, "\n[output]\njoints = \"some\"\n");
    const test::CliResult r = test::run_cli("solve " + scene.string() + " --quiet --out " + (dir / "o").string());
    CHECK(r.exit_code == 2);
    CHECK_MESSAGE(r.output.find("\"all\", \"none\"") != std::string::npos, r.output);
  }
  {
    // One-body scenes have no parts to choose.
    std::string text = test::read_file(kProblems + "heavy_top.toml");
    const fs::path p = dir / "one_body.toml";
    std::ofstream(p) << text << "\n[output]\nbodies = \"all\"\n";
    const test::CliResult r = test::run_cli("solve " + p.string() + " --quiet --out " + (dir / "o").string());
    CHECK(r.exit_code == 2);
    CHECK_MESSAGE(r.output.find("unknown key 'bodies'") != std::string::npos, r.output);
  }
}

TEST_CASE("recorded parts: a selection narrows steps.csv and trajectory.csv to the parts named") {
  const fs::path dir = test::fresh_temp_dir("parts_selected");
  const auto [all_scene, l1] = pendulum_with(dir, "");
  REQUIRE(test::run_cli("solve " + all_scene.string() + " --t-end 0.05 --quiet --out " + (dir / "all").string())
              .exit_code == 0);
  const auto [scene, l2] = pendulum_with(dir, "\n[output]\njoints = [\"elbow\"]\nbodies = \"none\"\n");
  REQUIRE(test::run_cli("solve " + scene.string() + " --t-end 0.05 --quiet --out " + (dir / "one").string())
              .exit_code == 0);
  const auto all_steps = header_of(dir / "all" / "steps.csv"), one_steps = header_of(dir / "one" / "steps.csv");
  const auto all_grid = header_of(dir / "all" / "trajectory.csv"), one_grid = header_of(dir / "one" / "trajectory.csv");
  CHECK(has(all_steps, "shoulder.force_z"));
  CHECK(has(all_steps, "upper.mu_norm"));
  CHECK(!has(one_steps, "shoulder.force_z"));
  CHECK(!has(one_steps, "upper.mu_norm"));
  CHECK(has(one_steps, "elbow.force_z"));
  CHECK(has(one_steps, "elbow.lambda_x"));
  CHECK(has(one_steps, "energy"));
  CHECK(one_steps.size() < all_steps.size());
  CHECK(!has(one_grid, "upper.qw"));
  CHECK(!has(one_grid, "shoulder.force_x"));
  CHECK(has(one_grid, "elbow.force_x"));
  CHECK(has(one_grid, "energy"));
  CHECK(one_grid.size() == all_grid.size() - 2 * 13 - 8);
  const nlohmann::json s = nlohmann::json::parse(test::read_file(dir / "one" / "summary.json"));
  CHECK(s["recorded_parts"]["steps"]["joints"] == nlohmann::json::array({"elbow"}));
  CHECK(s["recorded_parts"]["steps"]["bodies"].empty());
  CHECK(s["recorded_parts"]["chosen_by_scene"]["joints"] == true);
}

TEST_CASE("recorded parts: above 50 joints the step file holds the global columns unless the scene names parts") {
  // A chain of 51 links hanging at rest (built in code: the count, not the
  // motion, is what is tested).
  Scene s = test::multibody_base(Coordinates::Quaternion, Equations::Euler, "ggl");
  MultibodySpec& m = *s.multibody;
  const int n = static_cast<int>(kAllPartsUpToJoints) + 1;
  for (int i = 0; i < n; ++i) {
    BodySpec b;
    b.name = "link" + std::to_string(i);
    b.mass = 1.0;
    b.inertia_com = Vec3(0.01, 0.01, 0.001).asDiagonal();
    b.x0_W = Vec3(0, 0, -0.1 * i - 0.05);
    b.R0_WB = Mat3::Identity();
    b.where = {"built_in.toml", 2 + i, 1};
    m.bodies.push_back(b);
  }
  for (int i = 0; i < n; ++i)
    m.joints.push_back(test::joint_at(m, &joint_type("spherical"), i == 0 ? kGround : i - 1, i, Vec3(0, 0, -0.1 * i),
                                      Vec3::UnitZ(), Vec3::UnitX(), "j" + std::to_string(i)));
  s.time = {0.0, 0.01, 0.01};
  const fs::path dir = test::fresh_temp_dir("parts_large");
  REQUIRE(solve_scene(s, dir / "default").run.status == RunStatus::Success);
  const auto cut = header_of(dir / "default" / "steps.csv");
  CHECK(cut == std::vector<std::string>{"t", "h", "order", "drift_position", "drift_velocity", "energy",
                                        "energy_rel_error"});
  const nlohmann::json sd = nlohmann::json::parse(test::read_file(dir / "default" / "summary.json"));
  CHECK(sd["recorded_parts"].contains("note"));
  CHECK(sd["recorded_parts"]["steps"]["joints"].empty());
  // trajectory.csv keeps every part by default (one row per output time).
  CHECK(header_of(dir / "default" / "trajectory.csv").size() == 1 + 13 * n + 8 * n + 7);

  m.output_joints = std::vector<int>{0, 50};
  REQUIRE(solve_scene(s, dir / "chosen").run.status == RunStatus::Success);
  const auto chosen = header_of(dir / "chosen" / "steps.csv");
  CHECK(has(chosen, "j0.force_z"));
  CHECK(has(chosen, "j50.force_z"));
  CHECK(!has(chosen, "j1.force_z"));
  CHECK(!has(chosen, "link0.mu_norm"));  // bodies still the (cut) default
  CHECK(chosen.size() == 7 + 2 * (3 + 3 + 8));  // ggl: lambda and mu per point row, then reaction and drift
}

TEST_SUITE_END();
