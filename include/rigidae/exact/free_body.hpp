#pragma once
// The torque-free rigid body (Euler-Poinsot motion) in closed form.
//
// In principal axes with moments I1 < I2 < I3, body angular momentum L and
// energy E, omega is A cn, B sn, C dn of lambda t + const (Landau & Lifshitz
// sec. 37), with the cn and dn roles of axes 1 and 3 exchanged on the other
// side of the separatrix L^2 = 2 E I2. The space angular momentum is fixed;
// the orientation is the rotation taking the body direction of L to its space
// direction, followed by an angle phi about L with
//   phi' = |L| (L_x^2/I_x + L_y^2/I_y)/(L_x^2 + L_y^2)
// (x, y: the body axes other than the one L never approaches, the cn axis),
// periodic and integrated once per period (src/exact/periodic_integral.hpp).
// Symmetric bodies (two equal moments) precess with constant rates; a
// spherical body, or one spinning about a principal axis, turns at constant omega.
#include <memory>

#include "rigidae/core/types.hpp"
#include "rigidae/exact/exact_solution.hpp"

namespace rigidae::exact {

// J_B: inertia about the centre of mass (or the fixed point), body axes, SPD,
// any orientation of its principal axes. `span`: the time span (s) the
// accuracy estimate refers to.
// Throws std::invalid_argument exactly on the separatrix (L^2 = 2 E I2 to
// round-off, I1 < I2 < I3, not a steady rotation), where the period is infinite.
std::unique_ptr<ExactSolution> make_free_body_solution(const Mat3& J_B, const Mat3& R0_WB, const Vec3& omega0_B,
                                                      double t0, double span);

}  // namespace rigidae::exact
