#include "rigidae/io/checked_file.hpp"
#include "rigidae/app/reference.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "rigidae/app/compare.hpp"
#include "rigidae/app/solve.hpp"
#include "rigidae/core/error.hpp"
#include "rigidae/exact/exact_solution.hpp"
#include "rigidae/record/trajectory_csv.hpp"
#include "rigidae/so3/rotation.hpp"

namespace rigidae {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr const char* kSummary = "reference.json";

// Largest angle between two grid orientations over the points both have.
double max_angle(const std::vector<Vec4>& a, const std::vector<Vec4>& b) {
  const std::size_t n = std::min(a.size(), b.size());
  double m = 0.0;
  for (std::size_t i = 0; i < n; ++i) m = std::max(m, so3::quaternion_distance(a[i], b[i]));
  return n > 0 ? m : kNaN;
}

void fill_from_run(ReferenceTrajectory& ref, const std::filesystem::path& dir) {
  if (ref.multibody) {
    ref.bodies = read_body_grid(dir / "reference" / "trajectory.csv");
    ref.t = ref.bodies.t;
    return;
  }
  GridTrajectory g = read_trajectory_csv(dir / "reference" / "trajectory.csv");
  ref.t = std::move(g.t);
  ref.q_WB = std::move(g.q_WB);
  ref.omega_B = std::move(g.omega_B);
}

}  // namespace

std::string to_string(ReferenceKind k) {
  switch (k) {
    case ReferenceKind::Exact: return "exact";
    case ReferenceKind::Tight: return "tight";
    default: return "auto";
  }
}

std::string ReferenceTrajectory::describe() const {
  if (!ok) return fmt::format("none ({})", message);
  if (exact) return fmt::format("{}, the closed-form solution (estimated accuracy {:.1e} rad)", combination, accuracy_rad);
  return fmt::format("{} at rtol {:g}; its accuracy, estimated as the largest angle to {} at the same rtol over the "
                     "output grid: {:.1e} rad",
                     combination, rtol, check_combination, accuracy_rad);
}

std::optional<ReferenceTrajectory> exact_reference(const Scene& scene, std::string* why) {
  if (scene.multibody) {
    if (why) *why = "a scene with bodies and joints (schema_version = 2) has no closed form in rigidae";
    return std::nullopt;
  }
  const std::unique_ptr<exact::ExactSolution> closed_form = exact::find_exact_solution(scene, why);
  if (!closed_form) return std::nullopt;
  ReferenceTrajectory ref;
  ref.exact = ref.ok = true;
  ref.combination = "exact: " + closed_form->name();
  ref.accuracy_rad = closed_form->accuracy();
  const OutputGrid grid(scene.time);
  for (std::size_t k = 0; k < grid.size(); ++k) {
    const exact::RotationState s = closed_form->at(grid[k]);
    ref.t.push_back(grid[k]);
    ref.q_WB.push_back(so3::matrix_to_quaternion(s.R_WB));
    ref.omega_B.push_back(s.omega_B);
  }
  return ref;
}

double default_reference_rtol(double rtol) { return std::clamp(rtol / 100.0, 1e-13, 1e-12); }

ReferenceTrajectory make_reference(const Scene& scene, const std::string& kind, double tight_rtol,
                                   const std::filesystem::path& dir,
                                   const std::function<void(const std::string&)>& progress) {
  auto say = [&](const std::string& s) {
    if (progress) progress(s);
  };
  if (kind != "auto" && kind != "exact" && kind != "tight")
    throw InputError(fmt::format("unknown reference '{}'; valid values: auto, exact, tight", kind));
  if (kind != "tight") {
    std::string why_not_exact;
    std::optional<ReferenceTrajectory> closed_form = exact_reference(scene, &why_not_exact);
    if (closed_form) {
      say(fmt::format("reference: {} (accuracy {:.1e} rad)", closed_form->combination, closed_form->accuracy_rad));
      return *closed_form;
    }
    if (kind == "exact")
      throw InputError(fmt::format("{}: no exact solution for this scene: {}", scene.source, why_not_exact));
  }
  ReferenceTrajectory ref;
  ref.rtol = tight_rtol;
  ref.multibody = scene.multibody.has_value();
  const Combination ref_combo{Coordinates::Quaternion, Equations::Euler, "ggl"};
  // A multibody scene's Euler-angle bodies still carry the joints: the check
  // takes linear coordinates (no chart switches to add their own error).
  const Combination check_combo = ref.multibody ? Combination{Coordinates::Linear, Equations::Euler, "ggl"}
                                                : Combination{Coordinates::EulerAngles, Equations::Euler, "any"};
  ref.combination = ref_combo.name();
  ref.check_combination = check_combo.name();
  auto tight = [&](const Combination& c) {
    Scene s = c.applied_to(scene);
    s.solver.rtol = s.solver.atol = ref.rtol;
    s.solver.integrator = "ida";
    return s;
  };
  const SolveOutcome a = solve_scene(tight(ref_combo), dir / "reference");
  say(fmt::format("reference {} at rtol {:g}: {} in {:.2f} s", ref.combination, ref.rtol, to_string(a.run.status),
                  a.wall_seconds));
  const SolveOutcome b = solve_scene(tight(check_combo), dir / "reference-check");
  say(fmt::format("cross-check {} at rtol {:g}: {} in {:.2f} s", ref.check_combination, ref.rtol,
                  to_string(b.run.status), b.wall_seconds));
  ref.ok = a.run.status == RunStatus::Success && b.run.status == RunStatus::Success;
  if (a.run.status != RunStatus::Success) ref.message = "reference run failed: " + a.run.message;
  else if (b.run.status != RunStatus::Success) ref.message = "cross-check run failed: " + b.run.message;
  ref.accuracy_rad = kNaN;
  if (ref.ok) {
    fill_from_run(ref, dir);
    if (ref.multibody)
      ref.accuracy_rad = max_body_angle(read_body_grid(dir / "reference-check" / "trajectory.csv"), ref.bodies);
    else
      ref.accuracy_rad = max_angle(read_trajectory_csv(dir / "reference-check" / "trajectory.csv").q_WB, ref.q_WB);
  }
  nlohmann::json j{{"ok", ref.ok},
                   {"message", ref.message},
                   {"combination", ref.combination},
                   {"check_combination", ref.check_combination},
                   {"rtol", ref.rtol},
                   {"multibody", ref.multibody},
                   {"accuracy_rad", ref.accuracy_rad}};
  write_file_atomically(dir / kSummary, j.dump(2) + "\n");
  return ref;
}

std::optional<ReferenceTrajectory> read_reference(const std::filesystem::path& dir) {
  std::ifstream in(dir / kSummary);
  if (!in) return std::nullopt;
  nlohmann::json j;
  try {
    in >> j;
  } catch (const nlohmann::json::exception& e) {
    throw InputError(fmt::format("{}: not a reference summary: {}", (dir / kSummary).string(), e.what()));
  }
  ReferenceTrajectory ref;
  ref.ok = j.value("ok", false);
  if (!ref.ok) return std::nullopt;
  ref.message = j.value("message", "");
  ref.combination = j.value("combination", "");
  ref.check_combination = j.value("check_combination", "");
  ref.rtol = j.value("rtol", 0.0);
  ref.multibody = j.value("multibody", false);
  ref.accuracy_rad = j["accuracy_rad"].is_number() ? j["accuracy_rad"].get<double>() : kNaN;
  fill_from_run(ref, dir);
  return ref;
}

}  // namespace rigidae
