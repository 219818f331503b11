#pragma once
// What a benchmark number was measured on: CPU, cores, compiler, build type,
// library versions and the git commit of the sources. Printed as the first
// JSON line of every benchmark run, so that a results file says where it
// came from.
#include <sundials/sundials_config.h>

#include "peers/peer_common.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include <Eigen/Core>

namespace bench {

// Output of a shell command, trailing newlines removed ("" if it failed).
inline std::string command_output(const std::string& cmd) {
  std::unique_ptr<FILE, int (*)(FILE*)> p(popen((cmd + " 2>/dev/null").c_str(), "r"), pclose);
  if (!p) return {};
  std::string out;
  std::array<char, 512> buf{};
  while (std::fgets(buf.data(), buf.size(), p.get())) out += buf.data();
  while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
  return out;
}

// The value of "Key:" in lscpu's output.
inline std::string lscpu_field(const std::string& key) {
  std::string v = command_output("LC_ALL=C lscpu | sed -n 's/^" + key + ":[[:space:]]*//p' | head -1");
  return v;
}

inline nlohmann::json machine_info(const std::string& program) {
  const std::string src = RIGIDAE_BENCH_SOURCE_DIR;
  const std::string commit = command_output("git -C '" + src + "' rev-parse HEAD");
  const bool dirty = !command_output("git -C '" + src + "' status --porcelain --untracked-files=no").empty();
  char date[32];
  const std::time_t now = std::time(nullptr);
  std::strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  return {
      {"kind", "machine"},
      {"program", program},
      {"date_utc", date},
      {"cpu_model", lscpu_field("Model name")},
      {"cpus", lscpu_field("CPU(s)")},
      {"cores_per_socket", lscpu_field("Core(s) per socket")},
      {"load_average", command_output("cut -d' ' -f1-3 /proc/loadavg")},
      {"compiler", RIGIDAE_BENCH_COMPILER},
      {"build_type", RIGIDAE_BENCH_BUILD_TYPE},
      {"cxx_flags", RIGIDAE_BENCH_CXX_FLAGS},
      {"sundials", SUNDIALS_VERSION},
      {"eigen", std::to_string(EIGEN_WORLD_VERSION) + "." + std::to_string(EIGEN_MAJOR_VERSION) + "." +
                    std::to_string(EIGEN_MINOR_VERSION)},
      {"git_commit", commit.empty() ? "unknown" : commit},
      {"git_dirty", dirty},
  };
}

// Median of a non-empty sample.
template <class V>
double median(V v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// The error measure of bench/peers, so that every program is measured alike.
inline double angle_between(const Eigen::Vector4d& q_ref, const Eigen::Vector4d& q) {
  return peers::angle_between({q_ref[0], q_ref[1], q_ref[2], q_ref[3]}, {q[0], q[1], q[2], q[3]});
}

}  // namespace bench
