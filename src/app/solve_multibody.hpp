#pragma once
// solve_scene for schema-2 (multibody) scenes (internal header).
#include "rigidae/app/solve.hpp"

namespace rigidae {

SolveOutcome solve_multibody_scene(const Scene& scene, const std::filesystem::path& out_dir);

}  // namespace rigidae
