#pragma once
// One scene in every applicable coordinates x equations x scheme combination,
// side by side against one reference.
//
// Folder layout (out):
//   compare.csv, compare.txt, compare.md   the table
//   reference/, reference-check/          the reference and its cross-check
//   COORDINATES-EQUATIONS-SCHEME/         each combination's run folder, as `solve` writes it
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "rigidae/app/accuracy.hpp"
#include "rigidae/app/reference.hpp"
#include "rigidae/app/solve.hpp"
#include "rigidae/model/scene.hpp"

namespace rigidae {

// Coordinates without constraints (Euler angles) give every scheme the same
// ODE: they appear once per equation form, with scheme "any".
struct Combination {
  Coordinates coordinates = Coordinates::Quaternion;
  Equations equations = Equations::Euler;
  std::string scheme;  // registry name, or "any"

  std::string name() const;    // "quaternion/euler/ggl"
  std::string folder() const;  // "quaternion-euler-ggl"
  Scene applied_to(const Scene& scene) const;
};

// Every applicable combination: the registry's coordinates, then equations,
// then schemes, each in registry order.
std::vector<Combination> all_combinations();

// A pattern with '/' is a glob over the whole name ("quaternion/*/ggl");
// one without matches any single part ("ggl", "linear", "index*").
bool matches(const Combination& c, const std::string& pattern);

struct CompareOptions {
  int repeat = 3;                     // wall time: median of this many runs
  std::vector<std::string> only, skip;
  std::filesystem::path out;
  std::optional<double> reference_rtol;  // default: default_reference_rtol(rtol)
  // "auto", "exact" or "tight" (see make_reference); empty: the scene's choice.
  std::string reference;
  // Keep each run's steps.csv (and the reference's); by default only the
  // summaries and output grids stay (a full compare wrote 152 MB of steps).
  bool keep_steps = false;
};

struct CompareRow {
  Combination combination;
  SolveOutcome outcome;           // of the first run
  std::vector<double> wall_seconds;  // one per repeat
  double wall_median = 0.0;
  double error_final_rad = 0.0;   // NaN when the run did not reach the end or there is no reference
  double error_max_rad = 0.0;     // over the output grid points the run reached
  RunAccuracy accuracy;           // every error group
  double lambda_min = 0.0, lambda_max = 0.0;  // J, NaN without force multipliers
  double mu_abs_max = 0.0;                    // 1/s, NaN without kinematic multipliers
};

struct CompareReport {
  std::string scene_name, scene_source;
  double rtol = 0.0, atol = 0.0;
  ReferenceTrajectory reference;
  std::vector<CompareRow> rows;
};

// Runs everything; one combination's failure is a row, not an exception.
// progress receives one line per finished run (may be empty).
CompareReport compare_scene(const Scene& scene, const CompareOptions& opt,
                            const std::function<void(const std::string&)>& progress);

// The fixed-width table `rigidae compare` prints.
std::string format_compare_table(const CompareReport& r);
// compare.csv, compare.txt and compare.md into opt.out.
void write_compare_outputs(const CompareReport& r, const std::filesystem::path& out);

}  // namespace rigidae
