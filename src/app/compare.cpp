#include "rigidae/app/compare.hpp"

#include <fmt/format.h>
#include <fnmatch.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "rigidae/coords/representation.hpp"
#include "rigidae/core/error.hpp"
#include "rigidae/exact/exact_solution.hpp"
#include "rigidae/solver/ida_driver.hpp"
#include "rigidae/schemes/scheme.hpp"
#include "rigidae/so3/rotation.hpp"

namespace rigidae {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr const char* kAnyScheme = "any";
// The scheme an Euler-angle run uses: all give it the same ODE.
constexpr const char* kSchemeForUnconstrained = "ggl";

// The orientation on the output grid, read back from a run's trajectory.csv
// (columns t, qw, qx, qy, qz first).
struct GridOrientation {
  std::vector<double> t;
  std::vector<Vec4> q;
};

GridOrientation read_grid_orientation(const std::filesystem::path& csv) {
  GridOrientation g;
  std::ifstream in(csv);
  if (!in) throw InputError(fmt::format("{}: cannot read", csv.string()));
  std::string line;
  std::getline(in, line);  // units
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::istringstream row(line);
    std::string cell;
    double v[5];
    int k = 0;
    for (; k < 5 && std::getline(row, cell, ','); ++k) v[k] = std::strtod(cell.c_str(), nullptr);
    if (k < 5) break;
    g.t.push_back(v[0]);
    g.q.emplace_back(v[1], v[2], v[3], v[4]);
  }
  return g;
}

// Largest angle between two runs over the grid points both reached, and the
// angle at the reference's last point if the run reached it (else NaN).
std::pair<double, double> orientation_errors(const GridOrientation& run, const std::vector<double>& t_ref,
                                             const std::vector<Vec4>& q_ref) {
  const std::size_t n = std::min(run.t.size(), t_ref.size());
  double max_err = 0.0;
  for (std::size_t i = 0; i < n; ++i) max_err = std::max(max_err, so3::quaternion_distance(run.q[i], q_ref[i]));
  const bool complete = !t_ref.empty() && run.t.size() == t_ref.size();
  return {complete ? so3::quaternion_distance(run.q.back(), q_ref.back()) : kNaN, n > 0 ? max_err : kNaN};
}

double median(std::vector<double> v) {
  if (v.empty()) return kNaN;
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

std::string sci(double x, int digits = 1) {
  if (std::isnan(x)) return "-";
  return fmt::format("{:.{}e}", x, digits);
}

}  // namespace

std::string Combination::name() const {
  return fmt::format("{}/{}/{}", to_string(coordinates), to_string(equations), scheme);
}

std::string Combination::folder() const {
  return fmt::format("{}-{}-{}", to_string(coordinates), to_string(equations), scheme);
}

Scene Combination::applied_to(const Scene& scene) const {
  Scene s = scene;
  s.formulation.coordinates = coordinates;
  s.formulation.equations = equations;
  s.formulation.scheme = scheme == kAnyScheme ? kSchemeForUnconstrained : scheme;
  return s;
}

std::vector<Combination> all_combinations() {
  std::vector<Combination> all;
  for (Coordinates c : {Coordinates::EulerAngles, Coordinates::Quaternion, Coordinates::Linear})
    for (Equations e : {Equations::Lagrange, Equations::Euler}) {
      if (c == Coordinates::EulerAngles) {
        all.push_back({c, e, kAnyScheme});
        continue;
      }
      for (const std::string& s : scheme_names()) all.push_back({c, e, s});
    }
  return all;
}

bool matches(const Combination& c, const std::string& pattern) {
  if (pattern.find('/') != std::string::npos) return fnmatch(pattern.c_str(), c.name().c_str(), 0) == 0;
  for (const std::string& part : {to_string(c.coordinates), to_string(c.equations), c.scheme})
    if (fnmatch(pattern.c_str(), part.c_str(), 0) == 0) return true;
  return false;
}

CompareReport compare_scene(const Scene& scene, const CompareOptions& opt,
                            const std::function<void(const std::string&)>& progress) {
  auto say = [&](const std::string& s) {
    if (progress) progress(s);
  };
  std::vector<Combination> selected;
  for (const Combination& c : all_combinations()) {
    const bool in = opt.only.empty() || std::any_of(opt.only.begin(), opt.only.end(),
                                                    [&](const std::string& p) { return matches(c, p); });
    const bool out = std::any_of(opt.skip.begin(), opt.skip.end(), [&](const std::string& p) { return matches(c, p); });
    if (in && !out) selected.push_back(c);
  }
  if (selected.empty()) throw InputError("--only/--skip leave no combination to run; see rigidae compare --help");

  CompareReport report;
  report.scene_name = scene.name;
  report.scene_source = scene.source;
  report.rtol = scene.solver.rtol;
  report.atol = scene.solver.atol;

  ReferenceInfo& ref = report.reference;
  if (opt.reference != "auto" && opt.reference != "exact" && opt.reference != "tight")
    throw InputError(fmt::format("unknown reference '{}'; valid values: auto, exact, tight", opt.reference));
  std::string why_not_exact;
  std::unique_ptr<exact::ExactSolution> closed_form;
  if (opt.reference != "tight") {
    try {
      closed_form = exact::make_exact_solution(scene, &why_not_exact);
    } catch (const std::invalid_argument& e) {  // a case the closed forms do not cover (e.g. a separatrix)
      why_not_exact = e.what();
    }
    if (!closed_form && opt.reference == "exact")
      throw InputError(fmt::format("{}: no exact solution for this scene: {}", scene.source, why_not_exact));
  }
  if (closed_form) {
    ref.exact = true;
    ref.ok = true;
    ref.combination = "exact: " + closed_form->name();
    ref.accuracy_rad = closed_form->accuracy();
    ref.t = output_grid(scene.time);
    for (double t : ref.t) ref.q_WB.push_back(so3::matrix_to_quaternion(closed_form->at(t).R_WB));
    say(fmt::format("reference: {} (closed form, accuracy {:.1e} rad)", closed_form->name(), ref.accuracy_rad));
  } else {
    ref.rtol = opt.reference_rtol.value_or(std::clamp(scene.solver.rtol / 100.0, 1e-13, 1e-12));
    const Combination ref_combo{Coordinates::Quaternion, Equations::Euler, "ggl"};
    const Combination check_combo{Coordinates::EulerAngles, Equations::Euler, kAnyScheme};
    ref.combination = ref_combo.name();
    ref.check_combination = check_combo.name();
    auto tight = [&](const Combination& c) {
      Scene s = c.applied_to(scene);
      s.solver.rtol = ref.rtol;
      s.solver.atol = ref.rtol;
      return s;
    };
    const SolveOutcome a = solve_scene(tight(ref_combo), opt.out / "reference");
    say(fmt::format("reference {} at rtol {:g}: {} in {:.2f} s", ref.combination, ref.rtol, to_string(a.run.status),
                    a.wall_seconds));
    const SolveOutcome b = solve_scene(tight(check_combo), opt.out / "reference-check");
    say(fmt::format("cross-check {} at rtol {:g}: {} in {:.2f} s", ref.check_combination, ref.rtol,
                    to_string(b.run.status), b.wall_seconds));
    ref.ok = a.run.status == RunStatus::Success && b.run.status == RunStatus::Success;
    if (a.run.status != RunStatus::Success) ref.message = "reference run failed: " + a.run.message;
    else if (b.run.status != RunStatus::Success) ref.message = "cross-check run failed: " + b.run.message;
    ref.accuracy_rad = kNaN;
    if (ref.ok) {
      GridOrientation ga = read_grid_orientation(opt.out / "reference" / "trajectory.csv");
      const GridOrientation gb = read_grid_orientation(opt.out / "reference-check" / "trajectory.csv");
      ref.accuracy_rad = orientation_errors(gb, ga.t, ga.q).second;
      ref.t = std::move(ga.t);
      ref.q_WB = std::move(ga.q);
    }
  }

  const int total = static_cast<int>(selected.size());
  for (int k = 0; k < total; ++k) {
    CompareRow row;
    row.combination = selected[k];
    const Scene s = row.combination.applied_to(scene);
    const std::filesystem::path dir = opt.out / row.combination.folder();
    row.outcome = solve_scene(s, dir);
    row.wall_seconds.push_back(row.outcome.wall_seconds);
    // Repeats time the same work; a failed run is not worth timing again.
    for (int r = 1; r < opt.repeat && row.outcome.run.status == RunStatus::Success; ++r)
      row.wall_seconds.push_back(solve_scene(s, dir).wall_seconds);
    row.wall_median = median(row.wall_seconds);

    if (ref.ok) {
      const auto [final_err, max_err] =
          orientation_errors(read_grid_orientation(dir / "trajectory.csv"), ref.t, ref.q_WB);
      row.error_final_rad = row.outcome.run.status == RunStatus::Success ? final_err : kNaN;
      row.error_max_rad = max_err;
    } else {
      row.error_final_rad = row.error_max_rad = kNaN;
    }

    row.lambda_min = row.lambda_max = row.mu_abs_max = kNaN;
    const RunExtremes& x = row.outcome.extremes;
    for (std::size_t i = 0; i < row.outcome.multiplier_names.size() && x.steps_recorded > 0; ++i) {
      const bool force = row.outcome.multiplier_names[i].rfind("lambda_", 0) == 0;
      const int j = static_cast<int>(i);
      if (force) {
        row.lambda_min = std::isnan(row.lambda_min) ? x.multiplier_min(j) : std::min(row.lambda_min, x.multiplier_min(j));
        row.lambda_max = std::isnan(row.lambda_max) ? x.multiplier_max(j) : std::max(row.lambda_max, x.multiplier_max(j));
      } else {
        const double m = std::max(std::abs(x.multiplier_min(j)), std::abs(x.multiplier_max(j)));
        row.mu_abs_max = std::isnan(row.mu_abs_max) ? m : std::max(row.mu_abs_max, m);
      }
    }
    const IdaCounters& c = row.outcome.run.counters;
    say(fmt::format("[{}/{}] {:<28} {:<8} {:>8} steps {:>8.3f} s  final error {}", k + 1, total, row.combination.name(),
                    to_string(row.outcome.run.status), c.steps, row.wall_median, sci(row.error_final_rad)));
    report.rows.push_back(std::move(row));
  }
  return report;
}

std::string format_compare_table(const CompareReport& r) {
  std::string s;
  s += fmt::format("rigidae compare: {} ({}), rtol {:g}, atol {:g}\n", r.scene_name, r.scene_source, r.rtol, r.atol);
  const ReferenceInfo& ref = r.reference;
  if (ref.ok && ref.exact)
    s += fmt::format("reference: {}, the closed-form solution (estimated accuracy {:.1e} rad)\n", ref.combination,
                     ref.accuracy_rad);
  else if (ref.ok)
    s += fmt::format("reference: {} at rtol {:g}; its accuracy, estimated as the largest angle to {} at the same "
                     "rtol over the output grid: {:.1e} rad\n",
                     ref.combination, ref.rtol, ref.check_combination, ref.accuracy_rad);
  else
    s += fmt::format("reference: none ({}); errors are not reported\n", ref.message);
  s += fmt::format("{:<28} {:<8} {:>8} {:>9} {:>6} {:>8} {:>8} {:>8} {:>8} {:>8} {:>8} {:>21} {:>8} {:>8}\n",
                   "combination", "status", "steps", "res.evals", "jacs", "wall s", "max|Phi|", "max|dPhi|",
                   "max|dE/E|", "err end", "err max", "lambda range J", "max|mu|", "restarts");
  for (const CompareRow& row : r.rows) {
    const IdaCounters& c = row.outcome.run.counters;
    const RunExtremes& x = row.outcome.extremes;
    const bool constrained = row.combination.coordinates != Coordinates::EulerAngles;
    const std::string lambda =
        std::isnan(row.lambda_min) ? "-" : fmt::format("[{:.3g}, {:.3g}]", row.lambda_min, row.lambda_max);
    s += fmt::format("{:<28} {:<8} {:>8} {:>9} {:>6} {:>8.3f} {:>8} {:>8} {:>8} {:>8} {:>8} {:>21} {:>8} {:>8}\n",
                     row.combination.name(), to_string(row.outcome.run.status), c.steps,
                     c.residual_evals + c.jacobian_residual_evals, c.jacobian_evals, row.wall_median,
                     constrained ? sci(x.max_drift_position) : "-", constrained ? sci(x.max_drift_velocity) : "-",
                     sci(x.max_abs_energy_error), sci(row.error_final_rad), sci(row.error_max_rad), lambda,
                     sci(row.mu_abs_max), c.restarts);
  }
  bool any_failed = false;
  for (const CompareRow& row : r.rows)
    if (row.outcome.run.status != RunStatus::Success) {
      if (!any_failed) s += "failures:\n";
      any_failed = true;
      s += fmt::format("  {}: {}\n", row.combination.name(), row.outcome.run.message);
    }
  s += "units: drift |Phi| 1, |dPhi/dt| 1/s; errors are rotation angles to the reference in rad; wall is the median "
       "of the repeats; res.evals include those spent on difference Jacobians\n";
  return s;
}

void write_compare_outputs(const CompareReport& r, const std::filesystem::path& out) {
  auto open = [&](const char* name) {
    std::ofstream f(out / name);
    if (!f) throw InputError(fmt::format("{}: cannot open for writing", (out / name).string()));
    return f;
  };
  {
    std::ofstream f = open("compare.csv");
    f << fmt::format("# units: wall_s s (median of repeats); drift_position 1; drift_velocity 1/s; error_* rad to the "
                     "reference {}{} (estimated accuracy {:.3e} rad); lambda J; mu 1/s\n",
                     r.reference.combination,
                     r.reference.exact ? "" : fmt::format(" at rtol {:g}", r.reference.rtol), r.reference.accuracy_rad);
    f << "combination,coordinates,equations,scheme,status,steps,residual_evals,jacobian_residual_evals,jacobian_evals,"
         "nonlinear_iters,error_test_fails,nonlinear_conv_fails,restarts,projections,chart_switches,wall_s,repeats,"
         "max_drift_position,max_drift_velocity,max_abs_energy_rel_error,error_final_rad,error_max_rad,lambda_min,"
         "lambda_max,mu_abs_max,rtol,atol,scene,run_dir,message\n";
    for (const CompareRow& row : r.rows) {
      const IdaCounters& c = row.outcome.run.counters;
      const RunExtremes& x = row.outcome.extremes;
      std::string msg = row.outcome.run.message;
      std::replace(msg.begin(), msg.end(), '"', '\'');
      f << fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{:.6g},{},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e},"
                       "{:.6e},{:.6e},{:g},{:g},{},{},\"{}\"\n",
                       row.combination.name(), to_string(row.combination.coordinates),
                       to_string(row.combination.equations), row.combination.scheme, to_string(row.outcome.run.status),
                       c.steps, c.residual_evals, c.jacobian_residual_evals, c.jacobian_evals, c.nonlinear_iters,
                       c.error_test_fails, c.nonlinear_conv_fails, c.restarts, c.projections,
                       row.outcome.run.switch_count, row.wall_median, row.wall_seconds.size(), x.max_drift_position,
                       x.max_drift_velocity, x.max_abs_energy_error, row.error_final_rad, row.error_max_rad,
                       row.lambda_min, row.lambda_max, row.mu_abs_max, r.rtol, r.atol, r.scene_name,
                       row.combination.folder(), msg);
    }
  }
  const std::string table = format_compare_table(r);
  open("compare.txt") << table;
  {
    std::ofstream f = open("compare.md");
    f << "| combination | status | steps | residual evals | wall s | max \\|Phi\\| | max \\|dPhi/dt\\| | max \\|dE/E\\| "
         "| error at end, rad | max error, rad | restarts |\n|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const CompareRow& row : r.rows) {
      const IdaCounters& c = row.outcome.run.counters;
      const RunExtremes& x = row.outcome.extremes;
      const bool constrained = row.combination.coordinates != Coordinates::EulerAngles;
      f << fmt::format("| {} | {} | {} | {} | {:.3f} | {} | {} | {} | {} | {} | {} |\n", row.combination.name(),
                       to_string(row.outcome.run.status), c.steps, c.residual_evals + c.jacobian_residual_evals,
                       row.wall_median, constrained ? sci(x.max_drift_position) : "–",
                       constrained ? sci(x.max_drift_velocity) : "–", sci(x.max_abs_energy_error),
                       sci(row.error_final_rad), sci(row.error_max_rad), c.restarts);
    }
  }
}

}  // namespace rigidae
