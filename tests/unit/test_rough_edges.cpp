// The rough edges a new user meets: a rejected command leaves no output
// folder, and compare and study keep step files only when asked. (The
// message fixes -- JSON scenes, NaN/Infinity, 1e300 rad/s, a 1e-300
// quaternion -- are in the bad-input corpus, tests/bad_scenes/.)
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "cli_runner.hpp"

TEST_SUITE_BEGIN("system");

namespace fs = std::filesystem;
using rigidae::test::fresh_temp_dir;
using rigidae::test::run_cli;

namespace {
const std::string kHeavyTop = std::string(RIGIDAE_SOURCE_DIR) + "/problems/heavy_top.toml";
}  // namespace

TEST_CASE("rough edges: a rejected command leaves no output folder") {
  const fs::path dir = fresh_temp_dir("rejected");
  // Rejected after the run's files were opened (klu needs an exact or central Jacobian).
  auto r = run_cli("solve " + kHeavyTop + " --linear-solver klu --jacobian ida_dq --out " + (dir / "solve" / "x").string());
  CHECK(r.exit_code == 2);
  CHECK(!fs::exists(dir / "solve"));
  r = run_cli("compare " + kHeavyTop + " --only nothing_matches --out " + (dir / "compare").string());
  CHECK(r.exit_code == 2);
  CHECK(!fs::exists(dir / "compare"));
  std::ofstream(dir / "s.toml") << "schema_version = 1\nname = \"s\"\nscenes = [\"" << kHeavyTop
                                << "\"]\n[grid]\ncombinations = [\"quaternion/euler/ggl\"]\nrtol = [1e-6]\n";
  r = run_cli("study run " + (dir / "s.toml").string() + " --run no_such_run --out " + (dir / "study").string());
  CHECK(r.exit_code == 2);
  CHECK(!fs::exists(dir / "study"));
  // A folder that existed before is left alone, even if empty.
  fs::create_directories(dir / "mine");
  r = run_cli("compare " + kHeavyTop + " --only nothing_matches --out " + (dir / "mine").string());
  CHECK(r.exit_code == 2);
  CHECK(fs::exists(dir / "mine"));
}

TEST_CASE("rough edges: compare and study keep step files only with --keep-steps") {
  const fs::path dir = fresh_temp_dir("keep_steps");
  const std::string cmp = "compare " + kHeavyTop + " --t-end 0.05 --repeat 1 --quiet --only quaternion/euler/ggl --out ";
  REQUIRE(run_cli(cmp + (dir / "c1").string()).exit_code == 0);
  const fs::path run1 = dir / "c1" / "quaternion-euler-ggl";
  CHECK(!fs::exists(run1 / "steps.csv"));
  for (const char* f : {"summary.json", "trajectory.csv", "events.csv"}) CHECK(fs::exists(run1 / f));
  CHECK(fs::exists(dir / "c1" / "compare.csv"));
  REQUIRE(run_cli(cmp + (dir / "c2").string() + " --keep-steps").exit_code == 0);
  CHECK(fs::exists(dir / "c2" / "quaternion-euler-ggl" / "steps.csv"));

  std::ofstream(dir / "s.toml") << "schema_version = 1\nname = \"s\"\nscenes = [\"" << kHeavyTop
                                << "\"]\n[grid]\ncombinations = [\"quaternion/euler/ggl\"]\nrtol = [1e-6]\n"
                                   "[timing]\nwarmups = 0\nrepeats = 1\n";
  for (const bool keep : {false, true}) {
    const fs::path out = dir / (keep ? "s_keep" : "s_drop");
    REQUIRE(run_cli("study " + (dir / "s.toml").string() + " --no-plot --quiet --out " + out.string() +
                    (keep ? " --keep-steps" : ""))
                .exit_code == 0);
    int runs = 0, steps = 0;
    for (const auto& e : fs::recursive_directory_iterator(out)) {
      runs += e.path().filename() == "run.json";
      steps += e.path().filename() == "steps.csv" && e.path().parent_path().filename() != "reference";
    }
    CHECK(runs == 1);
    CHECK(steps == (keep ? 1 : 0));
  }
}

TEST_SUITE_END();
