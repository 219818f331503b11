// The accuracy verdict: closed form or companion run, see
// include/rigidae/app/error_estimate.hpp.
#include "rigidae/app/error_estimate.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <iterator>
#include <cmath>
#include <fstream>
#include <tuple>
#include <vector>

#include "counters_json.hpp"
#include "rigidae/app/multibody_accuracy_check.hpp"
#include "rigidae/app/reference.hpp"
#include "rigidae/solver/ida_driver.hpp"
#include "rigidae/core/error.hpp"
#include "rigidae/io/checked_file.hpp"
#include "rigidae/model/one_body_system.hpp"
#include "rigidae/record/trajectory_csv.hpp"
#include "rigidae/settings/settings.hpp"
#include "rigidae/so3/rotation.hpp"

namespace rigidae {

namespace {

// Angles between two grids' orientations on the common output grid (the
// worst body per point): at the last point and the largest over points.
OrientationError compare_orientations(const BodyGrid& run, const BodyGrid& other) {
  OrientationError e;
  const std::size_t n = std::min(run.t.size(), other.t.size());
  if (n == 0) return e;
  e.max = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    if (std::abs(run.t[i] - other.t[i]) > 1e-9 * (1.0 + std::abs(other.t[i])))
      throw InputError(fmt::format("output grids differ at point {}: t = {} s and {} s", i, run.t[i], other.t[i]));
    double worst = 0.0;
    for (std::size_t b = 0; b < std::min(run.bodies.size(), other.bodies.size()); ++b)
      worst = std::max(worst, so3::quaternion_distance(run.q_WB[i][b], other.q_WB[i][b]));
    e.max = std::max(e.max, worst);
    e.final = worst;
    e.t_final = run.t[i];
  }
  return e;
}

nlohmann::json number_or_null(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); }

nlohmann::json error_json(const OrientationError& e) {
  return {{"final_orientation_rad", number_or_null(e.final)},
          {"max_orientation_rad", number_or_null(e.max)},
          {"t_final", number_or_null(e.t_final)}};
}

// The system's size L that position differences are divided by: the
// mechanism's size (app/multibody_accuracy_check.hpp), and at least each
// pivoted body's lever from its pivot (a top's, or a pendulum's on a pivot,
// which the anchors alone would put at the 1 mm floor).
double system_size(const Scene& scene) {
  const Scene system = as_system(scene);
  double L = mechanism_size(*system.multibody);
  for (const BodySpec& b : system.multibody->bodies)
    if (b.pivot_W) L = std::max(L, (b.x0_W - *b.pivot_W).norm());
  return L;
}

// The companion's grid against the run's, body by body: orientation angle
// and, where the files record positions (a mechanism's), the centre-of-mass
// distance over the system's size L, the worst body per point.
void compare_bodies(const Scene& scene, const BodyGrid& run, const BodyGrid& companion, ErrorEstimate& e) {
  if (run.t.empty() || companion.t.empty() || run.bodies.empty() || run.bodies != companion.bodies)
    throw InputError("the run's and the companion's trajectory.csv hold different bodies or no grid point");
  if (run.t.size() != companion.t.size())
    throw InputError(fmt::format("the run has {} output points, the companion {}", run.t.size(), companion.t.size()));
  e.orientation = compare_orientations(run, companion);
  if (!run.has_positions() || !companion.has_positions()) return;
  e.length_scale_m = system_size(scene);
  e.position_rel_max = 0.0;
  for (std::size_t i = 0; i < run.t.size(); ++i) {
    double x = 0.0;
    for (std::size_t b = 0; b < run.bodies.size(); ++b)
      x = std::max(x, (run.x_W[i][b] - companion.x_W[i][b]).norm() / e.length_scale_m);
    e.position_rel_max = std::max(e.position_rel_max, x);
    e.position_rel_final = x;
  }
}

std::string status_text(const SolveOutcome& o) {
  return o.run.status == RunStatus::Success ? "success" : to_string(o.run.status) + ": " + o.run.message;
}

}  // namespace

std::string to_string(EstimateSource s) {
  switch (s) {
    case EstimateSource::ClosedForm: return "closed form";
    case EstimateSource::Companion: return "companion";
    default: return "none";
  }
}

std::pair<double, double> tight_tolerances(const SolverSettings& run) {
  const double rtol_min = settings::scene_setting("solver.rtol").min->value;
  const double atol_min = settings::scene_setting("solver.atol").min->value;
  return {std::max(run.rtol / 100.0, rtol_min), std::max(run.atol / 100.0, atol_min)};
}

void judge(ErrorEstimate& e, const Scene& scene) {
  e.tolerance = std::max(scene.solver.rtol, scene.solver.atol);
  e.length_scale_m = system_size(scene);
  e.limit = kVerdictFactor * e.tolerance;
  e.warnings.clear();
  e.branch_disagreement = false;
  if (!e.estimated()) return;
  const bool closed = e.source == EstimateSource::ClosedForm;
  const std::string against =
      closed ? "against the closed form"
             : fmt::format("estimated against a companion run{} at rtol {:g}, atol {:g}",
                           e.companion_combination.empty() ? "" : " in " + e.companion_combination, e.rtol, e.atol);
  // After a singular pose the companion is no closer to the truth than the
  // run (either may have switched branch: on problems/singular_linkage.toml
  // runs within 1e-5 rad of the closed form had companions 1.7-2.6 rad away),
  // so the difference is reported as what it is, not as the run's error.
  const bool after_singular_pose =
      e.source == EstimateSource::Companion && e.singular_pose_passed && e.arbiter != "companion";
  auto warn = [&](const char* quantity, double value, const std::string& what) {
    if (!(value > e.limit) && std::isfinite(value)) return;
    e.warnings.push_back({quantity, value, e.limit, kVerdictFactor, e.tolerance,
                          fmt::format("{} {:.2e} ({}, {}), {:.3g} x the tolerance max(rtol, atol) = {:.2e}, past the "
                                      "limit 300 x tolerance = {:.2e}: {}",
                                      quantity, value, what, against, value / e.tolerance, e.tolerance, e.limit,
                                      after_singular_pose ? "the results may be far less accurate than the tolerance "
                                                            "suggests"
                                                          : "the results are far less accurate than the tolerance "
                                                            "suggests")});
  };
  warn("orientation_error", e.orientation.max, "rad, the largest over the output grid and the bodies");
  // A mechanism's companion, or its closed form (the simple pendulum), gives positions too.
  if (std::isfinite(e.position_rel_max))
    warn("position_error", e.position_rel_max,
         fmt::format("the largest centre-of-mass distance over the output grid and the bodies relative to the "
                     "mechanism's size L = {:.3g} m",
                     e.length_scale_m));
  if (e.source == EstimateSource::Companion && std::isfinite(e.position_rel_max)) {
    const bool apart = e.position_rel_max > 1.0;
    e.branch_disagreement = apart || (after_singular_pose && !e.warnings.empty());
    // An arbiter that agreed with the companion is said below, for every scene.
    if (e.arbiter != "companion" && apart && !e.warnings.empty())
      e.warnings.back().message += fmt::format(
          "; the run and its companion differ by more than the mechanism's size: one of them changed assembly "
          "branch at a singular pose (or the motion is chaotic), and which one is right is not known");
    else if (e.arbiter != "companion" && e.branch_disagreement)
      for (AccuracyWarning& w : e.warnings)
        w.message += "; the run or its companion passed a singular pose (singular_pose), where either may have "
                     "changed assembly branch: the difference may be the companion's and which one is right is "
                     "not known (compare with a closed form or the mechanism's known branch)";
  }
  if (e.arbiter == "companion")
    for (AccuracyWarning& w : e.warnings)
      w.message += fmt::format(
          "; the run or its companion passed a singular pose, and a third run ({} at the companion's tolerances) "
          "agrees with the companion, not with the run: the run most likely changed assembly branch there",
          e.arbiter_combination);
}

void apply_verdict(SolveOutcome& run, const ErrorEstimate& e) {
  run.warnings.insert(run.warnings.end(), e.warnings.begin(), e.warnings.end());
}

namespace {

bool within(const ErrorEstimate& d, double limit) {
  return d.orientation.max <= limit && !(d.position_rel_max > limit);
}

// The Euler-form combinations on IDA that stand in for a companion that
// failed, and arbitrate after a singular pose, in the order tried: ggl (the
// reference formulation), then index2 and projection in linear coordinates,
// which pass singular poses where ggl's Newton iteration fails on the
// singular saddle-point matrix (on their branch or not as the step sequence
// falls: their own branch check says which).
struct StandIn {
  Coordinates coordinates;
  const char* scheme;
};
const StandIn kStandIns[] = {
    {Coordinates::Quaternion, "ggl"}, {Coordinates::Linear, "index2"}, {Coordinates::Linear, "projection"}};

std::string combination_name(const StandIn& c) {
  return fmt::format("{}/euler/{}", to_string(c.coordinates), c.scheme);
}

bool same_formulation(const Scene& s, const StandIn& c) {
  return s.formulation.coordinates == c.coordinates && s.formulation.equations == Equations::Euler &&
         s.formulation.scheme == c.scheme;
}

bool runs_as(const Scene& s, const StandIn& c) { return same_formulation(s, c) && s.solver.integrator == "ida"; }

Scene as_stand_in(const Scene& tight, const StandIn& c) {
  Scene s = tight;
  s.formulation.coordinates = c.coordinates;
  s.formulation.equations = Equations::Euler;
  s.formulation.scheme = c.scheme;
  s.solver.integrator = "ida";
  return s;
}

// The arbiter after a singular pose (error_estimate.hpp, "Branch check"):
// `tight` is the companion's scene (its tolerances and limits); e.tight_dir
// holds its run. The stand-ins in turn, ggl in other coordinates than the
// companion's first, the first that reaches the end without a branch switch
// of its own deciding (on singular_linkage at rtol 1e-11 linear/euler/index2
// switches, linear/euler/projection keeps it).
void arbitrate(const Scene& scene, const SolveOutcome& run, const Scene& tight, ErrorEstimate& e) {
  const StandIn linear_ggl{Coordinates::Linear, "ggl"};
  StandIn candidates[std::size(kStandIns)];
  std::copy(std::begin(kStandIns), std::end(kStandIns), candidates);
  if (!(e.companion_combination.empty() && same_formulation(tight, linear_ggl))) candidates[0] = linear_ggl;
  const std::filesystem::path dir = run.out_dir / "error_estimate_arbiter";
  std::string failures;
  for (const StandIn& candidate : candidates) {
    e.arbiter_combination = combination_name(candidate);
    // The companion's own combination, on any integrator, is no arbiter.
    const bool companion_itself = e.companion_combination.empty() ? same_formulation(tight, candidate)
                                                                  : e.companion_combination == e.arbiter_combination;
    if (companion_itself) continue;
    std::string failed;
    SolveOutcome a;
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);  // an earlier candidate's files
    try {
      a = solve_scene(as_stand_in(tight, candidate), dir);
      e.companion_wall_s += a.wall_seconds;
      if (a.run.status != RunStatus::Success)
        failed = status_text(a);
      else if (std::any_of(a.warnings.begin(), a.warnings.end(),
                           [](const AccuracyWarning& w) { return w.quantity == "branch_switch"; }))
        failed = "it changed branch at a singular pose itself";
    } catch (const std::runtime_error& x) {
      failed = x.what();
    }
    if (failed.empty()) {
      ErrorEstimate to_run, to_companion;
      try {
        const BodyGrid arbiter_grid = read_trajectory_csv(dir / "trajectory.csv");
        compare_bodies(scene, read_trajectory_csv(run.out_dir / "trajectory.csv"), arbiter_grid, to_run);
        compare_bodies(scene, read_trajectory_csv(e.tight_dir / "trajectory.csv"), arbiter_grid, to_companion);
      } catch (const std::runtime_error& x) {
        e.arbiter = fmt::format("failed: {}", x.what());
        return;
      }
      if (within(to_run, e.limit)) {
        e.arbiter = "run";
        e.orientation = to_run.orientation;
        e.position_rel_max = to_run.position_rel_max;
        e.position_rel_final = to_run.position_rel_final;
      } else {
        e.arbiter = within(to_companion, e.limit) ? "companion" : "neither";
      }
      return;
    }
    failures += fmt::format("{}{}: {}", failures.empty() ? "" : "; ", e.arbiter_combination, failed);
    if (g_interrupt_requested.load()) break;
  }
  e.arbiter = "failed: " + failures;
}

}  // namespace

ErrorEstimate estimate_global_error(const Scene& scene, const SolveOutcome& run, const CompanionLimits& limits) {
  ErrorEstimate e;
  Scene tight = scene;
  std::tie(tight.solver.rtol, tight.solver.atol) = tight_tolerances(scene.solver);
  tight.output.record = RecordMode::Grid;
  // Ten times the steps a run at 1/100 of the tolerance takes at order 2; no fewer than the run allowed.
  tight.solver.max_steps = limits.max_steps > 0 ? limits.max_steps : std::max(scene.solver.max_steps, 10 * scene.solver.max_steps);
  // A companion that takes 20 times the run's time is stalled, not tighter: at rtol/100 BDF of order
  // 1 to 5 needs 100^(1/5) to 100^(1/2) = 2.5 to 10 times the steps.
  tight.solver.wall_time_limit = std::max(limits.floor_s, limits.wall_factor * run.wall_seconds);
  e.rtol = tight.solver.rtol;
  e.atol = tight.solver.atol;
  e.tight_dir = run.out_dir / "error_estimate";
  auto not_estimated = [&](const std::string& why) {
    e.source = EstimateSource::None;
    e.not_estimated = why;
    judge(e, scene);
    return e;
  };
  if (run.run.status != RunStatus::Success)
    return not_estimated(fmt::format("the run did not reach the end ({})", to_string(run.run.status)));
  if (scene.output.record == RecordMode::None)
    return not_estimated("--record none leaves no output grid to compare");
  if (tight.solver.rtol == scene.solver.rtol && tight.solver.atol == scene.solver.atol)
    return not_estimated("the tolerances are at the tightest the settings table allows: no tighter companion");
  if (g_interrupt_requested.load()) return not_estimated("interrupted before the companion run");

  auto run_companion = [&](const Scene& companion, SolveOutcome& t) -> std::string {
    try {
      t = solve_scene(companion, e.tight_dir);
    } catch (const std::runtime_error& x) {
      return fmt::format("could not run: {}", x.what());
    }
    e.companion_wall_s = (std::isfinite(e.companion_wall_s) ? e.companion_wall_s : 0.0) + t.wall_seconds;
    e.tight_status = status_text(t);
    return t.run.status == RunStatus::Success ? "" : "did not finish: " + e.tight_status;
  };
  SolveOutcome t;
  std::string failed = run_companion(tight, t);
  // The run's own combination can fail at rtol/100 where a better-posed one
  // does not (index3 at rtol 1e-11 fails its first Newton iterations on the
  // slider mechanism): the same motion in quaternion/euler/ggl on IDA, the
  // reference formulation, is as good a companion. At a singular pose ggl's
  // Newton iteration can fail too (and ARKODE's steps collapse): then the
  // other stand-ins, which pass the poses (a companion that changes branch
  // there says so by its own branch check, and the arbiter below takes
  // over). Not after a signal.
  const std::string first = failed;
  for (const StandIn& stand_in : kStandIns) {
    if (failed.empty() || t.run.status == RunStatus::Interrupted || g_interrupt_requested.load()) break;
    if (runs_as(tight, stand_in)) continue;  // the run's own combination
    std::error_code ec;
    std::filesystem::remove_all(e.tight_dir, ec);
    const std::string combination = combination_name(stand_in);
    const std::string why = run_companion(as_stand_in(tight, stand_in), t);
    e.companion_combination = combination;
    e.companion_note = fmt::format("the run's own combination at rtol {:g}, atol {:g} {}", e.rtol, e.atol, first);
    failed = why.empty() ? "" : failed + "; so did " + combination + ", which " + why;
  }
  if (!failed.empty())
    return not_estimated(fmt::format("the companion run at rtol {:g}, atol {:g} {}", e.rtol, e.atol, failed));
  auto passed_singular_pose = [](const SolveOutcome& o) {
    return std::any_of(o.warnings.begin(), o.warnings.end(),
                       [](const AccuracyWarning& w) {
                         return w.quantity == "singular_pose" || w.quantity == "branch_switch";
                       });
  };
  e.singular_pose_passed = passed_singular_pose(run) || passed_singular_pose(t);
  try {
    compare_bodies(scene, read_trajectory_csv(run.out_dir / "trajectory.csv"),
                   read_trajectory_csv(e.tight_dir / "trajectory.csv"), e);
  } catch (const std::runtime_error& x) {
    return not_estimated(fmt::format("the companion's output grid cannot be compared: {}", x.what()));
  }
  e.source = EstimateSource::Companion;
  judge(e, scene);
  if (e.singular_pose_passed && !e.warnings.empty() && !g_interrupt_requested.load()) {
    arbitrate(scene, run, tight, e);
    judge(e, scene);
  }
  return e;
}

namespace {

// e from the run's grid against the closed form: a mechanism's (positions and
// orientations, as a companion's) or one body's orientation; judged.
void against_closed_form(const Scene& scene, const BodyGrid& run_grid, const ReferenceTrajectory& exact,
                         ErrorEstimate& e) {
  e.source = EstimateSource::ClosedForm;
  e.not_estimated.clear();
  try {
    if (exact.grid.layout == GridLayout::Bodies)
      compare_bodies(scene, run_grid, exact.grid, e);
    else
      e.orientation = compare_orientations(run_grid, exact.grid);
  } catch (const std::runtime_error& x) {
    e = ErrorEstimate{};
    e.not_estimated = fmt::format("the output grid cannot be compared with the closed form: {}", x.what());
  }
  judge(e, scene);
}

}  // namespace

ErrorEstimate closed_form_verdict(const Scene& scene, const BodyGrid& run_grid) {
  ErrorEstimate e;
  std::string why;
  const std::optional<ReferenceTrajectory> exact = exact_reference(scene, &why);
  if (!exact) {
    e.not_estimated = why;
    judge(e, scene);
    return e;
  }
  against_closed_form(scene, run_grid, *exact, e);
  return e;
}

ErrorEstimate accuracy_verdict(const Scene& scene, const SolveOutcome& run, bool companion,
                               const std::string& how_to_enable) {
  ErrorEstimate none;
  if (run.run.status != RunStatus::Success)
    none.not_estimated = fmt::format("the run did not reach the end ({})", to_string(run.run.status));
  else if (scene.output.record == RecordMode::None)
    none.not_estimated = "--record none leaves no output grid to compare";
  if (!none.not_estimated.empty()) {
    judge(none, scene);
    return none;
  }
  if (const std::optional<ReferenceTrajectory> exact = exact_reference(scene, nullptr)) {
    ErrorEstimate e;
    if (companion) {
      e = estimate_global_error(scene, run);
      if (e.estimated()) e.companion_orientation = e.orientation;
    }
    against_closed_form(scene, read_trajectory_csv(run.out_dir / "trajectory.csv"), *exact, e);
    return e;
  }
  if (companion) return estimate_global_error(scene, run);
  ErrorEstimate e;
  e.not_estimated = fmt::format("the scene has no closed form and no companion run was made ({} runs one at rtol/100)",
                                how_to_enable);
  judge(e, scene);
  return e;
}

OrientationError error_against(const SolveOutcome& run, const ReferenceTrajectory& reference) {
  return compare_orientations(read_trajectory_csv(run.out_dir / "trajectory.csv"), reference.grid);
}

void add_closed_form_error_to_summary(const std::filesystem::path& summary, const OrientationError& e) {
  std::ifstream in(summary);
  nlohmann::json j = nlohmann::json::parse(in);
  nlohmann::json x = error_json(e);
  x["definition"] = "rotation angle of R_exact^T R on the output grid (reference.csv holds the closed form there)";
  j["closed_form_error"] = x;
  write_file_atomically(summary, j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
}

nlohmann::json error_estimate_json(const ErrorEstimate& e) {
  nlohmann::json x = {
      {"status", e.estimated() ? "estimated" : "not estimated"},
      {"source", to_string(e.source)},
      {"not_estimated", e.not_estimated},
      {"method",
       "closed form: rotation angle of R_exact^T R on the output grid; companion: the same scene and combination at "
       "rtol/100 and atol/100 on the same grid, the rotation angle between the two runs (worst body) and, for a "
       "mechanism, the centre-of-mass distance over the mechanism's size L (worst body); maxima over the grid"},
      {"orientation", error_json(e.orientation)},
      {"position_rel_max", number_or_null(e.position_rel_max)},
      {"position_rel_final", number_or_null(e.position_rel_final)},
      {"length_scale_m", number_or_null(e.length_scale_m)},
      {"tolerance", e.tolerance},
      {"limit", e.limit},
      {"limit_rule", "300 x max(rtol, atol)"},
      {"branch_disagreement", e.branch_disagreement},
      {"singular_pose_passed", e.singular_pose_passed},
      {"arbiter",
       e.arbiter.empty() ? nlohmann::json(nullptr)
                         : nlohmann::json{{"verdict", e.arbiter}, {"combination", e.arbiter_combination}}},
      {"companion",
       {{"rtol", e.rtol},
        {"atol", e.atol},
        {"status", e.tight_status.empty() ? nlohmann::json(nullptr) : nlohmann::json(e.tight_status)},
        {"combination", e.companion_combination.empty() ? "the run's" : e.companion_combination},
        {"note", e.companion_note},
        {"wall_time_s", number_or_null(e.companion_wall_s)},
        {"run", e.tight_dir.empty() ? nlohmann::json(nullptr) : nlohmann::json(e.tight_dir.string())}}},
      {"companion_orientation", e.companion_orientation ? error_json(*e.companion_orientation) : nlohmann::json(nullptr)},
  };
  return x;
}

std::string with_error_estimate(const std::string& summary_text, const ErrorEstimate& e) {
  nlohmann::json j = nlohmann::json::parse(summary_text);
  j["error_estimate"] = error_estimate_json(e);
  nlohmann::json& w = j["warnings"];
  if (!w.is_array()) w = nlohmann::json::array();
  for (const nlohmann::json& x : warnings_json(e.warnings)) w.push_back(x);
  return j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

void add_error_estimate_to_summary(const std::filesystem::path& summary, const ErrorEstimate& e) {
  std::ifstream in(summary);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  write_file_atomically(summary, with_error_estimate(text, e));
}

std::string describe(const ErrorEstimate& e) {
  if (!e.estimated()) return "accuracy not estimated: " + e.not_estimated;
  std::string s = fmt::format("orientation error {:.2e} rad", e.orientation.max);
  if (std::isfinite(e.position_rel_max))
    s += fmt::format(", position error {:.2e} of L = {:.3g} m", e.position_rel_max, e.length_scale_m);
  s += e.source == EstimateSource::ClosedForm ? std::string(" against the closed form")
                                              : fmt::format(" estimated by a companion at rtol {:g}", e.rtol);
  s += fmt::format(" (max over the grid): {} the limit {:.2e} = 300 x max(rtol, atol)",
                   e.warnings.empty() ? "within" : "PAST", e.limit);
  if (std::isfinite(e.companion_wall_s) && e.source == EstimateSource::Companion)
    s += fmt::format("; companion {:.3f} s wall", e.companion_wall_s);
  return s;
}

}  // namespace rigidae
