#pragma once
// A multibody run's trajectory.csv read back on its output grid: each body's
// orientation, centre-of-mass position and angular velocity (space frame),
// by the columns BODY.qw .. qz, BODY.x .. z, BODY.wx .. wz that
// the mechanism columns write (multibody/multibody_problem.hpp, output_names).
#include <filesystem>
#include <string>
#include <vector>

#include "rigidae/core/types.hpp"

namespace rigidae {

struct BodyGrid {
  std::vector<std::string> bodies;          // in column order
  std::vector<double> t;                    // s
  std::vector<std::vector<Vec4>> q_WB;      // [grid point][body], unit quaternion, scalar first
  std::vector<std::vector<Vec3>> x_W;       // [grid point][body], m
  std::vector<std::vector<Vec3>> omega_W;   // [grid point][body], rad/s, space components
  bool empty() const { return bodies.empty(); }
};

// Throws InputError naming the file when it is missing or holds no BODY.qw column.
BodyGrid read_body_grid(const std::filesystem::path& csv);

// Largest rotation angle (rad) between the two grids' body orientations, over
// the grid points and bodies both have; NaN when they share none.
double max_body_angle(const BodyGrid& a, const BodyGrid& b);

}  // namespace rigidae
