// No silent data loss: a write the system refuses ends the run as failed,
// names the file and the reason, keeps what was written, and never leaves a
// truncated small file or a study run counted complete.
//
// The refusal is a file-size limit (RLIMIT_FSIZE, `ulimit -f`): past it the
// kernel fails write() with EFBIG ("File too large"), exactly like a full
// disk fails it with ENOSPC, and needs no privileges or mounts.
#include <doctest/doctest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_runner.hpp"
#include "rigidae/io/checked_file.hpp"

TEST_SUITE_BEGIN("system");

namespace fs = std::filesystem;
using rigidae::test::fresh_temp_dir;
using rigidae::test::read_file;

namespace {

// rigidae with a file-size limit of `kib` KiB (bash counts ulimit -f in KiB).
// SIGXFSZ is left at its default: rigidae itself must ignore it and report.
rigidae::test::CliResult run_cli_limited(int kib, const std::string& args) {
  const std::string cmd =
      "bash -c 'ulimit -f " + std::to_string(kib) + "; exec " + std::string(RIGIDAE_CLI) + " " + args + "' 2>&1";
  rigidae::test::CliResult r{-1, {}};
  FILE* p = popen(cmd.c_str(), "r");
  REQUIRE(p != nullptr);
  char buf[4096];
  std::size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) r.output.append(buf, n);
  const int status = pclose(p);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

// Runs f in a child process under a file-size limit of `bytes` (SIGXFSZ
// ignored); returns the child's exit code (f returns it).
template <class F>
int in_limited_child(rlim_t bytes, F f) {
  std::fflush(nullptr);
  const pid_t pid = fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    std::signal(SIGXFSZ, SIG_IGN);
    rlimit lim{bytes, bytes};
    setrlimit(RLIMIT_FSIZE, &lim);
    _exit(f());
  }
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

const std::string kHeavyTop = std::string(RIGIDAE_SOURCE_DIR) + "/problems/heavy_top.toml";

}  // namespace

TEST_CASE("output: an atomic small file is whole or absent, and the old one stays") {
  const fs::path dir = fresh_temp_dir("atomic");
  const fs::path file = dir / "summary.json";
  std::ofstream(file) << "old";
  const std::string big(10000, 'x');
  // 0: threw OutputError naming the file and the reason; 1: no throw; 2: wrong message.
  const int code = in_limited_child(4096, [&] {
    try {
      rigidae::write_file_atomically(file, big);
    } catch (const rigidae::OutputError& e) {
      const std::string m = e.what();
      return m.find(file.string()) != std::string::npos && m.find("File too large") != std::string::npos ? 0 : 2;
    }
    return 1;
  });
  CHECK(code == 0);
  CHECK(read_file(file) == "old");
  int others = 0;
  for (const auto& e : fs::directory_iterator(dir)) others += e.path() != file;
  CHECK(others == 0);  // the temporary is gone
  // Without a limit, the same call replaces the file whole.
  rigidae::write_file_atomically(file, big);
  CHECK(read_file(file) == big);
}

TEST_CASE("output: a checked stream reports the refused write and keeps the bytes before it") {
  const fs::path dir = fresh_temp_dir("stream");
  const fs::path file = dir / "steps.csv";
  const int code = in_limited_child(4096, [&] {
    try {
      rigidae::CheckedStream s(file, 1024);
      const std::string row(100, 'r');
      for (int k = 0; k < 100; ++k) s.write(row);
      s.close();
    } catch (const rigidae::OutputError& e) {
      return std::string(e.what()).find("File too large") != std::string::npos ? 0 : 2;
    }
    return 1;
  });
  CHECK(code == 0);
  CHECK(fs::file_size(file) == 4096);  // up to the limit, nothing lost before it
}

TEST_CASE("output: solve past a file-size limit fails with exit 1, names the file, keeps what was written") {
  const fs::path out = fresh_temp_dir("solve_limit");
  const auto r = run_cli_limited(64, "solve " + kHeavyTop + " --out " + out.string());
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("steps.csv") != std::string::npos);
  CHECK(r.output.find("File too large") != std::string::npos);
  CHECK(r.output.find("success") == std::string::npos);
  CHECK(fs::file_size(out / "steps.csv") == 64 * 1024);
  // The summary (small, under the limit) says so too.
  const auto j = nlohmann::json::parse(read_file(out / "summary.json"));
  CHECK(j["status"] == "failed");
  CHECK(j["message"].get<std::string>().find("steps.csv") != std::string::npos);
  // The same run without the limit succeeds: the failure was the limit's.
  CHECK(rigidae::test::run_cli("solve " + kHeavyTop + " --t-end 0.1 --quiet --out " + out.string()).exit_code == 0);
}

TEST_CASE("output: compare past a file-size limit fails with exit 1 naming the file") {
  const fs::path out = fresh_temp_dir("compare_limit");
  const auto r = run_cli_limited(8, "compare " + kHeavyTop + " --t-end 0.5 --repeat 1 --only quaternion/euler/ggl --quiet --out " +
                                        out.string());
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("File too large") != std::string::npos);
  CHECK(r.output.find(".csv") != std::string::npos);
  CHECK(!fs::exists(out / "compare.csv"));  // no table claims a complete comparison
}

TEST_CASE("output: a study run that cannot write is never counted complete") {
  const fs::path dir = fresh_temp_dir("study_limit");
  std::ofstream(dir / "s.toml") << "schema_version = 1\nname = \"s\"\nscenes = [\"" << kHeavyTop
                                << "\"]\n[grid]\ncombinations = [\"quaternion/euler/ggl\"]\nrtol = [1e-6]\n"
                                   "[timing]\nwarmups = 0\nrepeats = 1\n";
  const std::string study = (dir / "s.toml").string() + " --out " + (dir / "out").string() + " --no-plot --quiet";
  const auto r = run_cli_limited(16, "study " + study);
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("File too large") != std::string::npos);
  const auto collect = rigidae::test::run_cli("study collect " + study);
  CHECK(collect.exit_code == 1);
  CHECK(collect.output.find("1 run of the study have no complete folder yet") != std::string::npos);
}

// A small file's name can be a device or a link to one (-o /dev/stdout, a
// link to /dev/full standing for a full disk). Renaming the completed
// temporary over it replaced the device by a regular file: as root,
// `rigidae export --mjcf X -o /dev/full` put the model in /dev/full and
// reported success. Links here, so that a regression replaces only the link.
TEST_CASE("output: a small file named by a device is written into the device, never renamed over it") {
  const fs::path dir = fresh_temp_dir("device");
  const fs::path full = dir / "model_on_a_full_disk.xml", null = dir / "discarded.xml";
  fs::create_symlink("/dev/full", full);
  fs::create_symlink("/dev/null", null);
  std::string message = "no error";
  try {
    rigidae::write_file_atomically(full, "<mujoco/>");
  } catch (const rigidae::OutputError& e) {
    message = e.what();
  }
  CAPTURE(message);
  CHECK(message.rfind(full.string() + ": write failed", 0) == 0);
  CHECK(message.find("No space left on device") != std::string::npos);
  CHECK_NOTHROW(rigidae::write_file_atomically(null, "<mujoco/>"));
  for (const fs::path& link : {full, null}) {
    CHECK(fs::is_symlink(link));
    CHECK(fs::is_character_file(link));
  }
  int others = 0;
  for (const auto& e : fs::directory_iterator(dir)) others += e.path() != full && e.path() != null;
  CHECK(others == 0);  // no temporary left
  // Through the CLI: export into the full device fails (exit 1) naming the file.
  const auto r = rigidae::test::run_cli("export --mjcf " + (fs::path(RIGIDAE_SOURCE_DIR) / "problems" / "arm6.urdf").string() +
                                        " -o " + full.string());
  CAPTURE(r.output);
  CHECK(r.exit_code == 1);
  CHECK(r.output.find(full.string() + ": write failed") != std::string::npos);
  CHECK(r.output.find("rigidae export: wrote") == std::string::npos);
  CHECK(fs::is_character_file(full));
}

TEST_SUITE_END();
