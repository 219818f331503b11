#pragma once
// The reference a run's accuracy is measured against, on the scene's output
// grid, in the one layout of every run's grid (record/trajectory_csv.hpp):
// the closed-form solution when the scene has one (exact/), or a tight run
// of quaternion/euler/ggl cross-checked by a tight run of linear/euler/ggl
// (other coordinates, no chart); the accuracy estimate is the largest angle
// between the two over the grid and the bodies.
#include <filesystem>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "rigidae/core/types.hpp"
#include "rigidae/model/scene.hpp"
#include "rigidae/record/trajectory_csv.hpp"

namespace rigidae {

struct ReferenceTrajectory {
  bool ok = false;
  std::string message;  // why there is none, when !ok
  bool exact = false;   // a closed form, not a run
  std::string combination;        // "exact: NAME" or the tight run's combination
  std::string check_combination;  // the cross-check run's (tight only)
  double rtol = 0.0;              // of the tight runs
  double accuracy_rad = 0.0;      // estimated orientation accuracy over the grid
  double accuracy_m = std::numeric_limits<double>::quiet_NaN();  // position accuracy (a mechanism's closed form)
  BodyGrid grid;                  // on the scene's output grid

  // One line for reports.
  std::string describe() const;
};

// The closed-form reference on the scene's output grid, or nullopt with
// `why` filled when the scene has none.
std::optional<ReferenceTrajectory> exact_reference(const Scene& scene, std::string* why);

// The default tight rtol for a run tolerance: rtol / 100 in [1e-13, 1e-12].
double default_reference_rtol(double rtol);

// kind: "auto" (closed form if the scene has one, else tight), "exact" (the
// closed form, or an InputError saying why there is none), "tight".
// Tight runs go into dir/reference and dir/reference-check, and the result is
// summarised in dir/reference.json so that read_reference can reuse it.
ReferenceTrajectory make_reference(const Scene& scene, const std::string& kind, double tight_rtol,
                                   const std::filesystem::path& dir,
                                   const std::function<void(const std::string&)>& progress);

// A tight reference that make_reference wrote into dir earlier; nullopt when
// dir holds none, or only a failed one.
std::optional<ReferenceTrajectory> read_reference(const std::filesystem::path& dir);

// The kind a scene asks for ("auto", "exact" or "tight").
std::string to_string(ReferenceKind k);

}  // namespace rigidae
