#pragma once
// What a run looks like: the shapes of its scene's bodies, its joints'
// points and the columns of trajectory.csv that place them, as JSON for the
// tools that draw a run (tools/view_run.py, vtk_run.py, animate_run.py).
#include <filesystem>
#include <string>
#include <vector>

#include "rigidae/model/scene.hpp"

namespace rigidae {

// The semi-axes (a, b, c) of the uniform solid ellipsoid of mass m with the
// principal moments J = (J1, J2, J3) about its centre:
//   J1 = m (b^2 + c^2) / 5, ...  =>  a^2 = 5 (J2 + J3 - J1) / (2 m), ...
// A flat body (J1 = J2 + J3) has a zero semi-axis; it is raised to
// `min_fraction` of the largest so that the shape can be seen.
Vec3 inertia_ellipsoid_semi_axes(double mass, const Vec3& principal_moments, double min_fraction = 0.05);

// The geometry of `scene` as JSON (its layout: docs/viewer.md, "Geometry").
std::string scene_geometry_json(const Scene& scene);

// The run folders below `dir`: dir itself when it holds summary.json (a
// solve), else its sub-folders that do, in name order (a compare's output).
std::vector<std::filesystem::path> run_folders(const std::filesystem::path& dir);

// The scene file a run was solved from (summary.json's configuration.scene,
// relative to the current folder as the run recorded it), or `override` when
// given. InputError naming the run when neither exists.
std::filesystem::path run_scene_file(const std::filesystem::path& run, const std::filesystem::path& override_path);

}  // namespace rigidae
