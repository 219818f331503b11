// See machine_record.hpp.
#include "machine_record.hpp"

#include <unistd.h>

#include <array>
#include <cstdio>
#include <fstream>
#include <memory>
#include <string>

namespace rigidae {

namespace {

std::string first_line(const char* path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  return line;
}

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("model name", 0) == 0) {
      const std::size_t colon = line.find(':');
      return colon == std::string::npos ? "" : line.substr(line.find_first_not_of(" \t", colon + 1));
    }
  return "unknown";
}

// The commit of the sources this binary was built from, as git sees them
// now ("-dirty" when tracked files differ); "unknown" outside a checkout.
std::string source_commit() {
#ifdef RIGIDAE_SOURCE_DIR_FOR_COMMIT
  const std::string dir = RIGIDAE_SOURCE_DIR_FOR_COMMIT;
  auto run = [](const std::string& cmd) {
    std::unique_ptr<FILE, int (*)(FILE*)> p(popen((cmd + " 2>/dev/null").c_str(), "r"), pclose);
    std::string out;
    if (!p) return out;
    std::array<char, 256> buf{};
    while (std::fgets(buf.data(), buf.size(), p.get())) out += buf.data();
    while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
    return out;
  };
  const std::string commit = run("git -C '" + dir + "' rev-parse HEAD");
  if (commit.empty()) return "unknown";
  const bool dirty = !run("git -C '" + dir + "' status --porcelain --untracked-files=no").empty();
  return dirty ? commit + "-dirty" : commit;
#else
  return "unknown";
#endif
}

std::string compiler() {
#if defined(__clang__)
  return std::string("Clang ") + __clang_version__;
#elif defined(__GNUC__)
  return std::string("GNU ") + __VERSION__;
#else
  return "unknown";
#endif
}

}  // namespace

nlohmann::json machine_record() {
  static const nlohmann::json fixed = [] {
    char host[256] = "unknown";
    gethostname(host, sizeof host - 1);
    return nlohmann::json{{"host", host}, {"cpu_model", cpu_model()}, {"commit", source_commit()},
                          {"compiler", compiler()}};
  }();
  nlohmann::json j = fixed;
  const std::string load = first_line("/proc/loadavg");
  j["load_average"] = load.substr(0, load.find(' ', load.find(' ', load.find(' ') + 1) + 1));
  return j;
}

}  // namespace rigidae
