#pragma once
// The heavy symmetric (Lagrange) top with a fixed point in closed form.
//
// A transverse and C axial moment about the pivot, centre of mass at distance
// l on the symmetry axis e_s, gravity g. With u = cos(theta), theta the angle
// between e_s and the up direction, a = C omega_3 / A, b = L_up / A,
// alpha = (2E - C omega_3^2)/A, beta = 2 m g l / A:
//   u'^2 = f(u) = (1 - u^2)(alpha - beta u) - (b - a u)^2,
//   u = u1 + (u2 - u1) sn^2(lambda (t - t1) | k^2),
// and the z-x-z angles about the up direction have rates
//   phi' + psi' = (omega_3 - a) + (b + a)/(1 + u),
//   phi' - psi' = -(omega_3 - a) + (b - a)/(1 - u),
// integrated in closed form near a pole (an arctangent carries the fast swing
// of the azimuth there) and by periodic quadrature elsewhere.
#include <memory>

#include "rigidae/core/types.hpp"
#include "rigidae/exact/exact_solution.hpp"

namespace rigidae::exact {

// J_B: inertia about the pivot (body axes) with two equal principal moments,
// c_B: pivot -> centre of mass, on the remaining principal axis (non-zero),
// gravity_W non-zero. `span`: the time span (s) the accuracy estimate refers to.
// Throws std::invalid_argument if the body is not such a top, or if the
// symmetry axis starts exactly vertical while it has a transverse angular
// velocity (the z-x-z angles start at their singularity). A top spinning
// about its vertical axis (sleeping, or hanging) is handled: it turns at constant omega.
std::unique_ptr<ExactSolution> make_lagrange_top_solution(const Mat3& J_B, const Vec3& c_B, double mass,
                                                          const Vec3& gravity_W, const Mat3& R0_WB,
                                                          const Vec3& omega0_B, double t0, double span);

}  // namespace rigidae::exact
