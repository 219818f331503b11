// Recording: what --record writes, the shortest-double writer against
// std::to_chars, output at given times against the even grid.
#include <doctest/doctest.h>

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "record/shortest_double.hpp"
#include "rigidae/app/error_estimate.hpp"
#include "rigidae/io/scene_loader.hpp"
#include "rigidae/app/solve.hpp"
#include "test_multibody_scenes.hpp"
#include "test_scenes.hpp"

TEST_SUITE_BEGIN("system");

namespace fs = std::filesystem;
using namespace rigidae;

namespace {

std::string to_chars_text(double x) {
  char buf[64];
  return std::string(buf, std::to_chars(buf, buf + sizeof buf, x).ptr);
}

std::string shortest_text(double x) {
  char buf[64];
  return std::string(buf, record_detail::write_shortest(buf, x));
}

std::string read_all(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

// The rows of a CSV file written by rigidae (units line and header skipped), as numbers.
std::vector<std::vector<double>> csv_rows(const fs::path& p) {
  std::ifstream f(p);
  std::string line;
  std::getline(f, line);
  std::getline(f, line);
  std::vector<std::vector<double>> rows;
  while (std::getline(f, line)) {
    std::vector<double> row;
    std::stringstream cells(line);
    std::string cell;
    while (std::getline(cells, cell, ',')) row.push_back(std::strtod(cell.c_str(), nullptr));
    rows.push_back(row);
  }
  return rows;
}

}  // namespace

TEST_CASE("recording: the shortest-double writer writes exactly what std::to_chars writes") {
  std::mt19937_64 rng(20261125);
  long checked = 0;
  auto same = [&](double x) {
    const std::string a = to_chars_text(x), b = shortest_text(x);
    if (a != b) FAIL_CHECK("x = " << a << " written as " << b);
    ++checked;
  };
  // Every bit pattern class: random bits cover all exponents, subnormals, NaN and inf.
  for (int i = 0; i < 1'000'000; ++i) {
    const std::uint64_t bits = rng();
    double x;
    std::memcpy(&x, &bits, sizeof x);
    same(x);
  }
  // Values a run writes: few digits, near the fixed/scientific crossover.
  std::uniform_int_distribution<long> digits(0, 999999);
  std::uniform_int_distribution<int> exponent(-25, 25);
  for (int i = 0; i < 1'000'000; ++i) same(static_cast<double>(digits(rng)) * std::pow(10.0, exponent(rng)));
  for (int e = -325; e <= 308; ++e) {
    same(std::pow(10.0, e));
    same(-std::pow(10.0, e));
    same(1.5 * std::pow(10.0, e));
  }
  for (long k = -20000; k <= 20000; ++k) same(static_cast<double>(k));
  for (double x : {0.0, -0.0, 5e-324, 2.2250738585072014e-308, 1.7976931348623157e308, 0.1, 0.3, 1e16, 1e17,
                   123456789012345680.0, 9007199254740993.0, 0.0001, 0.00001, 1e-5, 1.234e-5})
    same(x);
  CHECK(checked > 2'000'000);
}

TEST_CASE("recording: --record steps, grid and none write what they say, and the run is the same") {
  const Scene base = test::heavy_top_scene();
  Scene s = base;
  s.time = {0.0, 0.3, 0.01};
  struct Mode {
    RecordMode mode;
    const char* name;
  };
  std::vector<SolveOutcome> outcomes;
  std::vector<fs::path> dirs;
  for (const Mode m : {Mode{RecordMode::Steps, "steps"}, Mode{RecordMode::Grid, "grid"}, Mode{RecordMode::None, "none"}}) {
    Scene x = s;
    x.output.record = m.mode;
    const fs::path dir = test::fresh_temp_dir(std::string("record_") + m.name);
    // A previous run's files must not pass for this run's.
    std::ofstream(dir / "steps.csv") << "stale";
    std::ofstream(dir / "trajectory.csv") << "stale";
    outcomes.push_back(solve_scene(x, dir));
    dirs.push_back(dir);
    CHECK(fs::exists(dir / "summary.json"));
    CHECK(fs::exists(dir / "events.csv"));
    CHECK(fs::exists(dir / "steps.csv") == (m.mode == RecordMode::Steps));
    CHECK(fs::exists(dir / "trajectory.csv") == (m.mode != RecordMode::None));
    CHECK(!fs::exists(dir / "steps.npy"));
  }
  // The same steps, the same extremes: recording observes every step whatever it writes.
  for (const SolveOutcome& o : outcomes) {
    CHECK(o.run.status == RunStatus::Success);
    CHECK(o.run.counters.steps == outcomes[0].run.counters.steps);
    CHECK(o.extremes.steps_recorded == outcomes[0].run.counters.steps);
    CHECK(o.extremes.max_drift_position == outcomes[0].extremes.max_drift_position);
    CHECK(o.extremes.max_abs_energy_error == outcomes[0].extremes.max_abs_energy_error);
    CHECK((o.extremes.last.q_WB - outcomes[0].extremes.last.q_WB).norm() == 0.0);
  }
  CHECK(read_all(dirs[0] / "trajectory.csv") == read_all(dirs[1] / "trajectory.csv"));
  // steps.csv has one row per step.
  CHECK(static_cast<long>(csv_rows(dirs[0] / "steps.csv").size()) == outcomes[0].run.counters.steps);
}

TEST_CASE("recording: the record modes of a multibody run") {
  Scene s = test::absolute_heavy_top(Coordinates::Quaternion, Equations::Euler, "ggl");
  s.time = {0.0, 0.05, 0.01};
  for (const RecordMode mode : {RecordMode::Steps, RecordMode::Grid, RecordMode::None}) {
    Scene x = s;
    x.output.record = mode;
    const fs::path dir = test::fresh_temp_dir("record_multibody_" + std::to_string(static_cast<int>(mode)));
    const SolveOutcome o = solve_scene(x, dir);
    CHECK(o.run.status == RunStatus::Success);
    CHECK(o.extremes.steps_recorded == o.run.counters.steps);
    CHECK(fs::exists(dir / "summary.json"));
    CHECK(fs::exists(dir / "steps.csv") == (mode == RecordMode::Steps));
    CHECK(fs::exists(dir / "trajectory.csv") == (mode != RecordMode::None));
  }
}

namespace {

// The columns of each quaternion's scalar part (qw, BODY.qw).
std::vector<std::size_t> quaternion_columns(const fs::path& csv) {
  std::ifstream f(csv);
  std::string line;
  std::getline(f, line);
  std::getline(f, line);
  std::vector<std::size_t> cols;
  std::stringstream cells(line);
  std::string cell;
  for (std::size_t k = 0; std::getline(cells, cell, ','); ++k)
    if (cell == "qw" || (cell.size() > 3 && cell.compare(cell.size() - 3, 3, ".qw") == 0)) cols.push_back(k);
  REQUIRE(!cols.empty());
  return cols;
}

// The row of `rows` whose t (column 0) is within 1e-12 of t.
const std::vector<double>* row_at(const std::vector<std::vector<double>>& rows, double t) {
  for (const auto& r : rows)
    if (std::abs(r[0] - t) <= 1e-12) return &r;
  return nullptr;
}

void check_times_against_even_grid(const Scene& even_scene, const std::vector<double>& times, const char* name) {
  const fs::path even_dir = test::fresh_temp_dir(std::string(name) + "_even");
  const fs::path given_dir = test::fresh_temp_dir(std::string(name) + "_given");
  const SolveOutcome even = solve_scene(even_scene, even_dir);
  Scene given = even_scene;
  given.time.output_times = times;
  const SolveOutcome g = solve_scene(given, given_dir);
  REQUIRE(even.run.status == RunStatus::Success);
  REQUIRE(g.run.status == RunStatus::Success);
  CHECK(g.run.counters.steps == even.run.counters.steps);  // output does not change the steps
  const auto even_rows = csv_rows(even_dir / "trajectory.csv");
  const auto given_rows = csv_rows(given_dir / "trajectory.csv");
  REQUIRE(given_rows.size() == times.size());
  for (std::size_t k = 0; k < times.size(); ++k) {
    CHECK(given_rows[k][0] == times[k]);  // exactly the time asked for
    const std::vector<double>* e = row_at(even_rows, times[k]);
    REQUIRE(e != nullptr);
    REQUIRE(e->size() == given_rows[k].size());
    // The same interpolation of the same steps; only t's last bit may differ,
    // and a quaternion's sign (kept continuous from one output to the next).
    std::vector<double> mine = given_rows[k];
    for (std::size_t c : quaternion_columns(given_dir / "trajectory.csv")) {
      double dot = 0.0;
      for (int i = 0; i < 4; ++i) dot += mine[c + i] * (*e)[c + i];
      if (dot < 0)
        for (int i = 0; i < 4; ++i) mine[c + i] = -mine[c + i];
    }
    for (std::size_t c = 1; c < e->size(); ++c) CHECK(std::abs((*e)[c] - mine[c]) <= 1e-11 * (1.0 + std::abs((*e)[c])));
  }
}

}  // namespace

TEST_CASE("recording: output.times gives the even grid's values at the times asked for (one body)") {
  Scene s = test::heavy_top_scene();
  s.time = {0.0, 0.5, 0.01};
  // 0 and 0.5 are grid points exactly; 0.25 and 0.37 within round-off of start + k step.
  check_times_against_even_grid(s, {0.0, 0.25, 0.37, 0.5}, "times_one_body");
  // Times that leave out the start and the end: the run still goes to the end.
  Scene t = s;
  t.time.output_times = {0.1, 0.2};
  const fs::path dir = test::fresh_temp_dir("times_inner");
  const SolveOutcome o = solve_scene(t, dir);
  CHECK(o.run.t_reached == doctest::Approx(0.5));
  CHECK(csv_rows(dir / "trajectory.csv").size() == 2);
}

TEST_CASE("recording: output.times gives the even grid's values at the times asked for (multibody)") {
  Scene s = test::absolute_heavy_top(Coordinates::Quaternion, Equations::Euler, "ggl");
  s.time = {0.0, 0.1, 0.01};
  check_times_against_even_grid(s, {0.02, 0.05, 0.1}, "times_multibody");
}

TEST_CASE("recording: the tight tolerances of --error-estimate stop at the settings table's limits") {
  SolverSettings s;
  s.rtol = 1e-6;
  s.atol = 1e-7;
  CHECK(tight_tolerances(s).first == doctest::Approx(1e-8));
  CHECK(tight_tolerances(s).second == doctest::Approx(1e-9));
  s.rtol = 2e-14;
  s.atol = 1e-99;
  CHECK(tight_tolerances(s).first == kMinRelativeTolerance);
  CHECK(tight_tolerances(s).second == kMinAbsoluteTolerance);
}

TEST_CASE("recording: --error-estimate is within a small factor of the true (closed-form) error") {
  // A free body near its intermediate axis and a Lagrange top: closed forms (exact/).
  for (const char* name : {"free_body", "lagrange_top"}) {
    for (const double rtol : {1e-5, 1e-7}) {
      CAPTURE(name);
      CAPTURE(rtol);
      Scene s = io::load_scene(std::string(RIGIDAE_SOURCE_DIR) + "/problems/" + name + ".toml");
      s.time.end = std::min(s.time.end, 5.0);
      s.solver.rtol = s.solver.atol = rtol;
      s.output.record = RecordMode::Grid;
      const fs::path dir = test::fresh_temp_dir(std::string("estimate_") + name + std::to_string(rtol));
      const SolveOutcome o = solve_scene(s, dir);
      REQUIRE(o.run.status == RunStatus::Success);
      // The closed form decides; the companion's estimate is kept beside it.
      const ErrorEstimate e = accuracy_verdict(s, o, true, "--error-estimate");
      REQUIRE(e.tight_status == "success");
      REQUIRE(e.source == EstimateSource::ClosedForm);
      REQUIRE(e.companion_orientation.has_value());
      CHECK(e.companion_orientation->t_final == doctest::Approx(s.time.end));
      CHECK(std::isfinite(e.companion_wall_s));
      // The true error is well above round-off here, so a ratio is meaningful.
      REQUIRE(e.orientation.final > 1e-9);
      const double ratio_final = e.companion_orientation->final / e.orientation.final;
      const double ratio_max = e.companion_orientation->max / e.orientation.max;
      CHECK(ratio_final > 1.0 / 3.0);
      CHECK(ratio_final < 3.0);
      CHECK(ratio_max > 1.0 / 3.0);
      CHECK(ratio_max < 3.0);
      // It reaches summary.json.
      add_error_estimate_to_summary(dir / "summary.json", e);
      const std::string text = read_all(dir / "summary.json");
      CHECK(text.find("\"error_estimate\"") != std::string::npos);
      CHECK(text.find("\"companion_orientation\"") != std::string::npos);
    }
  }
}

TEST_CASE("recording: solve --record, --step-format and --error-estimate on the command line") {
  const std::string free_body = std::string(RIGIDAE_SOURCE_DIR) + "/problems/free_body.toml";
  const fs::path out = test::fresh_temp_dir("cli_record");
  auto r = test::run_cli("solve " + free_body + " --t-end 2 --record none --out " + (out / "none").string());
  CHECK(r.exit_code == 0);
  CHECK(r.output.find("events.csv, summary.json") != std::string::npos);
  CHECK(fs::exists(out / "none" / "summary.json"));
  CHECK(!fs::exists(out / "none" / "trajectory.csv"));
  CHECK(!fs::exists(out / "none" / "steps.csv"));

  r = test::run_cli("solve " + free_body + " --t-end 2 --record steps --step-format npy --quiet --out " +
                    (out / "npy").string());
  CHECK(r.exit_code == 0);
  CHECK(fs::exists(out / "npy" / "steps.npy"));
  CHECK(read_all(out / "npy" / "steps.npy").rfind("\x93NUMPY\x01", 0) == 0);

  // The estimate compares output grids: without one it is refused before anything is made.
  r = test::run_cli("solve " + free_body + " --record none --error-estimate --out " + (out / "refused").string());
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("--error-estimate") != std::string::npos);
  CHECK(!fs::exists(out / "refused"));

  r = test::run_cli("solve " + free_body + " --t-end 2 --rtol 1e-6 --atol 1e-6 --record grid --error-estimate --out " +
                    (out / "estimate").string());
  CHECK(r.exit_code == 0);
  CHECK(r.output.find("companion at rtol 1e-08") != std::string::npos);
  CHECK(r.output.find("against the closed form") != std::string::npos);
  CHECK(fs::exists(out / "estimate" / "error_estimate" / "trajectory.csv"));
  const std::string summary = read_all(out / "estimate" / "summary.json");
  CHECK(summary.find("\"error_estimate\"") != std::string::npos);
  CHECK(summary.find("\"rtol\": 1e-08") != std::string::npos);
}

TEST_CASE("recording: --output-step replaces a scene's output.times with the even grid, with a note") {
  const fs::path out = test::fresh_temp_dir("cli_output_step");
  std::string text = test::read_file(std::string(RIGIDAE_SOURCE_DIR) + "/problems/free_body.toml");
  const std::size_t at = text.find("output_step");
  REQUIRE(at != std::string::npos);
  text.erase(at, text.find('\n', at) - at);  // the scene's own grid out: output.times instead
  text += "\n[output]\ntimes = [0.1, 0.5]\n";
  const fs::path scene = out / "times.toml";
  std::ofstream(scene) << text;
  auto r = test::run_cli("solve " + scene.string() + " --t-end 1 --output-step 0.1 --out " + (out / "grid").string());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK(r.output.find("note: --output-step 0.1 s replaces the scene's 2 output times with an even grid") !=
        std::string::npos);
  const auto rows = test::read_csv_rows(out / "grid" / "trajectory.csv");
  REQUIRE(rows.size() == 11);  // t = 0, 0.1, ..., 1
  CHECK(std::stod(rows[3].at("t")) == doctest::Approx(0.3));
  CHECK(read_all(out / "grid" / "summary.json").find("\"output_step\": 0.1") != std::string::npos);
  // Without --output-step the scene's times hold.
  r = test::run_cli("solve " + scene.string() + " --t-end 1 --quiet --out " + (out / "times").string());
  REQUIRE(r.exit_code == 0);
  CHECK(test::read_csv_rows(out / "times" / "trajectory.csv").size() == 2);
}

TEST_SUITE_END();
