#pragma once
// solve_scene for schema-2 (multibody) scenes (internal header).
#include "rigidae/app/solve.hpp"

namespace rigidae {

SolveOutcome solve_multibody_scene(const Scene& scene, const std::filesystem::path& out_dir);

// The integrator a multibody scene may name: ida only (MultibodyProblem is a
// DAE; its ODE form is not built). InputError naming the file otherwise.
void check_multibody_integrator(const Scene& scene);

}  // namespace rigidae
