#pragma once
// Runs the real rigidae binary, as a user would, for the command-line tests.
#include <doctest/doctest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace rigidae::test {

struct CliResult {
  int exit_code;       // -1 if the process did not exit normally (a crash)
  std::string output;  // stdout and stderr
};

// `args` go through the shell: quote anything unusual.
inline CliResult run_cli(const std::string& args) {
  const std::string cmd = std::string(RIGIDAE_CLI) + " " + args + " 2>&1";
  CliResult r{-1, {}};
  FILE* p = popen(cmd.c_str(), "r");
  REQUIRE(p != nullptr);
  char buf[4096];
  std::size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) r.output.append(buf, n);
  const int status = pclose(p);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

// A folder of its own under the system's temporary directory, emptied. The
// process id keeps test binaries of several build folders, run at the same
// time, apart.
inline std::filesystem::path fresh_temp_dir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / "rigidae_cli_tests" /
                   (std::to_string(::getpid()) + "-" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

inline std::string read_file(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace rigidae::test
