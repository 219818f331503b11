#pragma once
// A one-body scene (schema 1) as a system of one body (model/multibody_spec.hpp),
// the form in which the multibody model (multibody/) integrates it.
//
// A top on a fixed point ([support] type = "fixed_point") is a body pivoted
// at the space origin with its centre of mass at R0 c (c = [body]
// center_of_mass, from the fixed point); a free body is a body pivoted at its
// centre of mass (c = 0): its rotation is torque free and its centre of
// mass's ballistic motion is not integrated, as in the one-body model
// (model/rigid_body.hpp). Either way the unknowns are the rotation
// coordinates and velocities only, and the rotation block is the one the
// one-body model builds (inertia about the reference point, gravity torque).
#include "rigidae/model/scene.hpp"

namespace rigidae {

// The scene with `multibody` set to that one body (named "body"); the rest
// (formulation, solver, time, output) kept. `s` must be a one-body scene.
Scene one_body_system(const Scene& s);

// Any scene as the system the multibody model runs: itself when it has
// bodies and joints (schema 2, URDF), else one_body_system(s).
Scene as_system(const Scene& s);

}  // namespace rigidae
