#pragma once
// Closed-form reference solutions: the rotation at any time, without an integrator.
//
// Two classical integrable cases of rigid-body rotation are covered:
// - the torque-free body (Euler-Poinsot), any inertia: Jacobi elliptic
//   functions for omega, the angle about the fixed angular momentum by
//   quadrature (free_body.hpp);
// - the heavy symmetric top with a fixed point (Lagrange): Jacobi elliptic
//   functions for the nutation, precession and spin by quadrature
//   (lagrange_top.hpp).
// Everything else (an asymmetric heavy top, a symmetric one whose centre of
// mass is off the symmetry axis) has no closed form here: the factory says why.
#include <memory>
#include <string>

#include "rigidae/core/types.hpp"
#include "rigidae/model/scene.hpp"

namespace rigidae::exact {

struct RotationState {
  Mat3 R_WB;     // body -> space
  Vec3 omega_B;  // rad/s, body components
};

class ExactSolution {
 public:
  virtual ~ExactSolution() = default;
  // Which closed form this is, e.g. "free body (Jacobi elliptic)".
  virtual std::string name() const = 0;
  // The state at absolute scene time t (s); scene.time.start is the initial time.
  virtual RotationState at(double t) const = 0;
  // Estimated orientation accuracy (rad) over the time span the solution was
  // built for, from the measured agreement with tight integrations; grows
  // slowly (round-off in the phases) beyond it.
  virtual double accuracy() const = 0;
};

// The exact solution of a scene, or nullptr with `why` (if non-null) filled
// when the scene is not a case solved here. Decided from
// make_rigid_body_model(scene): torque free (free support, centre of mass at
// the reference point, or no gravity) -> free body; a fixed point with two
// equal principal moments about it (1e-12 relative) and the centre of mass on
// the third principal axis -> Lagrange top.
// Throws std::invalid_argument for a solvable case at an exact degeneracy the
// closed forms do not cover (the message says which).
std::unique_ptr<ExactSolution> make_exact_solution(const Scene& scene, std::string* why);

// The same, with the degenerate cases also reported through `why` (nullptr
// and the reason) instead of thrown: for callers that only need to know
// whether a closed form exists, and why not.
std::unique_ptr<ExactSolution> find_exact_solution(const Scene& scene, std::string* why);

}  // namespace rigidae::exact
