// The global-error estimate of solve --error-estimate: see
// include/rigidae/app/error_estimate.hpp.
#include "rigidae/app/error_estimate.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <tuple>
#include <vector>

#include "rigidae/app/reference.hpp"
#include "rigidae/core/error.hpp"
#include "rigidae/io/checked_file.hpp"
#include "rigidae/settings/settings.hpp"
#include "rigidae/so3/rotation.hpp"

namespace rigidae {

namespace {

// The orientations of a trajectory.csv: one quaternion per body (columns qw..qz
// of one body, BODY.qw..BODY.qz of each body of a multibody run) per row.
struct Orientations {
  std::vector<double> t;
  std::vector<std::vector<Vec4>> q;  // [row][body]
};

Orientations read_orientations(const std::filesystem::path& csv) {
  std::ifstream in(csv);
  if (!in) throw InputError(fmt::format("{}: cannot read", csv.string()));
  std::string line;
  std::getline(in, line);  // units
  if (!std::getline(in, line)) throw InputError(fmt::format("{}: no header line", csv.string()));
  std::vector<std::string> header;
  {
    std::stringstream cells(line);
    std::string cell;
    while (std::getline(cells, cell, ',')) header.push_back(cell);
  }
  std::vector<std::size_t> qw;  // the column of each body's qw
  for (std::size_t k = 0; k + 3 < header.size(); ++k) {
    const std::string& h = header[k];
    if (h == "qw" || (h.size() > 3 && h.compare(h.size() - 3, 3, ".qw") == 0)) qw.push_back(k);
  }
  if (header.empty() || header[0] != "t" || qw.empty())
    throw InputError(fmt::format("{}: not a trajectory (no t and qw columns)", csv.string()));
  Orientations o;
  std::vector<double> row;
  while (std::getline(in, line)) {
    row.clear();
    const char* p = line.c_str();
    char* end = nullptr;
    while (*p) {
      row.push_back(std::strtod(p, &end));
      p = *end == ',' ? end + 1 : end;
      if (*end != ',') break;
    }
    if (row.size() < header.size()) break;  // a row cut short: the rows before it stand
    o.t.push_back(row[0]);
    std::vector<Vec4> qs;
    for (std::size_t c : qw) qs.emplace_back(row[c], row[c + 1], row[c + 2], row[c + 3]);
    o.q.push_back(std::move(qs));
  }
  return o;
}

// Angles between two runs' orientations on the common output grid: the
// largest over bodies, then the last point and the largest over points.
OrientationError compare(const Orientations& a, const std::vector<double>& t_b,
                         const std::vector<std::vector<Vec4>>& q_b) {
  OrientationError e;
  const std::size_t n = std::min(a.t.size(), t_b.size());
  if (n == 0) return e;
  e.max = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    if (std::abs(a.t[i] - t_b[i]) > 1e-9 * (1.0 + std::abs(t_b[i])))
      throw InputError(fmt::format("output grids differ at point {}: t = {} s and {} s", i, a.t[i], t_b[i]));
    double worst = 0.0;
    for (std::size_t b = 0; b < std::min(a.q[i].size(), q_b[i].size()); ++b)
      worst = std::max(worst, so3::quaternion_distance(a.q[i][b], q_b[i][b]));
    e.max = std::max(e.max, worst);
    e.final = worst;
    e.t_final = a.t[i];
  }
  return e;
}

nlohmann::json number_or_null(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); }

nlohmann::json error_json(const OrientationError& e) {
  return {{"final_orientation_rad", number_or_null(e.final)},
          {"max_orientation_rad", number_or_null(e.max)},
          {"t_final", number_or_null(e.t_final)}};
}

}  // namespace

std::pair<double, double> tight_tolerances(const SolverSettings& run) {
  const double rtol_min = settings::scene_setting("solver.rtol").min->value;
  const double atol_min = settings::scene_setting("solver.atol").min->value;
  return {std::max(run.rtol / 100.0, rtol_min), std::max(run.atol / 100.0, atol_min)};
}

ErrorEstimate estimate_global_error(const Scene& scene, const SolveOutcome& run) {
  ErrorEstimate e;
  Scene tight = scene;
  std::tie(tight.solver.rtol, tight.solver.atol) = tight_tolerances(scene.solver);
  tight.output.record = RecordMode::Grid;
  // Ten times the steps a run at 1/100 of the tolerance takes at order 2; no fewer than the run allowed.
  tight.solver.max_steps = std::max(scene.solver.max_steps, 10 * scene.solver.max_steps);
  e.rtol = tight.solver.rtol;
  e.atol = tight.solver.atol;
  e.tight_dir = run.out_dir / "error_estimate";
  const Orientations mine = read_orientations(run.out_dir / "trajectory.csv");

  const SolveOutcome t = solve_scene(tight, e.tight_dir);
  e.tight_status = t.run.status == RunStatus::Success ? "success" : to_string(t.run.status) + ": " + t.run.message;
  if (t.run.status == RunStatus::Success) {
    const Orientations tight_grid = read_orientations(e.tight_dir / "trajectory.csv");
    e.estimate = compare(mine, tight_grid.t, tight_grid.q);
  }

  if (!scene.multibody) {
    std::string why;
    if (const std::optional<ReferenceTrajectory> exact = exact_reference(scene, &why))
      e.closed_form = error_against(run, *exact);
  }
  return e;
}

OrientationError error_against(const SolveOutcome& run, const ReferenceTrajectory& reference) {
  const Orientations mine = read_orientations(run.out_dir / "trajectory.csv");
  std::vector<std::vector<Vec4>> q;
  q.reserve(reference.q_WB.size());
  for (const Vec4& x : reference.q_WB) q.push_back({x});
  return compare(mine, reference.t, q);
}

void add_closed_form_error_to_summary(const std::filesystem::path& summary, const OrientationError& e) {
  std::ifstream in(summary);
  nlohmann::json j = nlohmann::json::parse(in);
  nlohmann::json x = error_json(e);
  x["definition"] = "rotation angle of R_exact^T R on the output grid (reference.csv holds the closed form there)";
  j["closed_form_error"] = x;
  write_file_atomically(summary, j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
}

void add_error_estimate_to_summary(const std::filesystem::path& summary, const ErrorEstimate& e) {
  std::ifstream in(summary);
  nlohmann::json j = nlohmann::json::parse(in);
  nlohmann::json x = {
      {"method", "the same scene at tighter tolerances; orientation angle to it on the output grid, the largest "
                 "over bodies"},
      {"tight_rtol", e.rtol},
      {"tight_atol", e.atol},
      {"tight_status", e.tight_status},
      {"tight_run", e.tight_dir.string()},
      {"estimate", error_json(e.estimate)},
      {"closed_form", e.closed_form ? error_json(*e.closed_form) : nlohmann::json(nullptr)},
  };
  j["error_estimate"] = x;
  write_file_atomically(summary, j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
}

}  // namespace rigidae
