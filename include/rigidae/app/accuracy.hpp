#pragma once
// How far a run's output grid is from the reference, by group: orientation
// (rad), angular velocity (rad/s) and multipliers (force lambda, kinematic mu)
// kept separate, each as the error at the end, its root mean square over the
// grid and its maximum; plus significant correct digits at the end.
#include <filesystem>
#include <limits>

#include "rigidae/app/body_grid.hpp"

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

// A multibody scene (schema 2) fills the same groups, each the largest over
// the bodies at a grid point: orientation_rad the largest rotation angle of
// R_ref^T R, angular_velocity the largest |omega_W - omega_W,ref| (space
// frame), position_m the largest centre-of-mass distance |x - x_ref|; lambda
// and mu stay NaN (joint reactions are not compared); scd and mescd are taken
// over every body's final (q_WB aligned in sign, x_W, omega_W).
struct RunAccuracy {
  ErrorStats orientation_rad;   // angle of R_ref^T R
  ErrorStats angular_velocity;  // |omega_B - omega_B,ref|, rad/s
  ErrorStats position_m;        // multibody only: max over bodies |x_W - x_W,ref|, m
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
// The multipliers' reference values are those the run's own DAE takes at
// the reference state (its consistent start there). `reached_end`: the run
// finished; otherwise the final errors stay NaN. scd and mescd are taken
// over the final physical state (q_WB aligned in sign with the reference,
// then omega_B).
RunAccuracy measure_accuracy(const Scene& scene, const GridTrajectory& run, const ReferenceTrajectory& ref,
                             bool reached_end);
// The same for a multibody run (the reference's `bodies` grid).
RunAccuracy measure_multibody_accuracy(const Scene& scene, const BodyGrid& run, const ReferenceTrajectory& ref,
                                       bool reached_end);
// Either, reading the run's trajectory.csv in run_dir.
RunAccuracy measure_run_accuracy(const Scene& scene, const std::filesystem::path& run_dir,
                                 const ReferenceTrajectory& ref, bool reached_end);

}  // namespace rigidae
