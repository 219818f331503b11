#pragma once
// The reference trajectory of a compare (or of a solve whose scene has a
// closed form) on the output grid, kept as DIR/reference.csv so that the
// error against time of every run can be drawn (tools/plot_compare.py,
// tools/plot_solve.py) without recomputing the closed form in Python.
#include <filesystem>

#include "rigidae/app/reference.hpp"

namespace rigidae::cli {

// Writes t, qw..qz, omega_x..z of `ref` (with a units line, like
// trajectory.csv) to `path`, whole under a temporary name; a multibody
// reference (schema 2) as t and per body BODY.qw..qz, BODY.wx..wz (space
// frame), BODY.x..z, the names of a multibody trajectory.csv. Nothing is
// written when the reference is not usable (!ref.ok). Throws OutputError on a
// failed write.
void write_reference_csv(const ReferenceTrajectory& ref, const std::filesystem::path& path);

}  // namespace rigidae::cli
