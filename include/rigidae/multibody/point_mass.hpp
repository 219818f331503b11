#pragma once
// A point mass (particle, [[bodies]] kind = "particle"): mass and position
// only. Its unknowns are x (3) and x' (3); it has no rotation coordinates
// (nqr = nvr = 0), no inertia and no orientation: R = I for ever. The
// assembler treats it as a body whose rotation block is empty, so every path
// (residual, exact matrix, start, rank, ODE form, reports) is the rigid
// body's with zero-sized rotation parts:
//   kinematics  x' - x_v = 0
//   dynamics    m x_v' - f_x (+ G_x^T lambda) = 0
// A body vector on a particle is p = x + s (s = 0: joints hold it at its
// position, the loader checks) or a constant direction s; the Lagrange-form
// branch of body_vector.cpp (which loops over nqr = 0 rotation coordinates)
// evaluates both exactly, in either equation form.
#include <memory>

#include "rigidae/coords/representation.hpp"
#include "rigidae/multibody/rotation_map.hpp"

namespace rigidae::multibody {

// The empty rotation block: nq = nv = nc = 0, orientation the identity.
std::unique_ptr<Representation> make_point_mass_rotation();
// The constant placement R = I with no coordinates (all partials empty).
std::unique_ptr<RotationMap> make_fixed_rotation_map();

}  // namespace rigidae::multibody
