// See machine_record.hpp.
#include "machine_record.hpp"

#include "rigidae_build_info.hpp"  // generated: cmake/build_info.cmake

#include <unistd.h>

#include <ctime>
#include <fstream>
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

std::string utc_now() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

// A word as a POSIX shell reads it back: bare when it holds only safe characters.
std::string shell_quoted(const std::string& w) {
  if (!w.empty() && w.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789"
                                        "@%+=:,./-_") == std::string::npos)
    return w;
  std::string q(1, '\'');
  for (char c : w) {
    if (c == '\'')
      q += "'\\''";
    else
      q += c;
  }
  q += '\'';
  return q;
}

std::string command_line() {
  std::ifstream in("/proc/self/cmdline", std::ios::binary);
  std::string word, line;
  while (std::getline(in, word, '\0')) {
    if (!line.empty()) line += ' ';
    line += shell_quoted(word);
  }
  return line;
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
    const std::string commit = std::string(RIGIDAE_BUILD_COMMIT) + (RIGIDAE_BUILD_DIRTY ? "-dirty" : "");
    return nlohmann::json{{"host", host}, {"cpu_model", cpu_model()}, {"commit", commit}, {"compiler", compiler()}};
  }();
  nlohmann::json j = fixed;
  const std::string load = first_line("/proc/loadavg");
  j["load_average"] = load.substr(0, load.find(' ', load.find(' ', load.find(' ') + 1) + 1));
  return j;
}

nlohmann::json build_record() {
  return nlohmann::json{{"commit", RIGIDAE_BUILD_COMMIT}, {"dirty", RIGIDAE_BUILD_DIRTY}, {"date", RIGIDAE_BUILD_DATE}};
}

nlohmann::json run_record() { return nlohmann::json{{"command_line", command_line()}, {"date", utc_now()}}; }

void add_provenance(nlohmann::json& summary) {
  summary["build"] = build_record();
  summary["run"] = run_record();
}

}  // namespace rigidae
