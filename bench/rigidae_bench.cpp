// rigidae_bench: what rigidae's combinations cost and what accuracy they buy.
// Not part of the test suite; docs/benchmarks.md shows the numbers.
//
//   rigidae_bench info
//       one JSON line: CPU, cores, compiler, build type, versions, git commit
//   rigidae_bench reference SCENE [--out FILE] [--check FILE]
//       the closed-form orientation at the scene's end time as a reference
//       file (the format of bench/peers/heavy_top_reference.json); --check
//       prints its angle to another reference file
//   rigidae_bench cost SCENE [--jacobian K] [--rtol X] [--repeats N] [--budget S]
//                            [--only LIST] [--skip LIST] [--calls N]
//       per combination: wall time per IDA step (median of repeats, with and
//       without recording) and per residual evaluation (a timed loop of N
//       calls at the initial state, median of 7 batches)
//   rigidae_bench sweep SCENE [--jacobian K] [--rtols a,b,..] [--repeats N] [--budget S]
//                             [--only LIST] [--skip LIST] [--reference FILE] [--mode M]
//                             [--integrator I] [--erk-method M] [--through-system P]
//       per combination and rtol (atol = rtol): counters, wall time and the
//       final orientation error, one JSON line each in the format of
//       bench/peers/results.jsonl (peer "rigidae", setting_kind "rtol")
//
// --through-system by-body | kkt (sweep, --mode unrecorded only): which path
// of the ODE form MultibodyOde the unrecorded runs take (every one-body
// scene runs as a system of one pivoted body, one_body_system): by-body (the
// default, what solve takes: the one-body arithmetic, schemes/body_ode.hpp)
// or kkt (the general mechanism solve); IDA runs the same DAE either way.
// Rows carry "through_system" when the flag is given. Callgrind counts of
// both forms: docs/benchmarks.md, "The ODE form through the multibody model".
//
// I is solver.integrator (ida, cvode-adams, cvode-bdf, arkode-erk; default:
// the scene's) and M solver.erk_method (fehlberg78, verner65, dopri5): the
// ODE integrators run the combinations whose scheme they accept (index1,
// projection); rows name the method "COMBINATION@INTEGRATOR[:ERK]".
// K is the scene's solver.jacobian (central | ida_dq today; whatever the
// library accepts). LIST: comma-separated patterns as in `rigidae compare`
// ('quaternion/euler/*', 'ggl'). --reference: a JSON file with "t" and
// "quaternion" [w, x, y, z] (default: the scene's closed-form solution).
// --mode recorded | unrecorded | both (default both): "recorded" runs
// solve_scene, writing every step to /tmp/rigidae-bench-runs (what `rigidae
// solve` does); "unrecorded" runs the same integration with a sink that keeps
// nothing. Wall times cover the integration (and recording), not the setup.
// Each setting is run up to N times (default 3), fewer once its runs took S
// seconds (default 3), at least once.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "machine_info.hpp"
#include "rigidae/app/compare.hpp"
#include "rigidae/app/solve.hpp"
#include "rigidae/core/error.hpp"
#include "rigidae/exact/exact_solution.hpp"
#include "rigidae/io/scene_loader.hpp"
#include "rigidae/model/one_body_system.hpp"
#include "rigidae/multibody/multibody_ode.hpp"
#include "rigidae/multibody/multibody_problem.hpp"
#include "rigidae/so3/rotation.hpp"
#include "rigidae/solver/ida_driver.hpp"
#include "rigidae/solver/integrators.hpp"
#include "rigidae/solver/ode_driver.hpp"

namespace fs = std::filesystem;
using nlohmann::json;
using namespace rigidae;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct Options {
  std::string command, scene_path;
  std::optional<std::string> jacobian;
  std::optional<std::string> integrator, erk_method;
  std::vector<double> rtols;
  int repeats = 3;
  double budget_s = 3.0;
  std::vector<std::string> only, skip;
  std::string reference;  // file; empty: closed form
  std::string mode = "both";
  std::string out, check;
  long calls = 200000;
  std::string through_system;  // "", "by-body" or "kkt"
};

Options parse(int argc, char** argv) {
  Options o;
  if (argc < 2) throw InputError("usage: rigidae_bench info|reference|cost|sweep [SCENE] [options]; see the source header");
  o.command = argv[1];
  int i = 2;
  if (o.command != "info") {
    if (argc < 3) throw InputError("rigidae_bench " + o.command + ": missing SCENE");
    o.scene_path = argv[2];
    i = 3;
  }
  for (; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) throw InputError("missing value after " + a);
      return argv[++i];
    };
    if (a == "--jacobian") o.jacobian = next();
    else if (a == "--integrator") o.integrator = next();
    else if (a == "--erk-method") o.erk_method = next();
    else if (a == "--rtol" || a == "--rtols") {
      o.rtols.clear();
      for (const auto& s : peers::split(next())) o.rtols.push_back(std::stod(s));
    } else if (a == "--repeats") o.repeats = std::max(1, std::stoi(next()));
    else if (a == "--budget") o.budget_s = std::stod(next());
    else if (a == "--only") o.only = peers::split(next());
    else if (a == "--skip") o.skip = peers::split(next());
    else if (a == "--reference") o.reference = next();
    else if (a == "--mode") o.mode = next();
    else if (a == "--out") o.out = next();
    else if (a == "--check") o.check = next();
    else if (a == "--calls") o.calls = std::stol(next());
    else if (a == "--through-system") o.through_system = next();
    else throw InputError("unknown option " + a);
  }
  if (o.mode != "both" && o.mode != "recorded" && o.mode != "unrecorded")
    throw InputError("--mode must be recorded, unrecorded or both");
  if (!o.through_system.empty() && o.through_system != "by-body" && o.through_system != "kkt")
    throw InputError("--through-system must be by-body or kkt, not '" + o.through_system + "'");
  if (!o.through_system.empty() && (o.command != "sweep" || o.mode != "unrecorded"))
    throw InputError("--through-system runs with sweep --mode unrecorded only");
  return o;
}

void print(const json& j) {
  std::cout << j.dump() << std::endl;
}

// The scene with the integrator options applied.
Scene load_with_integrator(const Options& o) {
  Scene s = io::load_scene(o.scene_path);
  if (o.integrator) s.solver.integrator = *o.integrator;
  if (o.erk_method) s.solver.erk_method = *o.erk_method;
  find_integrator(s.solver.integrator, "--integrator");
  find_erk_method(s.solver.erk_method, "--erk-method");
  return s;
}

// The combinations --only/--skip select that the integrator runs.
std::vector<Combination> selected(const Options& o, const Scene& scene) {
  std::vector<Combination> out;
  const IntegratorInfo& info = find_integrator(scene.solver.integrator);
  for (Combination c : all_combinations()) {
    // A combination names its integrator (Combination::applied_to sets it): the one asked for.
    c.integrator = scene.solver.integrator;
    c.erk_method = scene.solver.integrator == "arkode-erk" ? scene.solver.erk_method : "";
    if (!info.schemes.empty() && c.scheme != "any" &&
        std::find(info.schemes.begin(), info.schemes.end(), c.scheme) == info.schemes.end())
      continue;
    bool keep = o.only.empty();
    for (const auto& p : o.only) keep = keep || matches(c, p, c.integrator);
    for (const auto& p : o.skip) keep = keep && !matches(c, p, c.integrator);
    if (keep) out.push_back(c);
  }
  if (out.empty()) throw InputError("no combination matches --only/--skip");
  return out;
}

// ---- the reference -----------------------------------------------------------

Vec4 exact_final_quaternion(const Scene& scene, std::string* name) {
  std::string why;
  auto exact = exact::make_exact_solution(scene, &why);
  if (!exact) throw InputError(scene.source + ": no closed-form solution (" + why + "); pass --reference FILE");
  if (name) *name = exact->name();
  return so3::matrix_to_quaternion(exact->at(scene.time.end).R_WB);
}

Vec4 load_reference(const std::string& path, double t_end) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open reference");
  const json j = json::parse(in);
  const double t = j.at("t").get<double>();
  if (std::abs(t - t_end) > 1e-12 * std::max(1.0, std::abs(t_end)))
    throw InputError(path + ": reference at t = " + std::to_string(t) + ", the scene ends at " + std::to_string(t_end));
  const auto q = j.at("quaternion").get<std::vector<double>>();
  if (q.size() != 4) throw InputError(path + ": \"quaternion\" needs 4 numbers");
  return Vec4(q[0], q[1], q[2], q[3]);
}

// ---- one run -----------------------------------------------------------------

// Keeps only the state at the last output-grid point (the end time).
class FinalStateSink final : public StepSink {
 public:
  double t_last = kNaN;
  Eigen::VectorXd y_last;
  void on_step(double, double, int, const Eigen::VectorXd&) override {}
  void on_output(double t, const Eigen::VectorXd& y) override {
    t_last = t;
    y_last = y;
  }
  bool needs_every_output() const override { return false; }
};

struct RunSample {
  RunResult run;
  double wall_s = 0.0;
  Vec4 q_end = Vec4::Constant(kNaN);
};

// The integration without recording, as every scene runs: the scene as a
// system of one pivoted body; the ODE form on its per-body path (what solve
// takes) or on the KKT path.
RunSample run_through_system(const Scene& s, bool by_body) {
  multibody::MultibodyProblem problem(one_body_system(s));
  const bool ode_form = find_integrator(s.solver.integrator).is_ode;
  std::optional<multibody::MultibodyOde> ode;
  if (ode_form) ode.emplace(problem, false, s.source, true, by_body);
  FinalStateSink sink;
  RunSample r;
  const auto t0 = std::chrono::steady_clock::now();
  try {
    if (ode_form)
      r.run = integrate_ode(*ode, s.solver, s.time,
                            {s.solver.integrator,
                             s.solver.erk_method,
                             {problem.scheme().projection, s.formulation.projection.every_step,
                              projection_threshold(s)}},
                            sink);
    else
      r.run = integrate(problem, s.solver, s.time, sink);
  } catch (const SolverError& e) {
    r.run.status = RunStatus::Failed;
    r.run.message = e.what();
  }
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (r.run.status == RunStatus::Success && sink.y_last.size() > 0)
    r.q_end = problem.body_orientation(0, sink.y_last.data());
  return r;
}

RunSample run_recorded(const Scene& s, const Combination& c) {
  const fs::path dir = fs::path("/tmp/rigidae-bench-runs") / s.name / c.folder();
  const SolveOutcome o = solve_scene(s, dir);
  RunSample r;
  r.run = o.run;
  r.wall_s = o.wall_seconds;
  if (o.run.status == RunStatus::Success) r.q_end = o.extremes.last.q_WB;
  return r;
}

// Runs f up to `repeats` times (fewer once they took `budget` s, at least once).
template <class F>
std::pair<RunSample, std::vector<double>> repeated(F&& f, int repeats, double budget) {
  std::vector<double> walls;
  RunSample first;
  double total = 0.0;
  for (int k = 0; k < repeats; ++k) {
    RunSample r = f();
    if (k == 0) first = r;
    walls.push_back(r.wall_s);
    total += r.wall_s;
    if (total >= budget || r.run.status != RunStatus::Success) break;
  }
  return {first, walls};
}

json counters_json(const IdaCounters& c) {
  return {{"steps", c.steps},
          {"residual_evals", c.residual_evals},
          {"jacobian_residual_evals", c.jacobian_residual_evals},
          {"rhs_evals", c.residual_evals + c.jacobian_residual_evals},
          {"jacobian_evals", c.jacobian_evals},
          {"nonlinear_iters", c.nonlinear_iters},
          {"nonlinear_conv_fails", c.nonlinear_conv_fails},
          {"error_test_fails", c.error_test_fails},
          {"linear_setups", c.linear_setups},
          {"restarts", c.restarts}};
}

json nullable(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

Scene with_settings(const Scene& base, const Combination& c, double rtol, const std::optional<std::string>& jac) {
  Scene s = c.applied_to(base);
  s.solver.rtol = rtol;
  s.solver.atol = rtol;
  if (jac) s.solver.jacobian = *jac;
  // Euler angles ("any" scheme) carry no constraint: the plain ODE.
  if (c.scheme == "any" && find_integrator(s.solver.integrator).is_ode) s.formulation.scheme = "index1";
  return s;
}

// The work a setting takes and the error it leaves, one JSON line.
json measure(const Scene& s, const Combination& c, const Options& o, const std::optional<Vec4>& q_ref) {
  json row = {{"peer", "rigidae"},
              {"scene", s.name},
              {"method", c.name()},
              {"integrator", s.solver.integrator},
              {"jacobian", s.solver.jacobian},
              {"setting", s.solver.rtol},
              {"setting_kind", "rtol"},
              {"atol", s.solver.atol}};
  std::optional<RunSample> main;
  if (o.mode != "recorded") {
    auto [r, walls] = repeated(
        [&] {
          return run_through_system(s, o.through_system != "kkt");
        },
        o.repeats, o.budget_s);
    if (!o.through_system.empty()) row["through_system"] = o.through_system;
    row["wall_s_unrecorded"] = bench::median(walls);
    row["repeats_unrecorded"] = walls.size();
    main = r;
  }
  if (o.mode != "unrecorded") {
    auto [r, walls] = repeated([&] { return run_recorded(s, c); }, o.repeats, o.budget_s);
    row["wall_s"] = bench::median(walls);
    row["repeats"] = walls.size();
    if (main && r.run.counters.steps != main->run.counters.steps)
      row["warning"] = "recorded and unrecorded runs took different numbers of steps";
    main = r;
  } else {
    row["wall_s"] = row["wall_s_unrecorded"];
    row["repeats"] = row["repeats_unrecorded"];
  }
  const RunSample& r = *main;
  row["status"] = to_string(r.run.status);
  if (!r.run.message.empty()) row["message"] = r.run.message;
  row["t_reached"] = r.run.t_reached;
  row.update(counters_json(r.run.counters));
  const double err = q_ref && r.run.status == RunStatus::Success ? bench::angle_between(*q_ref, r.q_end) : kNaN;
  row["error_rad"] = nullable(err);
  row["q_final"] = {nullable(r.q_end[0]), nullable(r.q_end[1]), nullable(r.q_end[2]), nullable(r.q_end[3])};
  // An exact Jacobian spends no residual evaluations: a non-zero count means
  // the library fell back to difference quotients for this name.
  if (s.solver.jacobian == "exact" && r.run.counters.jacobian_residual_evals > 0)
    row["warning"] = "jacobian 'exact' requested but residual evaluations were spent on Jacobians";
  return row;
}

// ---- commands ----------------------------------------------------------------

int cmd_reference(const Options& o) {
  const Scene scene = io::load_scene(o.scene_path);
  std::string name;
  const Vec4 q = exact_final_quaternion(scene, &name);
  json j = {{"scene", scene.name + " (" + o.scene_path + ")"},
            {"t", scene.time.end},
            {"quaternion", {q[0], q[1], q[2], q[3]}},
            {"quaternion_order", "w, x, y, z (body to space)"},
            {"how", "rigidae's closed-form solution: " + name + " (include/rigidae/exact/)"}};
  if (!o.check.empty()) {
    const Vec4 other = load_reference(o.check, scene.time.end);
    j["check"] = {{"file", o.check}, {"angle_rad", bench::angle_between(other, q)}};
  }
  if (o.out.empty()) {
    print(j);
  } else {
    std::ofstream(o.out) << j.dump(2) << '\n';
    std::cerr << "rigidae_bench: wrote " << o.out << '\n';
  }
  return 0;
}

int cmd_cost(Options o) {
  const Scene scene = load_with_integrator(o);
  const double rtol = o.rtols.empty() ? scene.solver.rtol : o.rtols.front();
  o.mode = "both";
  print(bench::machine_info("rigidae_bench cost"));
  for (const Combination& c : selected(o, scene)) {
    const Scene s = with_settings(scene, c, rtol, o.jacobian);
    json row = measure(s, c, o, std::nullopt);
    row["kind"] = "cost";
    const double steps = row["steps"].get<double>();
    row["us_per_step"] = 1e6 * row["wall_s"].get<double>() / steps;
    row["us_per_step_unrecorded"] = 1e6 * row["wall_s_unrecorded"].get<double>() / steps;
    row["rhs_evals_per_step"] = row["rhs_evals"].get<double>() / steps;
    row["residual_evals_per_step"] = row["residual_evals"].get<double>() / steps;

    // One residual evaluation at the consistent initial state, timed in
    // batches: the scene as every scene runs (a system of one pivoted body).
    multibody::MultibodyProblem problem(one_body_system(s));
    Eigen::VectorXd y, yp, F(problem.size());
    problem.initial_state(s.time.start, y, yp);
    std::vector<double> per_call;
    double sink = 0.0;
    for (int b = 0; b < 7; ++b) {
      const auto t0 = std::chrono::steady_clock::now();
      for (long k = 0; k < o.calls; ++k) {
        problem.residual(s.time.start, y.data(), yp.data(), F.data());
        sink += F[0];
      }
      per_call.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() /
                         static_cast<double>(o.calls));
    }
    row["ns_per_residual"] = 1e9 * bench::median(per_call);
    row["n_unknowns"] = problem.size();
    if (!std::isfinite(sink)) row["warning"] = "non-finite residual at the start";
    print(row);
  }
  return 0;
}

int cmd_sweep(Options o) {
  const Scene scene = load_with_integrator(o);
  if (o.rtols.empty())
    for (int e = 3; e <= 13; ++e) o.rtols.push_back(std::pow(10.0, -e));
  std::optional<Vec4> q_ref;
  std::string ref_how;
  if (o.reference.empty()) {
    q_ref = exact_final_quaternion(scene, &ref_how);
    ref_how = "closed form: " + ref_how;
  } else {
    q_ref = load_reference(o.reference, scene.time.end);
    ref_how = o.reference;
  }
  json info = bench::machine_info("rigidae_bench sweep");
  info["scene"] = scene.name;
  info["reference"] = ref_how;
  print(info);
  for (const Combination& c : selected(o, scene))
    for (double rtol : o.rtols) {
      json row = measure(with_settings(scene, c, rtol, o.jacobian), c, o, q_ref);
      row["kind"] = "sweep";
      print(row);
    }
  return 0;
}

}  // namespace

int main(int argc, char** argv) try {
  const Options o = parse(argc, argv);
  if (o.command == "info") {
    print(bench::machine_info("rigidae_bench"));
    return 0;
  }
  if (o.command == "reference") return cmd_reference(o);
  if (o.command == "cost") return cmd_cost(o);
  if (o.command == "sweep") return cmd_sweep(o);
  throw InputError("unknown command '" + o.command + "' (info, reference, cost, sweep)");
} catch (const InputError& e) {
  std::cerr << "rigidae_bench: " << e.what() << '\n';
  return 2;
} catch (const std::exception& e) {
  std::cerr << "rigidae_bench: " << e.what() << '\n';
  return 1;
}
