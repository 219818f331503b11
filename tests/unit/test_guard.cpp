// The regression guard: a refactoring of the core changes no result.
//
// tests/guard/pinned.json holds, for the 26 coordinates x equations x scheme
// combinations on the heavy top and for every shipped scene in its own
// formulation, IDA's integer counters and the final state as computed on
// commit 4f13209 (tools/pin_guard.py wrote it). Each run here is the real
// CLI on the same scene; its counters must be equal (band 0) and its final
// orientation within 1e-12 rad of the pinned one. A change that moves these
// numbers changes what users see and must say why.
//
// pinned.json's "ode_runs" (commit 5df9816, `tools/pin_guard.py --ode`) pin
// ten single-body runs on CVODE (BDF, Adams) and ARKODE (explicit tables)
// the same way: the heavy top, the free bodies and sleeping_top over a
// spread of coordinates x equations x {index1, projection}, recorded while
// the one-body ODE form (SingleBodyOde) still existed beside the multibody
// one, so that deleting it stays guarded.
//
// tests/guard/pinned_mechanisms.json does the same for the shipped mechanism
// scenes (their default runs and a spread of combinations, commit 84ddc6d,
// `tools/pin_guard.py --mechanisms`): IDA's counters, and every body's final
// orientation and centre-of-mass position from the last row of
// trajectory.csv, before the single-body and multibody stacks are joined;
// re-pinned (same tool) when the bodies' own rows took the one-body
// assembler's arithmetic (schemes/body_rows.hpp): round-off, each move
// listed in that commit.
#include <doctest/doctest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <map>
#include <string>

#include "cli_runner.hpp"

TEST_SUITE_BEGIN("system");

namespace {

using nlohmann::json;

json pinned_runs(const char* file = "pinned.json", const char* list = "runs") {
  std::ifstream in(std::string(RIGIDAE_SOURCE_DIR) + "/tests/guard/" + file);
  REQUIRE(in.good());
  return json::parse(in)[list];
}

// Angle (rad) between the rotations of two unit quaternions, either sign.
double rotation_angle(const json& a, const json& b) {
  double dot = 0.0, na = 0.0, nb = 0.0;
  for (int i = 0; i < 4; ++i) {
    const double x = a[i].get<double>(), y = b[i].get<double>();
    dot += x * y;
    na += x * x;
    nb += y * y;
  }
  // 2 acos(|a.b|) loses digits near 1; 4 asin of the half-chord does not.
  double d2 = 0.0;
  const double s = dot < 0 ? -1.0 : 1.0;
  for (int i = 0; i < 4; ++i) {
    const double d = a[i].get<double>() / std::sqrt(na) - s * b[i].get<double>() / std::sqrt(nb);
    d2 += d * d;
  }
  return 4.0 * std::asin(std::min(1.0, std::sqrt(d2) / 2.0));
}

// Runs a pinned run's command into dir; checks its exit code, status and
// IDA's counters against the pin, and returns its summary.json.
json run_pinned(const json& pin, const std::filesystem::path& dir) {
  std::string args = "solve " + std::string(RIGIDAE_SOURCE_DIR) + "/" + pin["scene"].get<std::string>() +
                     " --quiet --out " + dir.string();
  for (const auto& a : pin["args"]) args += " " + a.get<std::string>();
  const auto r = rigidae::test::run_cli(args);
  INFO(r.output);
  REQUIRE(r.exit_code == (pin["status"] == "success" ? 0 : 1));
  std::ifstream in(dir / "summary.json");
  REQUIRE(in.good());
  const json s = json::parse(in);
  CHECK(s["status"] == pin["status"]);
  for (const auto& [key, value] : pin["counters"].items()) {
    INFO("counter " << key);
    CHECK(s["counters"][key].get<long>() == value.get<long>());
  }
  return s;
}

void check_run(const json& pin) {
  const std::string name = pin["name"];
  INFO("pinned run: " << name);
  const auto dir = rigidae::test::fresh_temp_dir("guard-" + std::to_string(std::hash<std::string>{}(name)));
  const json s = run_pinned(pin, dir);
  CHECK(s["chart_switch_count"].get<long>() == pin["chart_switch_count"].get<long>());
  CHECK(s["final"]["t"].get<double>() == pin["t"].get<double>());
  CHECK(rotation_angle(s["final"]["q_WB"], pin["q_WB"]) <= 1e-12);
  for (int i = 0; i < 3; ++i) {
    const double w = pin["omega_B"][i].get<double>();
    CHECK(std::abs(s["final"]["omega_B"][i].get<double>() - w) <= 1e-9 * std::max(1.0, std::abs(w)));
  }
}

// The last data row of a trajectory.csv, column name -> value.
std::map<std::string, double> last_row(const std::filesystem::path& csv) {
  const auto rows = rigidae::test::read_csv_rows(csv);
  REQUIRE(!rows.empty());
  std::map<std::string, double> out;
  for (const auto& [k, v] : rows.back()) out[k] = std::stod(v);
  return out;
}

void check_mechanism_run(const json& pin) {
  const std::string name = pin["name"];
  INFO("pinned mechanism run: " << name);
  const auto dir = rigidae::test::fresh_temp_dir("guard-mb-" + std::to_string(std::hash<std::string>{}(name)));
  run_pinned(pin, dir);
  const auto row = last_row(dir / "trajectory.csv");
  CHECK(row.at("t") == pin["t"].get<double>());
  for (const auto& [body, state] : pin["bodies"].items()) {
    INFO("body " << body);
    const json q = json::array({row.at(body + ".qw"), row.at(body + ".qx"), row.at(body + ".qy"), row.at(body + ".qz")});
    CHECK(rotation_angle(q, state["q"]) <= 1e-12);
    const char* axes[3] = {"x", "y", "z"};
    for (int i = 0; i < 3; ++i) {
      const double x = state["x"][i].get<double>();
      CHECK(std::abs(row.at(body + "." + axes[i]) - x) <= 1e-12 * std::max(1.0, std::abs(x)));
    }
  }
}

}  // namespace

TEST_CASE("guard: every shipped mechanism keeps today's counters and final body states" * doctest::test_suite("slow")) {
  int n = 0;
  for (const auto& pin : pinned_runs("pinned_mechanisms.json")) {
    check_mechanism_run(pin);
    ++n;
  }
  CHECK(n >= 16);
}

TEST_CASE("guard: the 26 combinations on the heavy top keep today's counters and final state" * doctest::test_suite("slow")) {
  int n = 0;
  for (const auto& pin : pinned_runs())
    if (pin["name"].get<std::string>().rfind("heavy_top/", 0) == 0 && pin["args"].size() > 0) {
      check_run(pin);
      ++n;
    }
  CHECK(n == 26);
}

TEST_CASE("guard: single-body runs on CVODE and ARKODE keep today's counters and final state" * doctest::test_suite("slow")) {
  int n = 0;
  std::map<std::string, int> integrators;
  for (const auto& pin : pinned_runs("pinned.json", "ode_runs")) {
    check_run(pin);
    ++integrators[pin["args"][1].get<std::string>()];
    ++n;
  }
  CHECK(n == 10);
  CHECK(integrators.size() == 3);  // cvode-bdf, cvode-adams, arkode-erk
}

TEST_CASE("guard: every shipped scene keeps today's counters and final state in its own formulation" * doctest::test_suite("slow")) {
  int n = 0;
  for (const auto& pin : pinned_runs())
    if (pin["args"].empty()) {
      check_run(pin);
      ++n;
    }
  CHECK(n >= 9);
}

TEST_SUITE_END();
