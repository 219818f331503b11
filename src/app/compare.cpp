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
#include "rigidae/app/accuracy.hpp"
#include "rigidae/core/error.hpp"
#include "rigidae/io/checked_file.hpp"
#include "rigidae/record/columns.hpp"
#include "rigidae/record/trajectory_csv.hpp"
#include "rigidae/solver/ida_driver.hpp"
#include "rigidae/schemes/scheme.hpp"
#include "rigidae/so3/rotation.hpp"

namespace rigidae {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr const char* kAnyScheme = "any";
// The scheme a run without constraints (Euler angles) uses: all give it the same ODE.
constexpr const char* kSchemeForUnconstrained = "ggl";

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
  // Compare and study read trajectory.csv and (--keep-steps, --plot) steps.csv:
  // the scene's output.record and step_format are for solve.
  s.output = OutputSettings{};
  return s;
}

std::vector<Combination> all_combinations() {
  std::vector<Combination> all;
  for (const Coordinates& c : all_coordinates())
    for (Equations e : {Equations::Lagrange, Equations::Euler}) {
      if (!has_constraints(c)) {
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

  const std::string kind = opt.reference.empty() ? to_string(scene.reference) : opt.reference;
  report.reference = make_reference(scene, kind,
                                    opt.reference_rtol.value_or(default_reference_rtol(scene.solver.rtol)),
                                    opt.out, say);
  const ReferenceTrajectory& ref = report.reference;
  auto drop_steps = [&](const std::filesystem::path& dir) {
    std::error_code ec;
    if (!opt.keep_steps) std::filesystem::remove(dir / "steps.csv", ec);
  };
  drop_steps(opt.out / "reference");
  drop_steps(opt.out / "reference-check");

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

    row.accuracy = measure_accuracy(s, read_trajectory_csv(dir / "trajectory.csv"), ref,
                                    row.outcome.run.status == RunStatus::Success);
    drop_steps(dir);
    row.error_final_rad = row.accuracy.orientation_rad.final;
    row.error_max_rad = row.accuracy.orientation_rad.max;

    row.lambda_min = row.lambda_max = row.mu_abs_max = kNaN;
    const RunExtremes& x = row.outcome.extremes;
    for (std::size_t i = 0; i < row.outcome.multiplier_names.size() && x.steps_recorded > 0; ++i) {
      const bool force = columns::is_force_multiplier(row.outcome.multiplier_names[i]);
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
  s += fmt::format("reference: {}{}\n", r.reference.describe(), r.reference.ok ? "" : "; errors are not reported");
  s += fmt::format("{:<28} {:<8} {:>8} {:>9} {:>6} {:>8} {:>8} {:>8} {:>8} {:>8} {:>8} {:>21} {:>8} {:>8}\n",
                   "combination", "status", "steps", "res.evals", "jacs", "wall s", "max|Phi|", "max|dPhi|",
                   "max|dE/E|", "err end", "err max", "lambda range J", "max|mu|", "restarts");
  for (const CompareRow& row : r.rows) {
    const IdaCounters& c = row.outcome.run.counters;
    const RunExtremes& x = row.outcome.extremes;
    const bool constrained = has_constraints(row.combination.coordinates);
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
  bool any_warned = false;
  for (const CompareRow& row : r.rows)
    if (!row.outcome.warnings.empty()) {
      if (!any_warned) s += "accuracy warnings (drift in tolerances; limits in docs/accuracy_check.md):\n";
      any_warned = true;
      s += fmt::format("  {}: {}\n", row.combination.name(), warnings_cell(row.outcome.warnings));
    }
  s += "units: drift |Phi| 1, |dPhi/dt| 1/s; errors are rotation angles to the reference in rad; wall is the median "
       "of the repeats; res.evals include those spent on difference Jacobians\n";
  return s;
}

void write_compare_outputs(const CompareReport& r, const std::filesystem::path& out) {
  // Each table is made whole in memory and written atomically (io/checked_file.hpp).
  {
    std::ostringstream f;
    f << fmt::format("# units: wall_s s (median of repeats); drift_position 1; drift_velocity 1/s; error_* rad to the "
                     "reference {}{} (estimated accuracy {:.3e} rad); lambda J; mu 1/s\n",
                     r.reference.combination,
                     r.reference.exact ? "" : fmt::format(" at rtol {:g}", r.reference.rtol), r.reference.accuracy_rad);
    f << "combination,coordinates,equations,scheme,status,steps,residual_evals,jacobian_residual_evals,jacobian_evals,"
         "nonlinear_iters,error_test_fails,nonlinear_conv_fails,restarts,projections,chart_switches,wall_s,repeats,"
         "max_drift_position,max_drift_velocity,max_abs_energy_rel_error,error_final_rad,error_max_rad,lambda_min,"
         "lambda_max,mu_abs_max,rtol,atol,scene,run_dir,message,warnings\n";
    for (const CompareRow& row : r.rows) {
      const IdaCounters& c = row.outcome.run.counters;
      const RunExtremes& x = row.outcome.extremes;
      std::string msg = row.outcome.run.message;
      std::replace(msg.begin(), msg.end(), '"', '\'');
      f << fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{:.6g},{},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e},"
                       "{:.6e},{:.6e},{:g},{:g},{},{},\"{}\",\"{}\"\n",
                       row.combination.name(), to_string(row.combination.coordinates),
                       to_string(row.combination.equations), row.combination.scheme, to_string(row.outcome.run.status),
                       c.steps, c.residual_evals, c.jacobian_residual_evals, c.jacobian_evals, c.nonlinear_iters,
                       c.error_test_fails, c.nonlinear_conv_fails, c.restarts, c.projections,
                       row.outcome.run.switch_count, row.wall_median, row.wall_seconds.size(), x.max_drift_position,
                       x.max_drift_velocity, x.max_abs_energy_error, row.error_final_rad, row.error_max_rad,
                       row.lambda_min, row.lambda_max, row.mu_abs_max, r.rtol, r.atol, r.scene_name,
                       row.combination.folder(), msg, warnings_cell(row.outcome.warnings));
    }
    write_file_atomically(out / "compare.csv", f.str());
  }
  write_file_atomically(out / "compare.txt", format_compare_table(r));
  {
    std::ostringstream f;
    f << "| combination | status | steps | residual evals | wall s | max \\|Phi\\| | max \\|dPhi/dt\\| | max \\|dE/E\\| "
         "| error at end, rad | max error, rad | restarts | warnings |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const CompareRow& row : r.rows) {
      const IdaCounters& c = row.outcome.run.counters;
      const RunExtremes& x = row.outcome.extremes;
      const bool constrained = has_constraints(row.combination.coordinates);
      f << fmt::format("| {} | {} | {} | {} | {:.3f} | {} | {} | {} | {} | {} | {} | {} |\n", row.combination.name(),
                       to_string(row.outcome.run.status), c.steps, c.residual_evals + c.jacobian_residual_evals,
                       row.wall_median, constrained ? sci(x.max_drift_position) : "–",
                       constrained ? sci(x.max_drift_velocity) : "–", sci(x.max_abs_energy_error),
                       sci(row.error_final_rad), sci(row.error_max_rad), c.restarts,
                       warnings_cell(row.outcome.warnings));
    }
    write_file_atomically(out / "compare.md", f.str());
  }
}

}  // namespace rigidae
