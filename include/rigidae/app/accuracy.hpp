#pragma once
// How far a run's output grid is from the reference, by group: orientation
// (rad), angular velocity (rad/s) and multipliers (force lambda, kinematic mu)
// kept separate, each as the error at the end, its root mean square over the
// grid and its maximum; plus significant correct digits at the end.
#include <filesystem>
#include <limits>

#include "rigidae/app/reference.hpp"
#include "rigidae/core/types.hpp"
#include "rigidae/model/scene.hpp"
#include "rigidae/record/trajectory_csv.hpp"

namespace rigidae {

struct ErrorStats {
  double final = std::numeric_limits<double>::quiet_NaN();  // at the end time; NaN if the run stopped short
  double l2 = std::numeric_limits<double>::quiet_NaN();     // sqrt(mean of squares) over the grid points reached
  double max = std::numeric_limits<double>::quiet_NaN();    // over the grid points reached
};

// Every scene is measured the same way, body by body on the output grid
// (record/trajectory_csv.hpp's BodyGrid; a one-body scene is one body),
// each group the largest over the bodies at a grid point: orientation_rad
// the rotation angle of R_ref^T R, angular_velocity |omega_B - omega_B,ref|
// (body frame), position_m the centre-of-mass distance |x - x_ref| where
// the files record positions (a mechanism's; a one-body scene turns about a
// fixed point); lambda and mu where the run's file names its multipliers
// lambda_*, mu_* (the one-body column set: a mechanism's joint reactions are
// not compared); scd and mescd over every body's final (q_WB aligned in
// sign, x_W where recorded, omega_B).
struct RunAccuracy {
  ErrorStats orientation_rad;   // angle of R_ref^T R
  ErrorStats angular_velocity;  // |omega_B - omega_B,ref|, rad/s
  ErrorStats position_m;        // max over bodies |x_W - x_W,ref|, m; NaN where no position is recorded
  ErrorStats lambda;            // max_i |lambda_i - lambda_i,ref|, J; NaN without force multipliers
  ErrorStats mu;                // max_i |mu_i|, 1/s (zero on the exact solution); NaN without them
  double scd = std::numeric_limits<double>::quiet_NaN();    // significant correct digits at the end
  double mescd = std::numeric_limits<double>::quiet_NaN();  // the mixed variant
  long points_compared = 0;
};

// Significant correct digits as the IVP Test Set defines them:
//   scd   = -log10 max_i |y_i - yref_i| / |yref_i|
//   mescd = -log10 max_i |y_i - yref_i| / (atol/rtol + |yref_i|)
// As in the Test Set's report code, components with |yref_i| < 1e-200 are
// left out of scd, and errors below the unit round-off count as it (so at
// most -log10(2^-53) = 15.95 digits).
double significant_correct_digits(const Eigen::VectorXd& y, const Eigen::VectorXd& y_ref);
double mixed_significant_correct_digits(const Eigen::VectorXd& y, const Eigen::VectorXd& y_ref, double atol_over_rtol);

// Errors of a run (scene = the formulation it ran) on the reference grid.
// The multipliers' reference values are those the run's own system takes
// at the reference state (its consistent start there). `reached_end`: the
// run finished; otherwise the final errors stay NaN.
RunAccuracy measure_accuracy(const Scene& scene, const BodyGrid& run, const ReferenceTrajectory& ref,
                             bool reached_end);
// The same, reading the run's trajectory.csv in run_dir.
RunAccuracy measure_run_accuracy(const Scene& scene, const std::filesystem::path& run_dir,
                                 const ReferenceTrajectory& ref, bool reached_end);

}  // namespace rigidae
