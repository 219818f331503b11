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

std::filesystem::path find_script(const std::string& name) {
  std::vector<std::filesystem::path> dirs;
  if (const char* env = std::getenv("RIGIDAE_TOOLS_DIR")) dirs.emplace_back(env);
#ifdef RIGIDAE_TOOLS_DIR
  dirs.emplace_back(RIGIDAE_TOOLS_DIR);
#endif
  std::error_code ec;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) dirs.push_back(exe.parent_path().parent_path() / "tools");
  for (const auto& d : dirs)
    if (std::filesystem::exists(d / name)) return d / name;
  return {};
}

}  // namespace

bool run_plot_script(const std::string& script, const std::vector<std::string>& args) {
  std::fflush(stdout);  // our lines before the script's
  const std::filesystem::path path = find_script(script);
  const char* python = "/usr/bin/python3";
  if (path.empty() || !std::filesystem::exists(python)) {
    fmt::print(stderr, "rigidae: warning: figures skipped: {} not found\n",
               path.empty() ? fmt::format("tools/{} (set RIGIDAE_TOOLS_DIR)", script) : std::string(python));
    return false;
  }
  std::vector<std::string> cmd{python, path.string()};
  cmd.insert(cmd.end(), args.begin(), args.end());
  const int rc = run_program(cmd);
  if (rc != 0)
    fmt::print(stderr, "rigidae: warning: {} exited with {} (it needs Debian's python3-matplotlib); the tables and "
                       "CSV files are written\n", path.string(), rc);
  return rc == 0;
}

}  // namespace rigidae::cli
