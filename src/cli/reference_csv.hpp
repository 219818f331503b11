#pragma once
// The reference trajectory of a compare (or of a solve whose scene has a
// closed form) on the output grid, kept as DIR/reference.csv so that the
// error against time of every run can be drawn (tools/plot_compare.py,
// tools/plot_solve.py) without recomputing the closed form in Python.
#include <filesystem>

#include "rigidae/app/reference.hpp"

namespace rigidae::cli {

// Writes `ref`'s grid (with a units line, like trajectory.csv) to `path`,
// whole under a temporary name, in the layout of the runs it is compared
// with (record/trajectory_csv.hpp, grid_csv_text): t, qw..qz, omega_x..z for
// one body; t and per body BODY.qw..qz, BODY.wx..wz (space frame),
// BODY.x..z for a mechanism. Nothing is written when the reference is not
// usable (!ref.ok). Throws OutputError on a failed write.
void write_reference_csv(const ReferenceTrajectory& ref, const std::filesystem::path& path);

}  // namespace rigidae::cli
