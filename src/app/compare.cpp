#include "rigidae/app/compare.hpp"

#include "rigidae/model/one_body_system.hpp"

#include <fmt/format.h>
#include <fnmatch.h>

#include <algorithm>
#include <chrono>
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
#include "rigidae/settings/settings.hpp"
#include "rigidae/solver/integrators.hpp"

namespace rigidae {

namespace {

constexpr const char* kAnyScheme = "any";
// The scheme a run without constraints (Euler angles) uses: all give it the same ODE.
constexpr const char* kSchemeForUnconstrained = "ggl";
constexpr const char* kIda = "ida";
constexpr const char* kArkodeErk = "arkode-erk";

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

std::string IntegratorChoice::label() const {
  return erk_method.empty() ? integrator : integrator + ":" + erk_method;
}

std::string Combination::integrator_label() const { return IntegratorChoice{integrator, erk_method}.label(); }

std::string Combination::name() const {
  const std::string base = fmt::format("{}/{}/{}", to_string(coordinates), to_string(equations), scheme);
  return integrator == kIda ? base : base + "@" + integrator_label();
}

std::string Combination::folder() const {
  const std::string base = fmt::format("{}-{}-{}", to_string(coordinates), to_string(equations), scheme);
  if (integrator == kIda) return base;
  return base + "-" + integrator + (erk_method.empty() ? "" : "-" + erk_method);
}

Scene Combination::applied_to(const Scene& scene) const {
  Scene s = scene;
  s.formulation.coordinates = coordinates;
  s.formulation.equations = equations;
  s.solver.integrator = integrator;
  s.solver.integrator_named = true;
  s.solver.integrator_choice = "named";
  if (!erk_method.empty()) s.solver.erk_method = erk_method;
  if (scheme != kAnyScheme) {
    s.formulation.scheme = scheme;
  } else {
    // No constraint: the ODE integrators' own default (the projection scheme), IDA's ggl.
    const std::string ode_default = settings::default_scheme(integrator);
    s.formulation.scheme = ode_default.empty() ? kSchemeForUnconstrained : ode_default;
  }
  // Compare and study read trajectory.csv and (--keep-steps, --plot) steps.csv:
  // the scene's output.record and step_format are for solve.
  s.output = OutputSettings{};
  return s;
}

IntegratorChoice parse_integrator_choice(const std::string& text, const std::string& default_erk_method,
                                         const std::string& where) {
  const std::size_t colon = text.find(':');
  IntegratorChoice c{text.substr(0, colon), ""};
  const std::vector<std::string> names = integrator_names();
  const bool known = std::find(names.begin(), names.end(), c.integrator) != names.end();
  const std::vector<std::string> methods = erk_method_names();
  const bool erk = c.integrator == kArkodeErk;
  if (erk) c.erk_method = colon == std::string::npos ? default_erk_method : text.substr(colon + 1);
  const bool method_ok = !erk || std::find(methods.begin(), methods.end(), c.erk_method) != methods.end();
  if (!known || !method_ok || (!erk && colon != std::string::npos))
    throw InputError(fmt::format("{}unknown integrator '{}'; valid: {}", where.empty() ? "" : where + ": ", text,
                                 integrator_choices_text()));
  return c;
}

std::string integrator_choices_text() {
  std::string s;
  for (const std::string& i : integrator_names()) {
    s += (s.empty() ? "" : ", ") + i;
    if (i == kArkodeErk)
      for (const std::string& m : erk_method_names()) s += ", " + i + ":" + m;
  }
  return s;
}

std::vector<Combination> all_combinations() {
  Scene single_body;
  return combinations_for(single_body, {{kIda, ""}});
}

std::vector<Combination> combinations_for(const Scene& scene, const std::vector<IntegratorChoice>& integrators,
                                          const std::string& where) {
  // Only runs that can differ, read off the system the scene is (as_system):
  // the coordinates and the form matter only when some body has rotation
  // coordinates (a system of particles runs the same bit for bit in all of
  // them: the scene's own are run); the scheme matters only when the system
  // has constraint rows in those coordinates: a joint, a driver, or a body's
  // own (|q| = 1, R^T R = I). Without any (Euler angles on bodies that
  // nothing joins) every scheme is the same ODE: one run, scheme "any".
  const Scene system = as_system(scene);
  const MultibodySpec& spec = *system.multibody;
  const bool rotation_free = !spec.bodies.empty() && std::all_of(spec.bodies.begin(), spec.bodies.end(),
                                                                 [](const BodySpec& b) { return b.particle; });
  const bool joined = !spec.joints.empty() || !spec.drivers.empty();
  std::vector<Combination> all;
  for (const IntegratorChoice& ic : integrators) {
    const IntegratorInfo& info = find_integrator(ic.integrator, where);
    auto runs = [&](const std::string& scheme) {
      return info.schemes.empty() || std::find(info.schemes.begin(), info.schemes.end(), scheme) != info.schemes.end();
    };
    for (const Coordinates& c : all_coordinates())
      for (Equations e : {Equations::Lagrange, Equations::Euler}) {
        if (rotation_free && (c != scene.formulation.coordinates || e != scene.formulation.equations)) continue;
        if (!joined && (rotation_free || !has_constraints(c))) {
          all.push_back({c, e, kAnyScheme, ic.integrator, ic.erk_method});
          continue;
        }
        for (const std::string& s : scheme_names())
          if (runs(s)) all.push_back({c, e, s, ic.integrator, ic.erk_method});
      }
  }
  return all;
}

std::vector<IntegratorChoice> default_integrators(const Scene& scene) {
  std::vector<IntegratorChoice> out;
  for (const IntegratorInfo& i : integrators()) {
    out.push_back({i.name, i.name == kArkodeErk ? scene.solver.erk_method : ""});
  }
  return out;
}

bool matches(const Combination& c, const std::string& pattern, const std::string& default_integrator) {
  const std::size_t at = pattern.find('@');
  std::string combo = pattern.substr(0, at);
  std::string integrator = at == std::string::npos ? default_integrator : pattern.substr(at + 1);
  const std::vector<std::string> names = integrator_names();
  const std::string word = combo.substr(0, combo.find(':'));
  if (at == std::string::npos && std::find(names.begin(), names.end(), word) != names.end()) {
    integrator = combo;  // a bare integrator name
    combo = "*";
  }
  const std::string against = integrator.find(':') == std::string::npos ? c.integrator : c.integrator_label();
  if (fnmatch(integrator.c_str(), against.c_str(), 0) != 0) return false;
  if (combo.find('/') != std::string::npos) {
    const std::string base = fmt::format("{}/{}/{}", to_string(c.coordinates), to_string(c.equations), c.scheme);
    return fnmatch(combo.c_str(), base.c_str(), 0) == 0;
  }
  for (const std::string& part : {to_string(c.coordinates), to_string(c.equations), c.scheme})
    if (fnmatch(combo.c_str(), part.c_str(), 0) == 0) return true;
  return false;
}

CompareReport compare_scene(const Scene& scene, const CompareOptions& opt,
                            const std::function<void(const std::string&)>& progress) {
  auto say = [&](const std::string& s) {
    if (progress) progress(s);
  };
  std::vector<Combination> selected;
  for (const Combination& c : combinations_for(scene, default_integrators(scene))) {
    const bool in = opt.only.empty() || std::any_of(opt.only.begin(), opt.only.end(),
                                                    [&](const std::string& p) { return matches(c, p); });
    const bool out = std::any_of(opt.skip.begin(), opt.skip.end(), [&](const std::string& p) { return matches(c, p); });
    if (in && !out) selected.push_back(c);
  }
  if (selected.empty())
    throw InputError(
        "--only/--skip leave no combination to run; a scene runs every coordinates x equations x scheme on ida and "
        "index1, projection on the ODE integrators, less those that are the same run (see rigidae compare --help)");

  CompareReport report;
  report.scene_name = scene.name;
  report.scene_source = scene.source;
  report.rtol = scene.solver.rtol;
  report.atol = scene.solver.atol;

  const std::string kind = opt.reference.empty() ? to_string(scene.reference) : opt.reference;
  const auto reference_started = std::chrono::steady_clock::now();
  report.reference = make_reference(scene, kind,
                                    opt.reference_rtol.value_or(default_reference_rtol(scene.solver.rtol)),
                                    opt.out, say);
  const double reference_wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - reference_started).count();
  report.run_timeout_s = opt.run_timeout.value_or(default_run_timeout(reference_wall));
  report.run_timeout_default = !opt.run_timeout.has_value();
  report.reference_wall_s = reference_wall;
  const ReferenceTrajectory& ref = report.reference;
  report.positions = ref.ok && ref.grid.has_positions();
  if (g_interrupt_requested.load()) {
    report.interrupted = true;
    report.stopped = fmt::format("interrupted by {} while making the reference; no combination was run",
                                 interrupt_cause());
    return report;
  }
  if (!ref.ok && !opt.keep_going) {
    report.stopped = "the reference failed, so no error can be measured; no combination was run (--keep-going "
                     "runs them anyway)";
    return report;
  }
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
    Scene s = row.combination.applied_to(scene);
    s.solver.wall_time_limit = report.run_timeout_s;
    const std::filesystem::path dir = opt.out / row.combination.folder();
    row.outcome = solve_scene(s, dir);
    row.wall_seconds.push_back(row.outcome.wall_seconds);
    // Repeats time the same work; a failed run is not worth timing again.
    for (int r = 1; r < opt.repeat && row.outcome.run.status == RunStatus::Success && !g_interrupt_requested.load();
         ++r) {
      SolveOutcome again = solve_scene(s, dir);
      row.wall_seconds.push_back(again.wall_seconds);
      // A repeat stopped by a signal or the time limit wrote over the folder: the row is that run.
      if (again.run.status != RunStatus::Success) row.outcome = std::move(again);
    }
    row.wall_median = median(row.wall_seconds);

    row.accuracy = measure_run_accuracy(s, dir, ref, row.outcome.run.status == RunStatus::Success);
    row.verdict = accuracy_verdict(s, row.outcome, opt.error_estimate, "compare without --no-error-estimate");
    if (row.outcome.run.status == RunStatus::Success) add_error_estimate_to_summary(dir / "summary.json", row.verdict);
    apply_verdict(row.outcome, row.verdict);
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
    // A mechanism's bodies have positions too (a particle only a position).
    const std::string error = report.positions ? fmt::format("{} rad, {} m", sci(row.error_final_rad),
                                                             sci(row.accuracy.position_m.final))
                                               : sci(row.error_final_rad);
    say(fmt::format("[{}/{}] {:<28} {:<8} {:>8} steps {:>8.3f} s  final error {}", k + 1, total, row.combination.name(),
                    to_string(row.outcome.run.status), c.steps, row.wall_median, error));
    const bool interrupted = row.outcome.run.status == RunStatus::Interrupted || g_interrupt_requested.load();
    report.rows.push_back(std::move(row));
    if (interrupted) {
      // The interrupted run is a row (its steps kept); the rest are not started.
      report.interrupted = true;
      report.stopped = fmt::format("interrupted by {} after {} of {} combinations; the rows so far are kept",
                                   interrupt_cause(), k + 1, total);
      break;
    }
  }
  return report;
}

double default_run_timeout(double reference_wall_s) { return std::max(300.0, 10.0 * reference_wall_s); }

namespace {

// The error a row is ranked by (see IntegratorRanking); NaN when it has none.
double ranked_error(const CompareReport& r, const CompareRow& row) {
  if (row.outcome.run.status != RunStatus::Success || !r.reference.ok) return kNaN;
  return r.positions ? row.accuracy.position_m.max : row.error_max_rad;
}

// At most this many levels (the smallest errors kept): 1e-1 ... 1e-12 fits.
constexpr int kMaxRankingLevels = 12;

}  // namespace

IntegratorRanking rank_integrators(const CompareReport& r) {
  IntegratorRanking k;
  k.unit = r.positions ? "m" : "rad";
  double largest = 0.0, smallest = std::numeric_limits<double>::infinity();
  for (const CompareRow& row : r.rows) {
    const std::string label = row.combination.integrator_label();
    if (std::find(k.integrators.begin(), k.integrators.end(), label) == k.integrators.end())
      k.integrators.push_back(label);
    const double e = ranked_error(r, row);
    if (!std::isfinite(e) || !(row.wall_median > 0.0)) continue;
    largest = std::max(largest, e);
    smallest = std::min(smallest, e);
  }
  if (!(largest > 0.0)) return k;
  // A run exact to round-off (error 0) is ranked at the smallest level shown.
  smallest = std::max(smallest, largest * 1e-30);
  // Below the reference's own accuracy (its cross-check's distance, or the
  // closed form's) an error is the reference's, not the row's: no level there.
  const double floor = r.positions ? r.reference.accuracy_m : r.reference.accuracy_rad;
  if (std::isfinite(floor) && floor > 0.0) smallest = std::max(smallest, std::min(floor, largest));
  const int top = static_cast<int>(std::ceil(std::log10(largest)));
  const int bottom = std::max(static_cast<int>(std::ceil(std::log10(smallest))), top - kMaxRankingLevels + 1);
  for (int p = top; p >= bottom; --p) {
    FastestToError level;
    level.level = std::pow(10.0, p);
    level.row.assign(k.integrators.size(), -1);
    for (std::size_t i = 0; i < r.rows.size(); ++i) {
      const CompareRow& row = r.rows[i];
      const double e = ranked_error(r, row);
      // A hair above the level still counts: 1e-6 read back from 10^-6 is not above it.
      if (!std::isfinite(e) || !(row.wall_median > 0.0) || e > level.level * (1 + 1e-12)) continue;
      const auto at = std::find(k.integrators.begin(), k.integrators.end(), row.combination.integrator_label());
      int& best = level.row[static_cast<std::size_t>(at - k.integrators.begin())];
      if (best < 0 || row.wall_median < r.rows[static_cast<std::size_t>(best)].wall_median) best = static_cast<int>(i);
    }
    for (std::size_t j = 0; j < level.row.size(); ++j)
      if (level.row[j] >= 0 &&
          (level.fastest < 0 || r.rows[static_cast<std::size_t>(level.row[j])].wall_median <
                                    r.rows[static_cast<std::size_t>(level.row[static_cast<std::size_t>(level.fastest)])].wall_median))
        level.fastest = static_cast<int>(j);
    k.levels.push_back(std::move(level));
  }
  return k;
}

std::string format_integrator_ranking(const CompareReport& r) {
  const IntegratorRanking k = rank_integrators(r);
  if (k.integrators.size() < 2 || k.levels.empty()) return "";
  std::string s = fmt::format(
      "integrators to each error (largest error on the grid, {}{}): wall s of each integrator's fastest row "
      "reaching it, * the fastest, - none reaches it\n",
      k.unit, r.positions ? ", the worst body's centre of mass" : ", rotation");
  std::vector<std::size_t> width;
  s += fmt::format("  {:<9}", "error <=");
  for (const std::string& name : k.integrators) {
    width.push_back(std::max<std::size_t>(name.size(), 10));
    s += fmt::format(" {:>{}}", name, width.back());
  }
  s += "  fastest\n";
  for (const FastestToError& level : k.levels) {
    s += fmt::format("  {:<9.0e}", level.level);
    for (std::size_t j = 0; j < k.integrators.size(); ++j) {
      const int i = level.row[j];
      const std::string cell =
          i < 0 ? "-"
                : fmt::format("{:.3g}{}", r.rows[static_cast<std::size_t>(i)].wall_median,
                              static_cast<int>(j) == level.fastest ? "*" : "");
      s += fmt::format(" {:>{}}", cell, width[j]);
    }
    if (level.fastest >= 0) {
      const CompareRow& best =
          r.rows[static_cast<std::size_t>(level.row[static_cast<std::size_t>(level.fastest)])];
      s += fmt::format("  {}", best.combination.name());
    }
    s += "\n";
  }
  return s;
}

std::string format_compare_table(const CompareReport& r) {
  std::string s;
  s += fmt::format("rigidae compare: {} ({}), rtol {:g}, atol {:g}\n", r.scene_name, r.scene_source, r.rtol, r.atol);
  s += fmt::format("reference: {}{}\n", r.reference.describe(), r.reference.ok ? "" : "; errors are not reported");
  // The limit each combination ran under: a row that timed out says so, and
  // the reader should know the limit before reading a row as slow.
  if (r.run_timeout_s <= 0.0)
    s += "time limit per combination: none (--run-timeout 0)\n";
  else if (r.run_timeout_default)
    s += fmt::format("time limit per combination: {:g} s (default max(300 s, 10 x the reference's {:.3g} s); "
                     "--run-timeout S sets it)\n",
                     r.run_timeout_s, r.reference_wall_s);
  else
    s += fmt::format("time limit per combination: {:g} s (--run-timeout)\n", r.run_timeout_s);
  std::size_t width = 28;
  for (const CompareRow& row : r.rows) width = std::max(width, row.combination.name().size());
  s += fmt::format("{:<{}} {:<8} {:>8} {:>9} {:>6} {:>8} {:>8} {:>8} {:>8} {:>8} {:>8} {:>21} {:>8} {:>8}{}\n",
                   "combination", width, "status", "steps", "res.evals", "jacs", "wall s", "max|Phi|", "max|dPhi|",
                   "max|dE/E|", "err end", "err max", "lambda range J", "max|mu|", "restarts",
                   r.positions ? fmt::format(" {:>9} {:>9}", "pos end m", "pos max m") : "");
  for (const CompareRow& row : r.rows) {
    const IdaCounters& c = row.outcome.run.counters;
    const RunExtremes& x = row.outcome.extremes;
    const bool constrained = row.outcome.constrained;
    const std::string lambda =
        std::isnan(row.lambda_min) ? "-" : fmt::format("[{:.3g}, {:.3g}]", row.lambda_min, row.lambda_max);
    s += fmt::format("{:<{}} {:<8} {:>8} {:>9} {:>6} {:>8.3f} {:>8} {:>8} {:>8} {:>8} {:>8} {:>21} {:>8} {:>8}{}\n",
                     row.combination.name(), width, to_string(row.outcome.run.status), c.steps,
                     c.residual_evals + c.jacobian_residual_evals, c.jacobian_evals, row.wall_median,
                     constrained ? sci(x.max_drift_position) : "-", constrained ? sci(x.max_drift_velocity) : "-",
                     sci(x.max_abs_energy_error), sci(row.error_final_rad), sci(row.error_max_rad), lambda,
                     sci(row.mu_abs_max), c.restarts,
                     r.positions ? fmt::format(" {:>9} {:>9}", sci(row.accuracy.position_m.final),
                                               sci(row.accuracy.position_m.max))
                                 : "");
  }
  s += format_integrator_ranking(r);
  bool any_failed = false;
  for (const CompareRow& row : r.rows)
    if (row.outcome.run.status != RunStatus::Success) {
      if (!any_failed) s += "failures:\n";
      any_failed = true;
      s += fmt::format("  {}: {}\n", row.combination.name(), row.outcome.run.message);
    }
  if (!r.stopped.empty()) s += fmt::format("stopped: {}\n", r.stopped);
  // A multibody scene's start notes are the scene's, the same for every row: once.
  std::vector<std::string> start_notes;
  for (const CompareRow& row : r.rows)
    for (const std::string& w : row.outcome.start_warnings)
      if (std::find(start_notes.begin(), start_notes.end(), w) == start_notes.end()) start_notes.push_back(w);
  for (const std::string& w : start_notes) s += fmt::format("scene warning: {}\n", w);
  bool any_warned = false;
  for (const CompareRow& row : r.rows)
    if (!row.outcome.warnings.empty()) {
      if (!any_warned) s += "accuracy warnings (drift or error in tolerances; limits in docs/accuracy_check.md):\n";
      any_warned = true;
      s += fmt::format("  {}: {}\n", row.combination.name(), warnings_cell(row.outcome.warnings));
    }
  bool any_unestimated = false;
  for (const CompareRow& row : r.rows)
    if (!row.verdict.estimated() && row.outcome.run.status == RunStatus::Success) {
      if (!any_unestimated) s += "accuracy not estimated:\n";
      any_unestimated = true;
      s += fmt::format("  {}: {}\n", row.combination.name(), row.verdict.not_estimated);
    }
  s += fmt::format(
      "units: drift max |Phi| over the constraint rows (1 for a body's own rows, m for point rows, rad for angular "
      "rows) and max |dPhi/dt| (1/s, m/s, rad/s); dE/E the energy error over the initial energy (docs/"
      "accuracy_check.md); errors are the worst body's: rotation angle to the reference in rad{}; wall is the median "
      "of the repeats; res.evals include those spent on difference Jacobians\n",
      r.positions ? ", centre-of-mass distance (pos) in m" : "");
  return s;
}

void write_compare_outputs(const CompareReport& r, const std::filesystem::path& out) {
  // Each table is made whole in memory and written atomically (io/checked_file.hpp).
  {
    std::ostringstream f;
    f << fmt::format("# units: wall_s s (median of repeats); drift_position 1{}; drift_velocity 1/s; error_*_rad rad to the "
                     "reference {}{} (estimated accuracy {:.3e} rad{}); error_position_* m; lambda J; mu 1/s\n",
                     " (max |Phi| over the constraint rows: 1, m or rad)",
                     r.reference.combination,
                     r.reference.exact ? "" : fmt::format(" at rtol {:g}", r.reference.rtol), r.reference.accuracy_rad,
                     (std::isfinite(r.reference.accuracy_m) ? fmt::format(", {:.3e} m", r.reference.accuracy_m)
                                                            : std::string()) +
                         "; the worst body");
    f << "combination,coordinates,equations,scheme,status,steps,residual_evals,jacobian_residual_evals,jacobian_evals,"
         "nonlinear_iters,error_test_fails,nonlinear_conv_fails,restarts,projections,chart_switches,wall_s,repeats,"
         "max_drift_position,max_drift_velocity,max_abs_energy_rel_error,error_final_rad,error_max_rad,lambda_min,"
         "lambda_max,mu_abs_max,rtol,atol,scene,run_dir,message,warnings,integrator,error_position_final_m,"
         "error_position_max_m,estimate_source,estimate_orientation_max_rad,estimate_position_max_rel,length_scale_m,"
         "estimate_limit,companion_wall_s,not_estimated\n";
    for (const CompareRow& row : r.rows) {
      const IdaCounters& c = row.outcome.run.counters;
      const RunExtremes& x = row.outcome.extremes;
      std::string msg = row.outcome.run.message;
      std::replace(msg.begin(), msg.end(), '"', '\'');
      std::string not_estimated = row.verdict.not_estimated;
      std::replace(not_estimated.begin(), not_estimated.end(), '"', '\'');
      f << fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{:.6g},{},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e},"
                       "{:.6e},{:.6e},{:g},{:g},{},{},\"{}\",\"{}\",{},{:.6e},{:.6e},{},{:.6e},{:.6e},{:.6e},{:.6e},{:.6g},\"{}\"\n",
                       row.combination.name(), to_string(row.combination.coordinates),
                       to_string(row.combination.equations), row.combination.scheme, to_string(row.outcome.run.status),
                       c.steps, c.residual_evals, c.jacobian_residual_evals, c.jacobian_evals, c.nonlinear_iters,
                       c.error_test_fails, c.nonlinear_conv_fails, c.restarts, c.projections,
                       row.outcome.run.switch_count, row.wall_median, row.wall_seconds.size(), x.max_drift_position,
                       x.max_drift_velocity, x.max_abs_energy_error, row.error_final_rad, row.error_max_rad,
                       row.lambda_min, row.lambda_max, row.mu_abs_max, r.rtol, r.atol, r.scene_name,
                       row.combination.folder(), msg, warnings_cell(row.outcome.warnings),
                       row.combination.integrator_label(), row.accuracy.position_m.final, row.accuracy.position_m.max,
                       to_string(row.verdict.source), row.verdict.orientation.max, row.verdict.position_rel_max,
                       row.verdict.length_scale_m, row.verdict.limit, row.verdict.companion_wall_s, not_estimated);
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
      const bool constrained = row.outcome.constrained;
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
