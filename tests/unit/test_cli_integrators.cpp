// --integrator / --erk-method and solver.integrator / solver.erk_method as a
// user meets them: an integrator/scheme pair the table does not run is exit
// 2 listing the valid schemes (with file:line:col from a scene file), and
// the ODE integrators run end to end through `rigidae solve`.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>

#include "cli_runner.hpp"

TEST_SUITE_BEGIN("system");

namespace {

using rigidae::test::run_cli;

const std::string kScene = std::string(RIGIDAE_SOURCE_DIR) + "/problems/heavy_top.toml";

std::filesystem::path temp_scene(const std::string& name, const std::string& text) {
  const auto dir = std::filesystem::temp_directory_path() / "rigidae_cli_integrator_tests";
  std::filesystem::create_directories(dir);
  const auto path = dir / name;
  std::ofstream(path) << text;
  return path;
}

// The heavy top's file with extra lines appended to [formulation] and [solver]
// (its own `integrator = "ida"`, which keeps the guard's pins, left out).
std::string heavy_top_with(const std::string& formulation, const std::string& solver) {
  std::ifstream in(kScene);
  std::string text((std::istreambuf_iterator<char>(in)), {});
  text = std::regex_replace(text, std::regex("scheme = \"ggl\""), formulation);
  text = std::regex_replace(text, std::regex("\nintegrator = \"ida\"\n"), "\n");
  return text + solver + "\n";
}

}  // namespace

TEST_CASE("cli: an integrator/scheme pair the table does not run exits 2 with the valid schemes") {
  auto r = run_cli("solve " + kScene + " --integrator arkode-erk --t-end 0.1");  // the file says ggl
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("does not run scheme 'ggl'") != std::string::npos);
  CHECK(r.output.find("index1, projection") != std::string::npos);

  r = run_cli("solve " + kScene + " --integrator rk4");
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("'ida', 'cvode-adams', 'cvode-bdf' or 'arkode-erk'") != std::string::npos);

  r = run_cli("solve " + kScene + " --integrator arkode-erk --scheme projection --erk-method verner87");
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("'dopri87', 'fehlberg78', 'verner65' or 'dopri5'") != std::string::npos);

  // In a scene file: file:line:col of the integrator key.
  const auto bad = temp_scene("adams_ggl.toml", heavy_top_with("scheme = \"ggl\"", "integrator = \"cvode-adams\""));
  r = run_cli("solve " + bad.string());
  CHECK(r.exit_code == 2);
  CHECK(r.output.find(bad.string() + ":") != std::string::npos);
  CHECK(r.output.find("index1, projection") != std::string::npos);
}

TEST_CASE("cli: the ODE integrators run through solve and say so in summary.json") {
  const auto out = std::filesystem::temp_directory_path() / "rigidae_cli_integrator_tests" / "run";
  const std::pair<const char*, const char*> runs[] = {
      {"arkode-erk", "--integrator arkode-erk --erk-method dopri5 --scheme projection"},
      {"cvode-adams", "--integrator cvode-adams --scheme index1"},
      {"cvode-bdf", "--integrator cvode-bdf --scheme projection"}};
  for (const auto& [integrator, args] : runs) {
    CAPTURE(args);
    std::filesystem::remove_all(out);
    const auto r = run_cli("solve " + kScene + " --t-end 0.1 --rtol 1e-8 --atol 1e-8 --quiet --out " + out.string() +
                           " " + std::string(args));
    REQUIRE(r.exit_code == 0);
    std::ifstream in(out / "summary.json");
    const auto s = nlohmann::json::parse(in);
    CHECK(s["configuration"]["solver"]["integrator"].get<std::string>() == integrator);
    CHECK(s["counters"]["steps"].get<long>() > 10);
    CHECK(std::filesystem::exists(out / "steps.csv"));
  }
  // A scene file naming an ODE integrator and no scheme runs the ODE form with projection.
  const auto file = temp_scene("adams_default.toml",
                               std::regex_replace(heavy_top_with("", "integrator = \"cvode-adams\""),
                                                  std::regex("end = 2.0"), "end = 0.1"));
  std::filesystem::remove_all(out);
  const auto r = run_cli("solve " + file.string() + " --quiet --out " + out.string());
  REQUIRE(r.exit_code == 0);
  std::ifstream in(out / "summary.json");
  const auto s = nlohmann::json::parse(in);
  CHECK(s["configuration"]["formulation"]["scheme"].get<std::string>() == "projection");
}

TEST_SUITE_END();
