// The default integrator rule (settings/default_integrator.hpp, issue 23
// item 4): a non-stiff scene with scheme index1 or projection gets the
// explicit table, a DAE-only scheme or a stiff spring gets IDA, a named
// integrator (scene file or command line) always wins; the rate estimate
// against hand-computed sqrt(k/m), c/m and sqrt(k/I); summary.json and the
// printed report say which integrator ran and why.
#include <doctest/doctest.h>
#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "rigidae/app/command_line.hpp"
#include "rigidae/io/scene_loader.hpp"
#include "rigidae/settings/default_integrator.hpp"

TEST_SUITE_BEGIN("system");

namespace {

using rigidae::Scene;
namespace settings = rigidae::settings;

// One rigid body (m = 2 kg, principal moments 2, 3, 4 kg m^2) with `solver`
// lines in [solver] and `scheme` in [formulation] ("" leaves it out).
std::string one_body(const std::string& scheme, const std::string& solver = "") {
  std::string s =
      "schema_version = 1\n"
      "[body]\nmass = 2.0\ninertia_principal = [2.0, 3.0, 4.0]\n"
      "[initial]\nquaternion = [1.0, 0.0, 0.0, 0.0]\nangular_velocity = [0.0, 0.0, 1.0]\n"
      "[time]\nend = 1.0\noutput_step = 0.01\n";
  if (!scheme.empty()) s += "[formulation]\nscheme = \"" + scheme + "\"\n";
  if (!solver.empty()) s += "[solver]\n" + solver + "\n";
  return s;
}

// A body of 2 kg on a linear spring-damper to the ground (k N/m, c N s/m),
// output every 0.01 s, scheme index1 unless `scheme` says otherwise.
std::string body_on_spring(double k, double c, const std::string& solver = "", const std::string& scheme = "index1") {
  std::string s = fmt::format(
      "schema_version = 2\n"
      "[[bodies]]\nname = \"b\"\nmass = 2.0\ninertia_principal = [2.0, 3.0, 4.0]\nposition = [0.0, 0.0, -1.0]\n"
      "[[springs]]\nname = \"coil\"\nbodies = [\"ground\", \"b\"]\npoint_a = [0.0, 0.0, 0.0]\n"
      "point_b = [0.0, 0.0, -1.0]\nstiffness = {}\ndamping = {}\nrest_length = 0.99\n"
      "[gravity]\nacceleration = [0.0, 0.0, -9.81]\n"
      "[time]\nend = 0.1\noutput_step = 0.01\n"
      "[formulation]\nscheme = \"{}\"\n",
      k, c, scheme);
  if (!solver.empty()) s += "[solver]\n" + solver + "\n";
  return s;
}

Scene parse(const std::string& text) { return rigidae::io::parse_scene(text, "t.toml"); }

}  // namespace

TEST_CASE("default integrator: a non-stiff index1 or projection scene gets the explicit table") {
  for (const char* scheme : {"index1", "projection"}) {
    CAPTURE(scheme);
    const Scene s = parse(one_body(scheme));
    CHECK(s.solver.integrator == "arkode-erk");
    CHECK_FALSE(s.solver.integrator_named);
    CHECK(s.solver.integrator_choice ==
          fmt::format("default for a non-stiff scene with scheme {}: no spring or damper", scheme));
  }
  // A soft spring: sqrt(k/m) = 100 1/s, x 0.01 s = 1; and a stiff one,
  // 1e4 1/s x 0.01 s = 100, still below the spring limit 1000 (an excited
  // stiff spring: measured cheaper on the explicit table).
  const Scene soft = parse(body_on_spring(2e4, 0.0));
  CHECK(soft.solver.integrator == "arkode-erk");
  CHECK(soft.solver.integrator_choice ==
        "default for a non-stiff scene with scheme index1: the fastest decay x the output step 0 <= 10, sqrt(k/m) x it 1 "
        "<= 1000");
  CHECK(parse(body_on_spring(2e8, 0.0)).solver.integrator == "arkode-erk");
}

TEST_CASE("default integrator: a DAE-only scheme or a stiff spring gets IDA") {
  // No scheme named: ggl, which only IDA runs (the shipped scenes' case).
  for (const char* scheme : {"", "ggl", "index3", "index2", "baumgarte"}) {
    CAPTURE(scheme);
    const Scene s = parse(one_body(scheme));
    CHECK(s.solver.integrator == "ida");
    CHECK(s.solver.integrator_choice.find("which only IDA runs") != std::string::npos);
  }
  // k = 8e10 N/m on 2 kg: sqrt(k/m) = 2e5 1/s, x 0.01 s = 2000 > 1000.
  const Scene stiff = parse(body_on_spring(8e10, 0.0));
  CHECK(stiff.solver.integrator == "ida");
  CHECK(stiff.solver.integrator_choice.rfind("default for a stiff scene: coil sets sqrt(k/m) = 2e+05 1/s", 0) == 0);
  // A stiff damper on a weak spring (overdamped): it decays at
  // (c + sqrt(c^2 - 4 k m)) / 2m = 1e4 1/s (to 1e-8), x 0.01 s = 100 > 10.
  const Scene damped = parse(body_on_spring(1.0, 2e4));
  CHECK(damped.solver.integrator == "ida");
  CHECK(damped.solver.integrator_choice.rfind("default for a stiff scene: coil is overdamped, its fast mode decays at "
                                              "1e+04 1/s", 0) == 0);
  // Just below the damping limit: 900 1/s, x 0.01 s = 9.
  CHECK(parse(body_on_spring(1.0, 1800.0)).solver.integrator == "arkode-erk");
  // A stiff spring with a DAE-only scheme: IDA for the scheme (rule 1 first).
  CHECK(parse(body_on_spring(8e10, 0.0, "", "ggl")).solver.integrator_choice.find("only IDA") != std::string::npos);
}

TEST_CASE("default integrator: the rate estimates are sqrt(k/m), c/m and sqrt(k/I) by hand") {
  const settings::ForceRates soft = settings::force_rates(parse(body_on_spring(2e4, 0.0)));
  CHECK(soft.spring == doctest::Approx(100.0).epsilon(1e-14));
  CHECK(soft.damping == 0.0);
  CHECK(soft.spring_element == "coil");
  // k = 8, c = 10, m = 2: overdamped (c^2 = 100 >= 4 k m = 64), eigenvalues
  // (-10 +- 6) / 4: the fast one -4.
  const settings::ForceRates both = settings::force_rates(parse(body_on_spring(8.0, 10.0)));
  CHECK(both.spring == doctest::Approx(2.0).epsilon(1e-14));   // sqrt(8 / 2)
  CHECK(both.damping == doctest::Approx(4.0).epsilon(1e-14));
  CHECK(both.damping_element == "coil");
  // Underdamped (c = 4: 16 < 64): no decaying mode faster than the oscillation.
  CHECK(settings::force_rates(parse(body_on_spring(8.0, 4.0))).damping == 0.0);
  const settings::ForceRates none = settings::force_rates(parse(one_body("index1")));
  CHECK(none.spring == 0.0);
  CHECK(none.damping == 0.0);
  // A hinge about z to the ground with a torsional damper of 6 N m s/rad
  // alone (then a spring of 800 N m/rad beside it): the body's moment about
  // z 2 kg m^2, 6 / 2 = 3 1/s (then sqrt(800 / 2) = 20 1/s, underdamped).
  const std::string hinge =
      "schema_version = 2\n"
      "[[bodies]]\nname = \"b\"\nmass = 2.0\ninertia_principal = [1.0, 3.0, 2.0]\nposition = [0.0, 0.0, 0.0]\n"
      "[[joints]]\nname = \"h\"\ntype = \"revolute\"\nbodies = [\"ground\", \"b\"]\npoint = [0.0, 0.0, 0.0]\n"
      "axis = [0.0, 0.0, 1.0]\nSPRINGdamping = 6.0\n"
      "[time]\nend = 0.1\n[formulation]\nscheme = \"index1\"\n";
  const auto with = [&](const std::string& spring) {
    return settings::force_rates(parse(std::regex_replace(hinge, std::regex("SPRING"), spring)));
  };
  const settings::ForceRates damper = with("");
  CHECK(damper.spring == 0.0);
  CHECK(damper.damping == doctest::Approx(3.0).epsilon(1e-12));
  CHECK(damper.damping_element == "h");
  const settings::ForceRates h = with("stiffness = 800.0\n");
  CHECK(h.spring == doctest::Approx(20.0).epsilon(1e-12));
  CHECK(h.damping == 0.0);
  CHECK(h.spring_element == "h");
}

TEST_CASE("default integrator: a named integrator always wins, in the file and on the command line") {
  const Scene erk_named_ida = parse(one_body("index1", "integrator = \"ida\""));
  CHECK(erk_named_ida.solver.integrator == "ida");
  CHECK(erk_named_ida.solver.integrator_named);
  CHECK(erk_named_ida.solver.integrator_choice == "named");
  const Scene stiff_named_adams = parse(body_on_spring(8e10, 0.0, "integrator = \"cvode-adams\""));
  CHECK(stiff_named_adams.solver.integrator == "cvode-adams");

  // The command line: the rule reads the final settings, so --scheme moves
  // the default and --integrator replaces it.
  const std::filesystem::path dir = rigidae::test::fresh_temp_dir("default_integrator_cli");
  const std::string file = (dir / "index1.toml").string();
  std::ofstream(file) << one_body("index1");
  const auto scene_of = [&](std::vector<std::string> args) {
    args.insert(args.begin(), file);
    return rigidae::cli::scene_from(rigidae::cli::parse_arguments(args, rigidae::cli::command_info("solve")),
                                    rigidae::cli::command_info("solve"));
  };
  CHECK(scene_of({}).solver.integrator == "arkode-erk");
  CHECK(scene_of({"--scheme", "ggl"}).solver.integrator == "ida");
  CHECK(scene_of({"--scheme", "projection"}).solver.integrator == "arkode-erk");
  const Scene bdf = scene_of({"--integrator", "cvode-bdf"});
  CHECK(bdf.solver.integrator == "cvode-bdf");
  CHECK(bdf.solver.integrator_choice == "named");
}

TEST_CASE("default integrator: summary.json and the report say which integrator ran and why") {
  const std::filesystem::path dir = rigidae::test::fresh_temp_dir("default_integrator_run");
  const std::string file = (dir / "index1.toml").string();
  std::ofstream(file) << one_body("index1");
  const auto r = rigidae::test::run_cli("solve " + file + " --record none --out " + (dir / "run").string());
  REQUIRE(r.exit_code == 0);
  CHECK(r.output.find("integrator    arkode-erk:dopri87 (default for a non-stiff scene with scheme index1: no "
                      "spring or damper; name [solver] integrator or --integrator to choose)") != std::string::npos);
  const auto summary = nlohmann::json::parse(rigidae::test::read_file(dir / "run" / "summary.json"));
  CHECK(summary["integrator"] == "arkode-erk");
  CHECK(summary["integrator_choice"] == "default for a non-stiff scene with scheme index1: no spring or damper");
  // A shipped single body (scheme ggl, no integrator named) stays on IDA.
  const auto fb = rigidae::test::run_cli("solve " + std::string(RIGIDAE_SOURCE_DIR) +
                                         "/problems/free_body.toml --record none --t-end 0.01 --out " +
                                         (dir / "free").string());
  REQUIRE(fb.exit_code == 0);
  const auto free = nlohmann::json::parse(rigidae::test::read_file(dir / "free" / "summary.json"));
  CHECK(free["integrator"] == "ida");
  CHECK(free["integrator_choice"] == "default for scheme ggl, which only IDA runs");
}

TEST_SUITE_END();
