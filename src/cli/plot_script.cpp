#include "plot_script.hpp"

#include <fmt/format.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>

namespace rigidae::cli {

namespace {

// Runs program with args, waits; returns its exit status (127 if it could not start).
int run_program(const std::vector<std::string>& argv) {
  const pid_t pid = fork();
  if (pid < 0) return 127;
  if (pid == 0) {
    std::vector<char*> cargv;
    for (const auto& a : argv) cargv.push_back(const_cast<char*>(a.c_str()));
    cargv.push_back(nullptr);
    execv(cargv[0], cargv.data());
    _exit(127);
  }
  int status = 0;
  if (waitpid(pid, &status, 0) < 0) return 127;
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128;
}

// The folders searched for the plot scripts, in order: $RIGIDAE_TOOLS_DIR
// when set, then share/rigidae/tools relative to this executable's folder:
// ../share/rigidae/tools when installed (PREFIX/bin/rigidae), and
// share/rigidae/tools beside it in the build tree (CMake links it to the
// source tree's tools/). No path of the build machine is compiled in: an
// installed prefix can be moved.
std::vector<std::filesystem::path> script_dirs() {
  std::vector<std::filesystem::path> dirs;
  if (const char* env = std::getenv("RIGIDAE_TOOLS_DIR"); env && *env) dirs.emplace_back(env);
  std::error_code ec;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const auto bin = exe.parent_path();
    dirs.push_back((bin.parent_path() / "share" / "rigidae" / "tools").lexically_normal());
    dirs.push_back(bin / "share" / "rigidae" / "tools");
  }
  return dirs;
}

// The script's path in the first of script_dirs() that holds it; empty when
// none does (`searched` then lists the folders).
std::filesystem::path find_script(const std::string& script, std::string& searched) {
  for (const auto& d : script_dirs()) {
    if (std::filesystem::exists(d / script)) return d / script;
    searched += fmt::format("{}{}", searched.empty() ? "" : ", ", d.string());
  }
  if (searched.empty()) searched = "no folder";
  return {};
}

}  // namespace

std::filesystem::path find_shared_file(const std::string& relative) {
  std::error_code ec;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) return {};
  const auto bin = exe.parent_path();
  for (const auto& d : {(bin.parent_path() / "share" / "rigidae").lexically_normal(), bin / "share" / "rigidae"})
    if (std::filesystem::exists(d / relative)) return d / relative;
  return {};
}

int run_tool_script(const std::string& script, const std::vector<std::string>& args) {
  std::fflush(stdout);
  const char* python = "/usr/bin/python3";
  std::string searched;
  const std::filesystem::path path = find_script(script, searched);
  if (path.empty()) {
    fmt::print(stderr, "rigidae: error: {} not found in {} (set RIGIDAE_TOOLS_DIR to the folder holding rigidae's "
                       "tools)\n", script, searched);
    return 1;
  }
  if (!std::filesystem::exists(python)) {
    fmt::print(stderr, "rigidae: error: {} not found (Debian's python3)\n", python);
    return 1;
  }
  if (std::getenv("RIGIDAE_SHOW_PLOT_SCRIPT")) fmt::print(stderr, "rigidae: tool script {}\n", path.string());
  std::vector<std::string> cmd{python, path.string()};
  cmd.insert(cmd.end(), args.begin(), args.end());
  const int rc = run_program(cmd);
  if (rc != 0) fmt::print(stderr, "rigidae: error: {} exited with {}\n", path.string(), rc);
  return rc;
}

bool run_plot_script(const std::string& script, const std::vector<std::string>& args) {
  std::fflush(stdout);  // our lines before the script's
  const char* python = "/usr/bin/python3";
  std::string searched;
  const std::filesystem::path path = find_script(script, searched);
  if (path.empty()) {
    fmt::print(stderr, "rigidae: warning: figures skipped: {} not found in {} (set RIGIDAE_TOOLS_DIR to the folder "
                       "holding rigidae's plot scripts)\n", script, searched);
    return false;
  }
  if (!std::filesystem::exists(python)) {
    fmt::print(stderr, "rigidae: warning: figures skipped: {} not found (Debian's python3 and python3-matplotlib)\n",
               python);
    return false;
  }
  if (std::getenv("RIGIDAE_SHOW_PLOT_SCRIPT")) fmt::print(stderr, "rigidae: plot script {}\n", path.string());
  std::vector<std::string> cmd{python, path.string()};
  cmd.insert(cmd.end(), args.begin(), args.end());
  const int rc = run_program(cmd);
  if (rc != 0)
    fmt::print(stderr, "rigidae: warning: {} exited with {} (it needs Debian's python3-matplotlib); the tables and "
                       "CSV files are written\n", path.string(), rc);
  return rc == 0;
}

}  // namespace rigidae::cli
