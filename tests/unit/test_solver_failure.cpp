// Solver failures and interruptions, through the real command line: each
// must name what stopped IDA (its flag in plain words), the time, the step
// size and a likely cause; keep every step taken on disk (steps.csv complete
// and parseable, one row per step counted in summary.json); write
// summary.json with status "failed" or "interrupted"; and exit with code 1.
// Each failure is forced cheaply (a few hundred residual evaluations).
#include <doctest/doctest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "cli_runner.hpp"

TEST_SUITE_BEGIN("system");

namespace fs = std::filesystem;
using rigidae::test::run_cli;

namespace {

const std::string kHeavyTop = std::string(RIGIDAE_SOURCE_DIR) + "/problems/heavy_top.toml";
const std::string kGimbalLock = std::string(RIGIDAE_SOURCE_DIR) + "/tests/failure_scenes/gimbal_lock.toml";

struct StepsFile {
  long rows = 0;
  double last_t = 0.0;
  bool ok = true;  // every row has the header's columns, numbers where numbers belong, t increasing
};

// Reads steps.csv as a user's script would: a '#' units line, a header, rows.
StepsFile read_steps(const fs::path& csv) {
  StepsFile f;
  std::ifstream in(csv);
  std::string line;
  REQUIRE(std::getline(in, line));
  CHECK(line.rfind("# units", 0) == 0);
  REQUIRE(std::getline(in, line));
  std::vector<std::string> header;
  for (std::stringstream ss(line); std::getline(ss, line, ',');) header.push_back(line);
  REQUIRE(header.size() > 10);
  REQUIRE(header[0] == "t");
  double previous_t = -INFINITY;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');) cells.push_back(c);
    if (cells.size() != header.size()) f.ok = false;
    for (std::size_t i = 0; i < cells.size() && i < header.size(); ++i) {
      if (header[i] == "chart") continue;  // a sequence name
      char* end = nullptr;
      const double x = std::strtod(cells[i].c_str(), &end);
      if (end == cells[i].c_str() || *end != '\0' || !std::isfinite(x)) f.ok = false;
    }
    const double t = std::strtod(cells.empty() ? "" : cells[0].c_str(), nullptr);
    if (!(t > previous_t)) f.ok = false;
    previous_t = f.last_t = t;
    ++f.rows;
  }
  return f;
}

nlohmann::json read_summary(const fs::path& dir) {
  std::ifstream in(dir / "summary.json");
  REQUIRE(in);
  return nlohmann::json::parse(in);
}

// The checks every failed or interrupted run must pass; returns the message.
// `unrecorded`: IDA steps counted in summary.json but, rightly, not in
// steps.csv (the step in which the root finding located a chart margin ends
// past it; the run stops at the root inside that step).
std::string check_stopped_run(const fs::path& out, const std::string& status, long unrecorded = 0) {
  const nlohmann::json s = read_summary(out);
  CHECK(s["status"] == status);
  const std::string message = s["message"];
  CHECK(message.find("t = ") != std::string::npos);
  CHECK(message.find("step size") != std::string::npos);
  const StepsFile steps = read_steps(out / "steps.csv");
  CHECK(steps.ok);
  CHECK(steps.rows == s["counters"]["steps"].get<long>() - unrecorded);  // every step taken is on disk
  if (steps.rows > 0) CHECK(steps.last_t <= s["t_reached"].get<double>());
  CHECK(fs::exists(out / "trajectory.csv"));
  return message;
}

}  // namespace

TEST_CASE("solver failure: Newton convergence failure (IDA_CONV_FAIL) is reported, kept and exits 1") {
  // Linear coordinates, index 2, at a first step of 1e-13 s: the iteration
  // matrix (condition ~1/h^2) is numerically singular and Newton fails at
  // every step size IDA tries.
  const fs::path out = rigidae::test::fresh_temp_dir("conv_fail");
  const auto r = run_cli("solve " + kHeavyTop + " --coordinates linear --equations lagrange --scheme index2 "
                         "--rtol 1e-13 --atol 1e-13 --initial-step 1e-13 --out " + out.string());
  CAPTURE(r.output);
  CHECK(r.exit_code == 1);
  const std::string message = check_stopped_run(out, "failed");
  CHECK(message.find("IDA_CONV_FAIL") != std::string::npos);
  CHECK(message.find("repeated Newton convergence failures") != std::string::npos);
  CHECK(message.find("iteration matrix is singular") != std::string::npos);  // the likely cause
  // IDA's own printer is silenced; its text is part of rigidae's message.
  CHECK(r.output.find("[IDA ERROR]") == std::string::npos);
  CHECK(message.find("(IDA: IDASolve: At t = ") != std::string::npos);
  CHECK(r.output.find("rigidae: error: " + message) != std::string::npos);
  fs::remove_all(out);
}

TEST_CASE("solver failure: repeated error-test failures (IDA_ERR_FAIL) are reported, kept and exit 1") {
  // atol at its floor: the error weights 1/atol of unknowns that start at 0
  // make round-off fail the error test at every step size.
  const fs::path out = rigidae::test::fresh_temp_dir("err_fail");
  const auto r = run_cli("solve " + kHeavyTop + " --atol 1e-100 --out " + out.string());
  CAPTURE(r.output);
  CHECK(r.exit_code == 1);
  const std::string message = check_stopped_run(out, "failed");
  CHECK(message.find("IDA_ERR_FAIL") != std::string::npos);
  CHECK(message.find("repeated error-test failures") != std::string::npos);
  CHECK(message.find("tolerances too tight") != std::string::npos);
  CHECK(r.output.find("[IDA ERROR]") == std::string::npos);
  CHECK(message.find("(IDA: IDASolve: At t = ") != std::string::npos);
  CHECK(message.find("error test failed repeatedly") != std::string::npos);  // IDA's own words
  CHECK(read_summary(out)["counters"]["error_test_fails"].get<long>() >= 10);
  fs::remove_all(out);
}

TEST_CASE("solver failure: too much work (max_steps) is reported with the rest it would take, kept and exits 1") {
  const fs::path out = rigidae::test::fresh_temp_dir("too_much_work");
  const auto r = run_cli("solve " + kHeavyTop + " --max-steps 50 --out " + out.string());
  CAPTURE(r.output);
  CHECK(r.exit_code == 1);
  const std::string message = check_stopped_run(out, "failed");
  CHECK(message.find("too much work (IDA_TOO_MUCH_WORK)") != std::string::npos);
  CHECK(message.find("raise --max-steps") != std::string::npos);
  CHECK(read_summary(out)["counters"]["steps"] == 50);
  fs::remove_all(out);
}

TEST_CASE("solver failure: an Euler-angle chart singularity with switching off stops at the margin and exits 1") {
  const fs::path out = rigidae::test::fresh_temp_dir("gimbal_lock");
  const auto r = run_cli("solve " + kGimbalLock + " --out " + out.string());
  CAPTURE(r.output);
  CHECK(r.exit_code == 1);
  const std::string message = check_stopped_run(out, "failed", 1);
  CHECK(message.find("chart singularity") != std::string::npos);
  CHECK(message.find("the integrator's root finding found the Euler-angle chart") != std::string::npos);
  CHECK(message.find("gimbal lock") != std::string::npos);
  CHECK(message.find("enable it") != std::string::npos);
  // Pitch about y at ~10 rad/s reaches |cos b| = 0.1 at b = acos(0.1) = 1.4706 rad.
  const double t = read_summary(out)["t_reached"];
  CHECK(t == doctest::Approx(std::acos(0.1) / 10.0).epsilon(0.01));
  fs::remove_all(out);
}

// Starts a long run, waits until it is integrating, sends `sig`, and checks
// the run stops between steps with everything kept.
void check_interrupt(int sig, const std::string& name) {
  const fs::path out = rigidae::test::fresh_temp_dir(name);
  const pid_t pid = fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    const std::string log = (out / "log.txt").string();
    std::freopen(log.c_str(), "w", stdout);
    std::freopen(log.c_str(), "a", stderr);
    execl(RIGIDAE_CLI, RIGIDAE_CLI, "solve", kHeavyTop.c_str(), "--t-end", "1000000", "--out", out.c_str(),
          static_cast<char*>(nullptr));
    std::_Exit(127);
  }
  // The recorder creates steps.csv just before the step loop starts.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (!fs::exists(out / "steps.csv") && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  REQUIRE(kill(pid, sig) == 0);
  int status = 0;
  REQUIRE(waitpid(pid, &status, 0) == pid);
  CAPTURE(rigidae::test::read_file(out / "log.txt"));
  REQUIRE(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 1);
  const std::string message = check_stopped_run(out, "interrupted");
  CHECK(message.find("interrupted by " + std::string(sig == SIGINT ? "SIGINT (Ctrl-C)" : "SIGTERM")) !=
        std::string::npos);
  CHECK(read_summary(out)["t_reached"].get<double>() < 1000000.0);
  fs::remove_all(out);
}

TEST_CASE("solver failure: Ctrl-C (SIGINT) stops the run between steps, keeps it and exits 1") {
  check_interrupt(SIGINT, "sigint");
}

TEST_CASE("solver failure: SIGTERM stops the run between steps, keeps it and exits 1") {
  check_interrupt(SIGTERM, "sigterm");
}

TEST_SUITE_END();
