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
#include "rigidae/exact/particle_pendulum.hpp"
#include "rigidae/record/trajectory_csv.hpp"
#include "rigidae/so3/rotation.hpp"

namespace rigidae {

namespace {

constexpr const char* kSummary = "reference.json";

void fill_from_run(ReferenceTrajectory& ref, const std::filesystem::path& dir) {
  ref.grid = read_trajectory_csv(dir / "reference" / "trajectory.csv");
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
  if (exact)
    return fmt::format("{}, the closed-form solution (estimated accuracy {:.1e} rad{})", combination, accuracy_rad,
                       std::isfinite(accuracy_m) ? fmt::format(", {:.1e} m", accuracy_m) : "");
  return fmt::format("{} at rtol {:g}; its accuracy, estimated as the largest angle to {} at the same rtol over the "
                     "output grid: {:.1e} rad",
                     combination, rtol, check_combination, accuracy_rad);
}

std::optional<ReferenceTrajectory> exact_reference(const Scene& scene, std::string* why) {
  // A mechanism's closed form: its bodies' positions (the simple pendulum's
  // particle); else one body's rotation (`why` says why neither).
  if (const std::optional<exact::ParticlePendulum> pendulum = exact::ParticlePendulum::of(scene, nullptr)) {
    ReferenceTrajectory ref;
    ref.exact = ref.ok = true;
    ref.combination = "exact: " + pendulum->name();
    ref.accuracy_rad = 0.0;  // a particle does not turn
    ref.accuracy_m = pendulum->accuracy();
    ref.grid.layout = GridLayout::Bodies;
    ref.grid.bodies = {pendulum->body()};
    const OutputGrid grid(scene.time);
    for (std::size_t k = 0; k < grid.size(); ++k)
      ref.grid.add_point(grid[k], {Vec4(1, 0, 0, 0)}, {pendulum->position(grid[k])}, {Vec3::Zero()});
    return ref;
  }
  const std::unique_ptr<exact::ExactSolution> closed_form = exact::find_exact_solution(scene, why);
  if (!closed_form) return std::nullopt;
  ReferenceTrajectory ref;
  ref.exact = ref.ok = true;
  ref.combination = "exact: " + closed_form->name();
  ref.accuracy_rad = closed_form->accuracy();
  // A closed form is one body's rotation: the one-body layout.
  ref.grid.layout = GridLayout::OneBody;
  ref.grid.bodies = {"body"};
  const OutputGrid grid(scene.time);
  for (std::size_t k = 0; k < grid.size(); ++k) {
    const exact::RotationState s = closed_form->at(grid[k]);
    ref.grid.add_point(grid[k], {so3::matrix_to_quaternion(s.R_WB)}, {}, {s.omega_B});
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
      const double m = closed_form->accuracy_m;
      say(fmt::format("reference: {} (accuracy {:.1e} rad{})", closed_form->combination, closed_form->accuracy_rad,
                      std::isfinite(m) ? fmt::format(", {:.1e} m", m) : ""));
      return *closed_form;
    }
    if (kind == "exact")
      throw InputError(fmt::format("{}: no exact solution for this scene: {}", scene.source, why_not_exact));
  }
  ReferenceTrajectory ref;
  ref.rtol = tight_rtol;
  const Combination ref_combo{Coordinates::Quaternion, Equations::Euler, "ggl", "ida", ""};
  // The check takes other coordinates with no chart (Euler angles' chart
  // switches would add their own error; a mechanism's Euler-angle bodies
  // still carry the joints' rows).
  const Combination check_combo{Coordinates::Linear, Equations::Euler, "ggl", "ida", ""};
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
    const BodyGrid check = read_trajectory_csv(dir / "reference-check" / "trajectory.csv");
    ref.accuracy_rad = max_body_angle(check, ref.grid);
    ref.accuracy_m = max_body_distance(check, ref.grid);  // NaN without positions (a single body)
  }
  nlohmann::json j{{"ok", ref.ok},
                   {"message", ref.message},
                   {"combination", ref.combination},
                   {"check_combination", ref.check_combination},
                   {"rtol", ref.rtol},
                   {"accuracy_rad", ref.accuracy_rad},
                   {"accuracy_m", std::isfinite(ref.accuracy_m) ? nlohmann::json(ref.accuracy_m) : nlohmann::json()}};
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
  ref.accuracy_rad = j["accuracy_rad"].is_number() ? j["accuracy_rad"].get<double>() : kNaN;
  ref.accuracy_m = j.contains("accuracy_m") && j["accuracy_m"].is_number() ? j["accuracy_m"].get<double>() : kNaN;
  fill_from_run(ref, dir);
  return ref;
}

}  // namespace rigidae
