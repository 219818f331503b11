// One summary.json schema: a single-body run and a mechanism's run name the
// same things the same way. Every key both carry has the same JSON type in
// both, the keys every run has are present in both, and the old multibody
// spellings are gone. Plus the honesty flag: multipliers of every IDA run
// (all schemes leave them out of the error test) say they are not
// error-controlled, with the reason.
#include <doctest/doctest.h>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>

#include "cli_runner.hpp"
#include "rigidae/app/solve.hpp"
#include "rigidae/io/scene_loader.hpp"
#include "test_multibody_scenes.hpp"

TEST_SUITE_BEGIN("system");

using namespace rigidae;
namespace fs = std::filesystem;

namespace {

nlohmann::json run_summary(const Scene& s, const std::string& name) {
  const fs::path dir = test::fresh_temp_dir(name);
  const SolveOutcome o = solve_scene(s, dir);
  REQUIRE(o.run.status == RunStatus::Success);
  return nlohmann::json::parse(test::read_file(dir / "summary.json"));
}

}  // namespace

TEST_CASE("summary schema: single-body and multibody summaries share their common keys' names and types") {
  Scene one = io::load_scene(std::string(RIGIDAE_SOURCE_DIR) + "/problems/heavy_top.toml");
  one.time.end = 0.02;
  Scene many = test::absolute_heavy_top(Coordinates::Quaternion, Equations::Euler, "ggl");
  many.time = {0.0, 0.02, 0.01};
  const nlohmann::json a = run_summary(one, "summary_one"), b = run_summary(many, "summary_many");

  const char* required[] = {"units", "scene", "source", "schema_version", "versions", "representation",
                            "coordinates", "equations", "scheme", "note", "integrator", "rtol", "atol", "jacobian",
                            "linear_solver", "linear_solver_setting", "status", "message", "t_reached",
                            "wall_time_s", "initial_residual_max_abs", "factor_nonzeros", "counters",
                            "chart_switch_count", "warnings", "multipliers_error_controlled",
                            "multipliers_error_note", "configuration", "maxima", "accuracy_check", "final",
                            "columns_units"};
  for (const char* k : required) {
    CAPTURE(k);
    CHECK(a.contains(k));
    CHECK(b.contains(k));
  }
  // Same name, same kind of value, one level down too (counters, maxima, final, ...).
  int shared = 0;
  for (const auto& [k, va] : a.items()) {
    if (!b.contains(k)) continue;
    CAPTURE(k);
    const nlohmann::json& vb = b[k];
    CHECK(va.type_name() == std::string(vb.type_name()));
    ++shared;
    if (va.is_object() && vb.is_object() && k != "configuration")
      for (const auto& [k2, v2] : va.items())
        if (vb.contains(k2)) {
          CAPTURE(k2);
          // null: a measure this run does not check (accuracy_check's
          // angular momenta on a mechanism); otherwise the same type.
          if (!v2.is_null() && !vb[k2].is_null()) CHECK(v2.type_name() == std::string(vb[k2].type_name()));
        }
  }
  CHECK(shared >= static_cast<int>(std::size(required)));
  // The counters are the same set of names.
  for (const auto& [k, v] : a["counters"].items()) CHECK_MESSAGE(b["counters"].contains(k), k);
  // The multibody spellings of before are gone, not kept beside.
  for (const char* old : {"wall_seconds"}) {
    CHECK(!a.contains(old));
    CHECK(!b.contains(old));
  }
  // The same values where both runs state the same thing.
  CHECK(a["schema_version"] == 1);
  CHECK(b["schema_version"] == 2);
  CHECK(a["representation"] == a["coordinates"].get<std::string>() + "/" + a["equations"].get<std::string>());
  CHECK(b["representation"] == b["coordinates"].get<std::string>() + "/" + b["equations"].get<std::string>());
  CHECK(b["final"]["t"] == b["t_reached"]);
  // IDA runs: multipliers outside the error test, said so with a reason naming the scheme.
  for (const nlohmann::json* s : {&a, &b}) {
    CHECK((*s)["multipliers_error_controlled"] == false);
    CHECK((*s)["multipliers_error_note"].get<std::string>().find("ggl") != std::string::npos);
  }
}

TEST_SUITE_END();
