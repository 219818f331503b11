// One system for every scene: the pivoted heavy top (problems/heavy_top.toml,
// a one-body scene) and the same top as a free body held by a spherical
// joint (problems/heavy_top_absolute.toml, a mechanism) run through the same
// code: one solve path (run_scene), one recorder with the column set the
// model chooses, one summary writer, one compare. What differs is only what
// each column set adds, and the physics agrees: the same top, the same motion.
#include <doctest/doctest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <set>
#include <string>

#include "cli_runner.hpp"
#include "rigidae/app/compare.hpp"
#include "rigidae/app/solve.hpp"
#include "rigidae/io/scene_loader.hpp"
#include "rigidae/record/recorder.hpp"
#include "rigidae/so3/rotation.hpp"

TEST_SUITE_BEGIN("system");

using namespace rigidae;
namespace fs = std::filesystem;

namespace {

Scene shipped(const std::string& name, double t_end) {
  Scene s = io::load_scene(std::string(RIGIDAE_SOURCE_DIR) + "/problems/" + name + ".toml");
  s.time.end = t_end;
  s.time.output_step = t_end / 10.0;
  s.solver.rtol = s.solver.atol = 1e-10;
  return s;
}

std::set<std::string> keys(const nlohmann::json& j) {
  std::set<std::string> k;
  for (const auto& [name, v] : j.items()) k.insert(name);
  return k;
}

std::set<std::string> minus(const std::set<std::string>& a, const std::set<std::string>& b) {
  std::set<std::string> d;
  for (const std::string& k : a)
    if (!b.count(k)) d.insert(k);
  return d;
}

int column(const std::vector<std::string>& names, const std::string& name) {
  const auto it = std::find(names.begin(), names.end(), name);
  REQUIRE_MESSAGE(it != names.end(), name);
  return static_cast<int>(it - names.begin());
}

}  // namespace

TEST_CASE("one system: a pivoted top and a free top on a spherical joint share the recorder and the summary") {
  const Scene pivoted = shipped("heavy_top", 0.1), jointed = shipped("heavy_top_absolute", 0.1);
  MemoryRows a_rows, b_rows;
  a_rows.keep_steps = a_rows.keep_grid = b_rows.keep_steps = b_rows.keep_grid = true;
  const fs::path a_dir = test::fresh_temp_dir("one_system_pivoted"), b_dir = test::fresh_temp_dir("one_system_jointed");
  const SolveOutcome a = run_scene(pivoted, a_dir, &a_rows), b = run_scene(jointed, b_dir, &b_rows);
  REQUIRE(a.run.status == RunStatus::Success);
  REQUIRE(b.run.status == RunStatus::Success);

  // One recorder: the rows in memory are the files' rows, for both column sets.
  for (const auto* run : {&a_rows, &b_rows}) {
    REQUIRE(run->step_columns.size() >= 3);
    CHECK(run->step_columns[0] == "t");
    CHECK(run->step_columns[1] == "h");
    CHECK(run->step_columns[2] == "order");
    CHECK(run->steps.size() % run->step_columns.size() == 0);
    CHECK(run->grid.size() == 11 * run->grid_columns.size());  // t = 0, 0.01, ..., 0.1
  }
  CHECK(static_cast<long>(a_rows.steps.size() / a_rows.step_columns.size()) == a.run.counters.steps);
  CHECK(static_cast<long>(b_rows.steps.size() / b_rows.step_columns.size()) == b.run.counters.steps);
  const std::string a_csv = test::read_file(a_dir / "steps.csv"), b_csv = test::read_file(b_dir / "steps.csv");
  CHECK(a_csv.find("\nt,h,order,") != std::string::npos);
  CHECK(b_csv.find("\nt,h,order,") != std::string::npos);

  // One summary: the same writer, so the keys differ by exactly what each
  // column set adds (a renamed key in one kind of run fails here).
  const nlohmann::json sa = nlohmann::json::parse(test::read_file(a_dir / "summary.json"));
  const nlohmann::json sb = nlohmann::json::parse(test::read_file(b_dir / "summary.json"));
  CHECK(sa.dump() == nlohmann::json::parse(a.summary).dump());  // the file is the outcome's summary
  const std::set<std::string> one_body_only{"multipliers", "final_row"};
  const std::set<std::string> mechanism_only{"bodies", "joints", "nonzeros", "start_warnings", "recorded_parts",
                                             "mobility", "redundant_rows", "reactions_determined",
                                             "reactions_indeterminate_joints", "reactions_method", "row_subset"};
  CHECK(minus(keys(sa), keys(sb)) == one_body_only);
  CHECK(minus(keys(sb), keys(sa)) == mechanism_only);
  for (const char* group : {"maxima", "final", "accuracy_check", "counters"}) {
    CAPTURE(group);
    const std::set<std::string> extra_a = minus(keys(sa[group]), keys(sb[group]));
    const std::set<std::string> extra_b = minus(keys(sb[group]), keys(sa[group]));
    CHECK(extra_b.empty());  // a mechanism reports nothing under another name
    for (const std::string& k : extra_a)  // a single body adds its own state and vertical momentum
      CHECK_MESSAGE((k == "q_WB" || k == "omega_B" || k.find("vertical_momentum") != std::string::npos), k);
  }
  CHECK(keys(sa["configuration"]["solver"]) == keys(sb["configuration"]["solver"]));
  CHECK(keys(sa["configuration"]["formulation"]) == keys(sb["configuration"]["formulation"]));

  // The same top: equal energy at the start (the potential's zero is the
  // pivot in both), and the same orientation at the end of the grid.
  const double H0a = sa["final"]["initial_energy"], H0b = sb["final"]["initial_energy"];
  CHECK(std::abs(H0a - H0b) < 1e-9 * std::abs(H0a));
  const std::size_t na = a_rows.grid_columns.size(), nb = b_rows.grid_columns.size();
  const double* last_a = a_rows.grid.data() + 10 * na;
  const double* last_b = b_rows.grid.data() + 10 * nb;
  CHECK(last_a[0] == doctest::Approx(0.1));
  CHECK(last_b[0] == doctest::Approx(0.1));
  const Vec4 qa(last_a[column(a_rows.grid_columns, "qw")], last_a[column(a_rows.grid_columns, "qx")],
                last_a[column(a_rows.grid_columns, "qy")], last_a[column(a_rows.grid_columns, "qz")]);
  const Vec4 qb(last_b[column(b_rows.grid_columns, "top.qw")], last_b[column(b_rows.grid_columns, "top.qx")],
                last_b[column(b_rows.grid_columns, "top.qy")], last_b[column(b_rows.grid_columns, "top.qz")]);
  CHECK(so3::quaternion_distance(qa, qb) < 1e-6);
}

TEST_CASE("one system: compare runs a one-body scene and its mechanism twin through the same rows") {
  const Scene pivoted = shipped("heavy_top", 0.05), jointed = shipped("heavy_top_absolute", 0.05);
  CompareOptions opt;
  opt.repeat = 1;
  opt.only = {"quaternion/euler/ggl", "linear/euler/index1"};
  opt.error_estimate = false;
  opt.out = test::fresh_temp_dir("one_system_compare_pivoted");
  const CompareReport a = compare_scene(pivoted, opt, nullptr);
  opt.out = test::fresh_temp_dir("one_system_compare_jointed");
  const CompareReport b = compare_scene(jointed, opt, nullptr);
  REQUIRE(a.reference.ok);
  REQUIRE(b.reference.ok);
  REQUIRE(a.rows.size() == 2);
  REQUIRE(b.rows.size() == 2);
  for (std::size_t i = 0; i < 2; ++i) {
    CAPTURE(a.rows[i].combination.name());
    CHECK(a.rows[i].combination.name() == b.rows[i].combination.name());
    REQUIRE(a.rows[i].outcome.run.status == RunStatus::Success);
    REQUIRE(b.rows[i].outcome.run.status == RunStatus::Success);
    // Each against its own tight reference, both as accurate as rtol 1e-10 promises.
    CHECK(a.rows[i].error_max_rad < 1e-6);
    CHECK(b.rows[i].error_max_rad < 1e-6);
    // The rows' summaries come from the one writer (the test above checks its keys).
    CHECK(nlohmann::json::parse(a.rows[i].outcome.summary).contains("accuracy_check"));
    CHECK(nlohmann::json::parse(b.rows[i].outcome.summary).contains("accuracy_check"));
  }
}

TEST_SUITE_END();
