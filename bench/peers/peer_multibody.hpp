// Shared helpers of the multibody peer programs (simbody_chain.cpp,
// mujoco_chain.cpp): the two scenes as bodies on spherical joints, the
// reference final state, the error metric, options and JSON output.
//
// Scenes (SI units; every body starts with R = I, body axes = space axes):
//   chain N  -- tools/make_chain.py N (spherical joints, defaults --length 0.1
//               --mass 0.1 --spin 1 --end 1): link k (k = 1..N) has mass m,
//               principal inertia (m 2 s^2 / 12, m (L^2 + s^2) / 12, same),
//               s = L / 10, centre of mass ((k - 1/2) L, 0, 0), velocity
//               (0, w x, 0) and angular velocity (0, 0, w) (a rigid turn about
//               the vertical at w = 1 rad/s); joint k at ((k - 1) L, 0, 0)
//               holds link k to link k-1 (link 0 = ground). End 1 s.
//   double_pendulum -- problems/double_pendulum.toml, taken over its first
//               second (the motion is chaotic: over its 10 s, runs at tight
//               tolerances already differ by 6e-4 rad, README "Several bodies").
// Gravity (0, 0, -9.81) in both.
//
// Error metric (the one `rigidae compare` uses on multibody scenes): the worst
// body's rotation angle of R_ref^T R at the end, in rad, and the worst body's
// centre-of-mass distance to the reference, in m.
#pragma once

#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "peer_common.hpp"

namespace mb {

using Vec = std::array<double, 3>;

struct Body {
  std::string name;
  double mass;
  Vec inertia;  // principal moments about the centre of mass, body axes (= space axes at t = 0)
  Vec com;      // initial centre of mass, space frame
  Vec velocity;
  Vec omega;    // space frame
  int parent;   // index of the parent body, -1 = ground
  Vec joint;    // spherical joint to the parent, space point at t = 0
};

struct Scene {
  std::string name;  // rigidae's scene name: chain_N or double_pendulum
  std::vector<Body> bodies;
  Vec gravity{0.0, 0.0, -9.81};
  double t_end = 1.0;
};

// tools/make_chain.py's arithmetic, in its order, so the doubles are the same.
inline Scene make_chain(int n, double length = 0.1, double mass = 0.1, double spin = 1.0, double end = 1.0) {
  if (n < 1) throw std::runtime_error("--links must be at least 1");
  Scene s;
  s.name = "chain_" + std::to_string(n);
  s.t_end = end;
  const double side = length / 10.0;
  const double j_axis = mass * 2.0 * side * side / 12.0;
  const double j_cross = mass * (length * length + side * side) / 12.0;
  for (int k = 1; k <= n; ++k) {
    const double x = (k - 0.5) * length;
    s.bodies.push_back({"link" + std::to_string(k), mass, {j_axis, j_cross, j_cross}, {x, 0.0, 0.0},
                        {0.0, spin * x, 0.0}, {0.0, 0.0, spin}, k - 2, {(k - 1) * length, 0.0, 0.0}});
  }
  return s;
}

// problems/double_pendulum.toml (numbers copied as written there).
inline Scene make_double_pendulum(double end = 1.0) {
  Scene s;
  s.name = "double_pendulum";
  s.t_end = end;
  s.bodies.push_back({"upper", 1.0, {0.00016666666666666666, 0.02086666666666667, 0.020966666666666665},
                      {0.25, 0.0, 0.0}, {0.0, 0.5, 0.0}, {0.0, 0.0, 2.0}, -1, {0.0, 0.0, 0.0}});
  s.bodies.push_back({"lower", 0.8, {0.010726666666666669, 0.00012, 0.010726666666666669},
                      {0.5, 0.2, 0.0}, {-0.4, 1.0, 0.0}, {0.0, 10.0, 2.0}, 0, {0.5, 0.0, 0.0}});
  return s;
}

inline Vec sub(const Vec& a, const Vec& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline Vec cross(const Vec& a, const Vec& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double dot(const Vec& a, const Vec& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline double norm(const Vec& a) { return std::sqrt(dot(a, a)); }

// Joint point relative to the parent's centre of mass (ground: to the origin)
// and to the child's centre of mass, in the (identical) initial frames.
inline Vec joint_in_parent(const Scene& s, int b) {
  const Body& body = s.bodies[b];
  return body.parent < 0 ? body.joint : sub(body.joint, s.bodies[body.parent].com);
}
inline Vec joint_in_child(const Scene& s, int b) { return sub(s.bodies[b].joint, s.bodies[b].com); }
// Angular velocity of a body relative to its parent (space = parent axes at t = 0).
inline Vec relative_omega(const Scene& s, int b) {
  const Body& body = s.bodies[b];
  return body.parent < 0 ? body.omega : sub(body.omega, s.bodies[body.parent].omega);
}

// Checks that the scene's velocities satisfy every joint (the joint point moves
// alike on both bodies), which is what lets a joint-coordinate peer start from
// relative angular velocities alone.
inline void check_consistent(const Scene& s) {
  for (int b = 0; b < static_cast<int>(s.bodies.size()); ++b) {
    const Body& c = s.bodies[b];
    Vec v_child = c.velocity;
    const Vec rc = sub(c.joint, c.com);
    const Vec wc = cross(c.omega, rc);
    for (int k = 0; k < 3; ++k) v_child[k] += wc[k];
    Vec v_parent{0.0, 0.0, 0.0};
    if (c.parent >= 0) {
      const Body& p = s.bodies[c.parent];
      const Vec wp = cross(p.omega, sub(c.joint, p.com));
      for (int k = 0; k < 3; ++k) v_parent[k] = p.velocity[k] + wp[k];
    }
    if (norm(sub(v_child, v_parent)) > 1e-12)
      throw std::runtime_error("scene: joint of " + c.name + " violated by the initial velocities");
  }
}

// Total energy of the initial state: kinetic plus -m g . x (rigidae's zero of
// potential energy is the space origin).
inline double initial_energy(const Scene& s) {
  double e = 0.0;
  for (const Body& b : s.bodies) {
    e += 0.5 * b.mass * dot(b.velocity, b.velocity);
    for (int k = 0; k < 3; ++k) e += 0.5 * b.inertia[k] * b.omega[k] * b.omega[k];
    e -= b.mass * dot(s.gravity, b.com);
  }
  return e;
}

// ---- reference (written by make_multibody_reference.py) ---------------------
struct Reference {
  std::vector<peers::Quat> q;  // per body (w, x, y, z)
  std::vector<Vec> com;
  double initial_energy = 0.0;  // rigidae's summary.json final.initial_energy
};

// Every number inside the bracketed value of "key" (nested arrays flattened).
inline std::vector<double> numbers_of(const std::string& text, const std::string& key, const std::string& path) {
  const auto k = text.find("\"" + key + "\"");
  if (k == std::string::npos) throw std::runtime_error("no \"" + key + "\" in " + path);
  std::size_t pos = text.find_first_of("[-0123456789", text.find(':', k));
  std::vector<double> out;
  if (text[pos] != '[') return {std::strtod(text.c_str() + pos, nullptr)};
  int depth = 0;
  while (pos < text.size()) {
    const char c = text[pos];
    if (c == '[') ++depth;
    else if (c == ']') { if (--depth == 0) break; }
    else if (c == '-' || c == '+' || c == '.' || (c >= '0' && c <= '9')) {
      char* end = nullptr;
      out.push_back(std::strtod(text.c_str() + pos, &end));
      pos = static_cast<std::size_t>(end - text.c_str());
      continue;
    }
    ++pos;
  }
  return out;
}

inline std::optional<Reference> load_reference(const std::string& path, std::size_t n_bodies) {
  std::ifstream in(path);
  if (!in) return std::nullopt;
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = ss.str();
  const auto q = numbers_of(text, "quaternions", path);
  const auto x = numbers_of(text, "coms", path);
  if (q.size() != 4 * n_bodies || x.size() != 3 * n_bodies)
    throw std::runtime_error(path + ": expected " + std::to_string(n_bodies) + " bodies");
  Reference r;
  for (std::size_t b = 0; b < n_bodies; ++b) {
    r.q.push_back({q[4 * b], q[4 * b + 1], q[4 * b + 2], q[4 * b + 3]});
    r.com.push_back({x[3 * b], x[3 * b + 1], x[3 * b + 2]});
  }
  r.initial_energy = numbers_of(text, "initial_energy", path).at(0);
  return r;
}

struct Errors {
  double rad = 0.0;  // worst body's rotation angle to the reference
  double com_m = 0.0;  // worst body's centre-of-mass distance
  int worst_body = 0;
};

inline Errors errors(const Reference& ref, const std::vector<peers::Quat>& q, const std::vector<Vec>& com) {
  Errors e;
  for (std::size_t b = 0; b < q.size(); ++b) {
    const double a = peers::angle_between(ref.q[b], q[b]);
    if (!(a <= e.rad)) { e.rad = a; e.worst_body = static_cast<int>(b); }  // NaN counts as worst
    e.com_m = std::max(e.com_m, norm(sub(com[b], ref.com[b])));
  }
  return e;
}

// ---- command line -----------------------------------------------------------
struct Options {
  Scene scene;
  int repeats = 5;
  double budget_s = 5.0;
  std::string reference;  // default: SCENE_reference.json in the current directory
  std::vector<double> settings;
  std::vector<std::string> methods;
  bool check_only = false;  // print the initial-state checks and stop
};

inline Options parse_options(int argc, char** argv, const char* usage) {
  Options o;
  std::string scene = "chain";
  int links = 10;
  double t_end = 1.0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) throw std::runtime_error("missing value after " + a);
      return argv[++i];
    };
    if (a == "--repeats") o.repeats = std::max(1, std::stoi(next()));
    else if (a == "--budget") o.budget_s = std::stod(next());
    else if (a == "--reference") o.reference = next();
    else if (a == "--scene") scene = next();
    else if (a == "--links") links = std::stoi(next());
    else if (a == "--t-end") t_end = std::stod(next());
    else if (a == "--settings") for (auto& s : peers::split(next())) o.settings.push_back(std::stod(s));
    else if (a == "--methods") o.methods = peers::split(next());
    else if (a == "--check") o.check_only = true;
    else if (a == "-h" || a == "--help") { std::printf("%s\n", usage); std::exit(0); }
    else throw std::runtime_error("unknown option " + a + "\n" + usage);
  }
  if (scene == "chain") o.scene = make_chain(links, 0.1, 0.1, 1.0, t_end);
  else if (scene == "double_pendulum") o.scene = make_double_pendulum(t_end);
  else throw std::runtime_error("unknown --scene '" + scene + "' (chain, double_pendulum)");
  check_consistent(o.scene);
  if (o.reference.empty()) o.reference = o.scene.name + "_reference.json";
  return o;
}

inline bool wanted(const Options& o, const std::string& method) {
  return o.methods.empty() || std::find(o.methods.begin(), o.methods.end(), method) != o.methods.end();
}

// Compares a peer's initial energy with the analytic one and rigidae's; throws
// on a mismatch beyond 1e-12 relative. Prints one line on stderr.
inline void check_energy(const char* prog, const Scene& s, double e_model, const std::optional<Reference>& ref) {
  const double e_analytic = initial_energy(s);
  const double scale = std::max(std::fabs(e_analytic), 1e-300);
  std::fprintf(stderr, "%s: %s initial energy: model %.17g, analytic %.17g", prog, s.name.c_str(), e_model, e_analytic);
  double worst = std::fabs(e_model - e_analytic) / scale;
  if (ref) {
    std::fprintf(stderr, ", rigidae %.17g", ref->initial_energy);
    worst = std::max(worst, std::fabs(e_model - ref->initial_energy) / scale);
  }
  std::fprintf(stderr, " (worst relative difference %.2e)\n", worst);
  if (worst > 1e-12) throw std::runtime_error("initial energy differs from the scene's by more than 1e-12 relative");
}

struct Row {
  std::string peer, method, setting_kind;
  double setting = 0.0, wall_s = 0.0;
  int repeats = 0;
  long long steps = 0;
  std::optional<long long> rhs_evals;
  std::optional<Errors> err;
  double energy0 = 0.0, rel_energy_drift = 0.0;
  std::string extra;
};

inline void print_row(const Scene& s, const Row& r) {
  using peers::num;
  std::string line = "{\"peer\": \"" + r.peer + "\", \"scene\": \"" + s.name + "\", \"bodies\": " +
                     std::to_string(s.bodies.size()) + ", \"t_end\": " + num(s.t_end) + ", \"method\": \"" + r.method +
                     "\", \"setting\": " + num(r.setting) + ", \"setting_kind\": \"" + r.setting_kind +
                     "\", \"wall_s\": " + num(r.wall_s) + ", \"repeats\": " + std::to_string(r.repeats) +
                     ", \"steps\": " + std::to_string(r.steps) +
                     ", \"rhs_evals\": " + (r.rhs_evals ? std::to_string(*r.rhs_evals) : "null") +
                     ", \"error_rad\": " + (r.err ? num(r.err->rad) : "null") +
                     ", \"error_com_m\": " + (r.err ? num(r.err->com_m) : "null") +
                     ", \"worst_body\": " + (r.err ? "\"" + s.bodies[r.err->worst_body].name + "\"" : "null") +
                     ", \"energy0\": " + num(r.energy0) + ", \"rel_energy_drift\": " + num(r.rel_energy_drift);
  if (!r.extra.empty()) line += ", " + r.extra;
  line += "}";
  std::puts(line.c_str());
  std::fflush(stdout);
}

}  // namespace mb
