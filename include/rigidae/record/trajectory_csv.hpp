#pragma once
// Reading back a run's trajectory.csv (the output grid), as the recorder
// wrote it: orientation, angular velocity and multipliers by column name.
#include <filesystem>
#include <string>
#include <vector>

#include "rigidae/core/types.hpp"

namespace rigidae {

struct GridTrajectory {
  std::vector<double> t;
  std::vector<Vec4> q_WB;     // unit quaternion of R_WB, scalar first
  std::vector<Vec3> omega_B;  // rad/s, body components
  std::vector<std::string> multiplier_names;  // "lambda_*", "mu_*", in column order
  std::vector<std::vector<double>> multipliers;  // [grid point][multiplier]
};

// Throws InputError naming the file when it is missing or not a trajectory.
GridTrajectory read_trajectory_csv(const std::filesystem::path& csv);

}  // namespace rigidae
