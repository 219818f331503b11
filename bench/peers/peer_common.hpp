// Shared helpers of the C++ peer programs: the scenes (heavy top, free body),
// the reference quaternion, the orientation error, timing and JSON output.
#pragma once

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace peers {

// ---- the scenes (SI units) ------------------------------------------------
// heavy_top: problems/heavy_top.toml. free_body: problems/free_body.toml, a
// torque-free asymmetric body; here a body turning about a ball joint at its
// centre of mass with gravity off, which has the same rotation (rigidae
// integrates only the rotation of a free body, about its centre of mass).
struct Scene {
  std::string name;
  double mass;
  double Icom[3];     // principal moments about the COM, body axes
  double com[3];      // body frame, from the pivot; on a body axis (or zero)
  double gravity[3];  // space frame
  double w0[3];       // body components; the initial orientation is the identity
  double t_end;
  double Jpivot[3];   // inertia about the pivot (parallel axis theorem)
  // Initial orientation (w, x, y, z). Only odeint_heavy_top reads it: the
  // other peers start from the identity (run them on heavy_top, free_body).
  double q0[4] = {1.0, 0.0, 0.0, 0.0};
};

inline Scene make_scene(const std::string& name) {
  Scene s;
  if (name == "heavy_top")
    s = {name, 15.0, {0.234375, 0.46875, 0.234375}, {0.0, 1.0, 0.0}, {0.0, 0.0, -9.81}, {0.0, 150.0, -4.61538}, 2.0, {}};
  else if (name == "free_body")
    s = {name, 1.0, {2.0, 3.0, 4.0}, {0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}, {0.1, 2.0, 0.1}, 20.0, {}};
  else if (name == "lagrange_top") {
    // problems/lagrange_top.toml: tilted 0.3 rad about space x.
    s = {name, 0.5, {2.0e-4, 2.0e-4, 3.0e-4}, {0.0, 0.0, 0.05}, {0.0, 0.0, -9.81}, {0.0, 0.0, 60.0}, 5.0, {}};
    s.q0[0] = std::cos(0.15);
    s.q0[1] = std::sin(0.15);
  } else
    throw std::runtime_error("unknown scene '" + name + "' (heavy_top, free_body, lagrange_top)");
  const double c2 = s.com[0] * s.com[0] + s.com[1] * s.com[1] + s.com[2] * s.com[2];
  int off_axis = 0;
  for (int k = 0; k < 3; ++k) {
    s.Jpivot[k] = s.Icom[k] + s.mass * (c2 - s.com[k] * s.com[k]);
    off_axis += s.com[k] != 0.0;
  }
  if (off_axis > 1) throw std::runtime_error("the COM must lie on a body axis (diagonal J about the pivot)");
  return s;
}

// The scene being run (set by parse_options from --scene; default heavy_top).
inline Scene scene = make_scene("heavy_top");

// Total energy of the initial state (kinetic about the pivot; the potential
// -m g . x_com is 0 because the COM starts level with the pivot).
inline double initial_energy() {
  const double* J = scene.Jpivot;
  const double* w = scene.w0;
  return 0.5 * (J[0] * w[0] * w[0] + J[1] * w[1] * w[1] + J[2] * w[2] * w[2]);
}

using Quat = std::array<double, 4>;  // (w, x, y, z)

inline Quat normalized(Quat q) {
  const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  for (double& c : q) c /= n;
  return q;
}

// Rotation angle of conj(q_ref) * q; independent of the sign and the norm of q.
inline double angle_between(const Quat& q_ref, const Quat& q) {
  const double a = q_ref[0], b = -q_ref[1], c = -q_ref[2], d = -q_ref[3];
  const double w = a * q[0] - b * q[1] - c * q[2] - d * q[3];
  const double x = a * q[1] + b * q[0] + c * q[3] - d * q[2];
  const double y = a * q[2] - b * q[3] + c * q[0] + d * q[1];
  const double z = a * q[3] + b * q[2] - c * q[1] + d * q[0];
  return 2.0 * std::atan2(std::sqrt(x * x + y * y + z * z), std::fabs(w));
}

// Reads "quaternion": [w, x, y, z] from the reference JSON (a minimal scan, no
// JSON library). Returns nothing if the file is missing.
inline std::optional<Quat> load_reference(const std::string& path) {
  std::ifstream in(path);
  if (!in) return std::nullopt;
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = ss.str();
  const auto key = text.find("\"quaternion\"");
  if (key == std::string::npos) throw std::runtime_error("no \"quaternion\" in " + path);
  auto pos = text.find('[', key);
  Quat q{};
  for (int i = 0; i < 4; ++i) {
    ++pos;
    char* end = nullptr;
    q[i] = std::strtod(text.c_str() + pos, &end);
    pos = static_cast<std::size_t>(end - text.c_str());
    if (text[pos] != ',' && text[pos] != ']') pos = text.find_first_of(",]", pos);
  }
  return q;
}

// ---- command line -----------------------------------------------------------
struct Options {
  int repeats = 5;           // N: wall time is the median of N runs
  double budget_s = 5.0;     // stop repeating a setting once its runs took this long
  std::string reference;  // default: SCENE_reference.json in the current directory
  std::vector<double> settings;  // tolerances or steps; empty: the program's default sweep
  std::vector<std::string> methods;  // empty: all
};

inline std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ',')) if (!item.empty()) out.push_back(item);
  return out;
}

inline Options parse_options(int argc, char** argv, const char* usage) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) throw std::runtime_error("missing value after " + a);
      return argv[++i];
    };
    if (a == "--repeats") o.repeats = std::max(1, std::stoi(next()));
    else if (a == "--budget") o.budget_s = std::stod(next());
    else if (a == "--reference") o.reference = next();
    else if (a == "--scene") scene = make_scene(next());
    else if (a == "--settings") for (auto& s : split(next())) o.settings.push_back(std::stod(s));
    else if (a == "--methods") o.methods = split(next());
    else if (a == "-h" || a == "--help") { std::printf("%s\n", usage); std::exit(0); }
    else throw std::runtime_error("unknown option " + a + "\n" + usage);
  }
  if (o.reference.empty()) o.reference = scene.name + "_reference.json";
  return o;
}

inline bool wanted(const Options& o, const std::string& method) {
  return o.methods.empty() || std::find(o.methods.begin(), o.methods.end(), method) != o.methods.end();
}

// ---- timing -----------------------------------------------------------------
// Runs f() up to `repeats` times (at least once; no more once the runs have
// taken `budget_s`) and returns the median wall time and the number of runs.
template <class F>
std::pair<double, int> median_wall(F&& f, int repeats, double budget_s) {
  std::vector<double> times;
  double total = 0.0;
  for (int r = 0; r < repeats; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    times.push_back(dt);
    total += dt;
    if (total >= budget_s) break;
  }
  std::sort(times.begin(), times.end());
  const std::size_t n = times.size();
  const double med = n % 2 ? times[n / 2] : 0.5 * (times[n / 2 - 1] + times[n / 2]);
  return {med, static_cast<int>(n)};
}

// ---- output -----------------------------------------------------------------
inline std::string num(double v) {
  if (!std::isfinite(v)) return "null";
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}
inline std::string num_or_null(std::optional<double> v) { return v ? num(*v) : "null"; }

struct Row {
  std::string peer, method, setting_kind;  // setting_kind: "tol", "accuracy" or "dt"
  double setting = 0.0;
  double wall_s = 0.0;
  int repeats = 0;
  long long steps = 0;
  std::optional<long long> rhs_evals;
  std::optional<double> error_rad;
  Quat q_final{};
  std::string extra;  // further `"key": value` pairs, comma-separated, or empty
};

inline void print_row(const Row& r) {
  std::string s = "{\"peer\": \"" + r.peer + "\", \"scene\": \"" + scene.name + "\", \"method\": \"" + r.method + "\", \"setting\": " +
                  num(r.setting) + ", \"setting_kind\": \"" + r.setting_kind + "\", \"wall_s\": " +
                  num(r.wall_s) + ", \"repeats\": " + std::to_string(r.repeats) +
                  ", \"steps\": " + std::to_string(r.steps) + ", \"rhs_evals\": " +
                  (r.rhs_evals ? std::to_string(*r.rhs_evals) : "null") +
                  ", \"error_rad\": " + num_or_null(r.error_rad) + ", \"q_final\": [" +
                  num(r.q_final[0]) + ", " + num(r.q_final[1]) + ", " + num(r.q_final[2]) + ", " +
                  num(r.q_final[3]) + "]";
  if (!r.extra.empty()) s += ", " + r.extra;
  s += "}";
  std::puts(s.c_str());
  std::fflush(stdout);
}

}  // namespace peers
