// Accuracy studies: the measures they report, how they split into shards,
// and that an interrupted study resumes without redoing finished runs.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "cli_runner.hpp"
#include "rigidae/app/accuracy.hpp"
#include "rigidae/app/study.hpp"
#include "rigidae/core/error.hpp"
#include "rigidae/io/scene_loader.hpp"
#include "rigidae/solver/ida_driver.hpp"
#include "test_scenes.hpp"

TEST_SUITE_BEGIN("system");

using namespace rigidae;
namespace fs = std::filesystem;

namespace {

// The torque-free body of problems/free_body.toml, over a shorter time.
constexpr const char* kFreeBody = R"(schema_version = 1
name = "free_body_short"
[body]
mass = 1.0
inertia_principal = [2.0, 3.0, 4.0]
[support]
type = "free"
[initial]
quaternion = [1.0, 0.0, 0.0, 0.0]
angular_velocity = [0.1, 2.0, 0.1]
[time]
start = 0.0
end = 4.0
output_step = 0.05
)";

StudySpec write_and_load_study(const fs::path& dir, const std::string& grid) {
  std::ofstream(dir / "free_body_short.toml") << kFreeBody;
  std::ofstream(dir / "study.toml") << "schema_version = 1\nname = \"t\"\nscenes = [\"free_body_short.toml\"]\n"
                                    << "[timing]\nwarmups = 0\nrepeats = 1\n[grid]\n"
                                    << grid;
  return load_study((dir / "study.toml").string());
}

nlohmann::json run_record(const fs::path& out, const StudySpec& spec, const StudyRun& r) {
  return nlohmann::json::parse(test::read_file(run_folder(out, spec, r) / "run.json"));
}

// Slope of log10(error) against log10(rtol), least squares.
double log_log_slope(const std::vector<double>& rtol, const std::vector<double>& err) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double n = static_cast<double>(rtol.size());
  for (std::size_t i = 0; i < rtol.size(); ++i) {
    const double x = std::log10(rtol[i]), y = std::log10(err[i]);
    sx += x, sy += y, sxx += x * x, sxy += x * y;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

}  // namespace

TEST_CASE("scd and mescd follow the IVP Test Set's definitions on a hand-made case") {
  Eigen::VectorXd y(3), ref(3);
  ref << 1.0, 2.0, -4.0;
  y << 1.0, 2.002, -4.0;  // relative error 1e-3 in one component
  CHECK(significant_correct_digits(y, ref) == doctest::Approx(3.0).epsilon(1e-9));
  // mixed: |dy| / (atol/rtol + |yref|) = 0.002 / (2 + 2)
  CHECK(mixed_significant_correct_digits(y, ref, 2.0) == doctest::Approx(-std::log10(0.002 / 4.0)).epsilon(1e-9));
  y << 1.0 + 1e-7, 2.0, -4.0 * (1 + 1e-5);  // the worst component decides
  CHECK(significant_correct_digits(y, ref) == doctest::Approx(5.0).epsilon(1e-6));
  const double all_digits = -std::log10(std::numeric_limits<double>::epsilon() / 2);
  CHECK(significant_correct_digits(ref, ref) == doctest::Approx(all_digits));
  ref << 0.0, 2.0, -4.0;
  y << 1e-3, 2.0, -4.0 * (1 + 1e-5);  // a zero reference component is left out, as in the Test Set
  CHECK(significant_correct_digits(y, ref) == doctest::Approx(5.0).epsilon(1e-6));
  // mixed: the zero component counts, against atol/rtol = 1
  CHECK(mixed_significant_correct_digits(y, ref, 1.0) == doctest::Approx(3.0).epsilon(1e-9));
}

TEST_CASE("a study's shards cover every run exactly once, for any number of shards") {
  StudySpec spec;
  spec.scenes = {test::heavy_top_scene(), test::heavy_top_scene()};
  spec.scenes[1].name = "other";
  spec.rtols = {1e-4, 1e-6, 1e-8};
  spec.skip = {"linear"};
  const std::vector<StudyRun> plan = plan_study(spec);
  // 2 scenes x (2 Euler-angle forms + 2 x 6 quaternion) x 3 tolerances
  REQUIRE(plan.size() == 2u * 14u * 3u);
  std::set<std::string> ids;
  for (const StudyRun& r : plan) ids.insert(r.id(spec));
  CHECK(ids.size() == plan.size());  // distinct folders
  for (int n = 1; n <= 9; ++n) {
    std::vector<int> seen(plan.size(), 0);
    for (int i = 0; i < n; ++i)
      for (const StudyRun& r : select_shard(plan, {i, n})) ++seen[static_cast<std::size_t>(r.index)];
    for (std::size_t k = 0; k < plan.size(); ++k) CHECK_MESSAGE(seen[k] == 1, "run ", k, " with ", n, " shards");
  }
  CHECK(parse_shard("2/5").index == 2);
  CHECK(parse_shard("2/5").count == 5);
  for (const char* bad : {"5/5", "-1/3", "1/0", "a/3", "1", "1/3x"}) CHECK_THROWS_AS(parse_shard(bad), InputError);
}

TEST_CASE("a Slurm array task picks its slice from the environment") {
  ::unsetenv("SLURM_ARRAY_TASK_ID");
  CHECK_FALSE(shard_from_slurm().has_value());
  ::setenv("SLURM_ARRAY_TASK_ID", "7", 1);
  ::setenv("SLURM_ARRAY_TASK_MIN", "5", 1);
  ::setenv("SLURM_ARRAY_TASK_COUNT", "4", 1);
  const auto s = shard_from_slurm();
  REQUIRE(s.has_value());
  CHECK(s->index == 2);
  CHECK(s->count == 4);
  ::setenv("SLURM_ARRAY_TASK_ID", "9", 1);  // beyond the array: not a slice
  CHECK_THROWS_AS(shard_from_slurm(), InputError);
  ::unsetenv("SLURM_ARRAY_TASK_ID");
  ::unsetenv("SLURM_ARRAY_TASK_MIN");
  ::unsetenv("SLURM_ARRAY_TASK_COUNT");
}

TEST_CASE("an interrupted study resumes without redoing complete runs") {
  const fs::path dir = test::fresh_temp_dir("study_resume");
  const StudySpec spec =
      write_and_load_study(dir, "combinations = [\"quaternion/euler/ggl\", \"euler/euler/any\"]\nrtol = [1e-4, 1e-6]\n");
  const std::vector<StudyRun> plan = plan_study(spec);
  REQUIRE(plan.size() == 4u);
  const fs::path out = dir / "out";
  StudyRunOptions opt;
  opt.out = out;

  // A first worker stops after its first run (Ctrl-C between runs).
  int finished = 0;
  opt.progress = [&](const StudyProgress&) {
    if (++finished == 1) g_interrupt_requested.store(true);
  };
  CHECK_FALSE(run_study(spec, plan, opt));
  g_interrupt_requested.store(false);
  CHECK(run_complete(out, spec, plan[0]));
  CHECK_FALSE(run_complete(out, spec, plan[1]));
  // A second worker was killed inside run 2: its temporary folder stays behind.
  const fs::path stale = run_folder(out, spec, plan[2]).parent_path() / ".stale.tmp-host-1";
  fs::create_directories(stale);
  std::ofstream(stale / "steps.csv") << "# cut short\n";
  // Shard 1/2 (runs 1 and 3) completes meanwhile.
  opt.progress = nullptr;
  CHECK(run_study(spec, select_shard(plan, {1, 2}), opt));
  const std::string first = test::read_file(run_folder(out, spec, plan[0]) / "run.json");
  const std::string second = test::read_file(run_folder(out, spec, plan[1]) / "run.json");

  int skipped = 0, done = 0;
  opt.progress = [&](const StudyProgress& p) {
    skipped = p.skipped;
    done = p.done;
  };
  CHECK(run_study(spec, plan, opt));
  CHECK(done == 4);
  CHECK(skipped == 3);  // only run 2 was left
  // Byte-identical records: the wall times in them would differ if redone.
  CHECK(test::read_file(run_folder(out, spec, plan[0]) / "run.json") == first);
  CHECK(test::read_file(run_folder(out, spec, plan[1]) / "run.json") == second);

  std::vector<std::string> missing;
  collect_study(spec, out, &missing);
  CHECK(missing.empty());
  std::ifstream csv(out / "results.csv");
  std::string line;
  int rows = 0;
  while (std::getline(csv, line)) rows += line.rfind("t,free_body_short,", 0) == 0;
  CHECK(rows == 4);
}

TEST_CASE("the error falls in step with rtol for the Euler forms, against the exact free body") {
  const fs::path dir = test::fresh_temp_dir("study_proportional");
  const StudySpec spec = write_and_load_study(
      dir, "combinations = [\"quaternion/euler/ggl\", \"euler/euler/any\", \"quaternion/lagrange/ggl\"]\n"
           "rtol = [1e-5, 1e-6, 1e-7, 1e-8, 1e-9]\n");
  const fs::path out = dir / "out";
  StudyRunOptions opt;
  opt.out = out;
  REQUIRE(run_study(spec, plan_study(spec), opt));
  std::map<std::string, std::vector<double>> rtol, err, lambda;
  for (const StudyRun& r : plan_study(spec)) {
    const nlohmann::json j = run_record(out, spec, r);
    REQUIRE(j["status"] == "success");
    REQUIRE(j["reference"].get<std::string>().rfind("exact:", 0) == 0);
    rtol[r.combination.name()].push_back(r.rtol);
    err[r.combination.name()].push_back(j["errors"]["orientation_rad"]["final"].get<double>());
    if (j["errors"]["lambda"]["max"].is_number()) lambda[r.combination.name()].push_back(j["errors"]["lambda"]["max"]);
  }
  // Measured slopes: 1.0-1.1 for both Euler forms; the Lagrange form's
  // error falls more slowly (~0.6-0.8, README "Choosing a scheme").
  for (const char* c : {"quaternion/euler/ggl", "euler/euler/any"}) {
    const double slope = log_log_slope(rtol[c], err[c]);
    INFO(c, " slope ", slope);
    CHECK(slope > 0.8);
    CHECK(slope < 1.3);
  }
  const double lagrange = log_log_slope(rtol["quaternion/lagrange/ggl"], err["quaternion/lagrange/ggl"]);
  CHECK(lagrange > 0.4);
  // Its multipliers converge too, to the values the DAE takes on the exact solution.
  const std::vector<double>& l = lambda["quaternion/lagrange/ggl"];
  REQUIRE(l.size() == 5u);
  CHECK(l.back() < 1e-2 * l.front());
}

TEST_CASE("study files: errors name the file, line and key, and what would be valid") {
  const fs::path dir = test::fresh_temp_dir("study_errors");
  std::ofstream(dir / "free_body_short.toml") << kFreeBody;
  auto message = [&](const std::string& text) {
    std::ofstream(dir / "bad.toml") << text;
    try {
      load_study((dir / "bad.toml").string());
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string head = "schema_version = 1\nscenes = [\"free_body_short.toml\"]\n";
  std::string m = message(head + "[grid]\nrtols = [1e-6]\n");
  CHECK(m.find("bad.toml:4:1: error: unknown key 'rtols' in [grid]; did you mean 'rtol'?") != std::string::npos);
  m = message(head + "[grid]\nrtol = [1e-6, 2.0]\n");
  CHECK(m.find("bad.toml:4:15: error: 'grid.rtol[1]' = 2 must lie in [1e-14, 1)") != std::string::npos);
  m = message(head + "[grid]\nrtol = [1e-6]\ncombinations = [\"quaternoin/*/ggl\"]\n");
  CHECK(m.find("bad.toml:5:17: error: 'grid.combinations[0]' = \"quaternoin/*/ggl\" matches no combination") !=
        std::string::npos);
  m = message("schema_version = 1\nscenes = [\"nowhere.toml\"]\n[grid]\nrtol = [1e-6]\n");
  CHECK(m.find("bad.toml:2:11: error: scene file") != std::string::npos);
  CHECK(m.find("does not exist") != std::string::npos);
  m = message(head + "[grid]\nrtol = [1e-6]\ncombinations = [\"ggl\"]\nskip = [\"quaternion\", \"linear\"]\n");
  CHECK(m.find("bad.toml:3:1: error: [grid] combinations and skip leave no combination to run") != std::string::npos);
  m = message(head + "reference_rtol = 1e-3\n[grid]\nrtol = [1e-6]\n");
  CHECK(m.find("bad.toml:3:18: error: 'reference_rtol' = 0.001 must be <= 1e-06, the smallest grid.rtol") != std::string::npos);
  std::ofstream(dir / "slash.toml") << std::string(kFreeBody).replace(std::string(kFreeBody).find("free_body_short"), 15, "a,b");
  m = message("schema_version = 1\nscenes = [\"slash.toml\"]\n[grid]\nrtol = [1e-6]\n");
  CHECK(m.find("bad.toml:2:11: error: scene") != std::string::npos);
  CHECK(m.find("scene names must be letters, digits") != std::string::npos);
  m = message(head + "[grid]\nrtol = [1e-6]\n[timing]\nrepeats = 0\n");
  CHECK(m.find("bad.toml:6:11: error: 'timing.repeats' = 0 must be an integer from 1 to 1000") != std::string::npos);
}

TEST_CASE("a scene may insist on the exact reference, and is told when it has none") {
  const std::string base = std::string(RIGIDAE_SOURCE_DIR) + "/problems/";
  const Scene top = io::parse_scene("reference = \"exact\"\n" + test::read_file(base + "heavy_top.toml"), "top.toml");
  CHECK(top.reference == ReferenceKind::Exact);
  // Off-axis centre of mass: not a Lagrange top.
  std::string text = test::read_file(base + "heavy_top.toml");
  const std::size_t at = text.find("center_of_mass");
  REQUIRE(at != std::string::npos);
  text.replace(at, text.find('\n', at) - at, "center_of_mass = [0.1, 1.0, 0.0]");
  try {
    io::parse_scene("reference = \"exact\"\n" + text, "off_axis.toml");
    FAIL("an off-axis heavy top was given an exact reference");
  } catch (const InputError& e) {
    const std::string m = e.what();
    CHECK(m.find("off_axis.toml:") == 0);
    CHECK(m.find("'reference' = \"exact\" but this scene has no closed-form solution") != std::string::npos);
  }
}

TEST_CASE("tolerances that differ only in the seventh digit get their own run folders") {
  StudySpec spec;
  spec.scenes = {test::heavy_top_scene()};
  spec.rtols = {1e-6, 1.0000001e-6};
  spec.only = {"quaternion/euler/ggl"};
  const std::vector<StudyRun> plan = plan_study(spec);
  REQUIRE(plan.size() == 2u);
  CHECK(plan[0].id(spec) != plan[1].id(spec));
}

TEST_CASE("a leftover folder without run.json at a run's place is replaced, not taken as done") {
  const fs::path dir = test::fresh_temp_dir("study_leftover");
  const StudySpec spec = write_and_load_study(dir, "combinations = [\"quaternion/euler/index1\"]\nrtol = [1e-4]\n");
  const std::vector<StudyRun> plan = plan_study(spec);
  const fs::path out = dir / "out";
  fs::create_directories(run_folder(out, spec, plan[0]));
  std::ofstream(run_folder(out, spec, plan[0]) / "steps.csv") << "# someone else's\n";
  CHECK_FALSE(run_complete(out, spec, plan[0]));
  StudyRunOptions opt;
  opt.out = out;
  CHECK(run_study(spec, plan, opt));
  CHECK(run_complete(out, spec, plan[0]));
  CHECK(run_record(out, spec, plan[0])["status"] == "success");
}

TEST_CASE("a tight reference that fails stops the study with the reason, and leaves no reference behind") {
  const fs::path dir = test::fresh_temp_dir("study_failed_reference");
  // An off-axis centre of mass: no closed form, so the reference is a tight
  // run; one step allowed makes it fail at once.
  std::string scene = kFreeBody;
  const std::string free_support = "[support]\ntype = \"free\"";
  scene.replace(scene.find(free_support), free_support.size(),
                "center_of_mass = [0.1, 0.0, 0.2]\n[support]\ntype = \"fixed_point\"");
  scene += "[solver]\nmax_steps = 1\n";
  std::ofstream(dir / "free_body_short.toml") << scene;
  std::ofstream(dir / "study.toml") << "schema_version = 1\nname = \"t\"\nscenes = [\"free_body_short.toml\"]\n"
                                       "[timing]\nwarmups = 0\nrepeats = 1\n[grid]\ncombinations = [\"euler/euler/any\"]\n"
                                       "rtol = [1e-4]\n";
  const StudySpec spec = load_study((dir / "study.toml").string());
  StudyRunOptions opt;
  opt.out = dir / "out";
  try {
    run_study(spec, plan_study(spec), opt);
    FAIL("the study went on without a reference");
  } catch (const SolverError& e) {
    CHECK(std::string(e.what()).find("the tight reference of scene 'free_body_short'") != std::string::npos);
  }
  CHECK_FALSE(fs::exists(opt.out / "reference" / "free_body_short"));
  CHECK_FALSE(run_complete(opt.out, spec, plan_study(spec)[0]));
}

TEST_SUITE_END();
