#pragma once
// One body's equations as an ODE x' = f(t, x), x = (q, v), for CVODE and
// ARKODE: the arithmetic of the deleted one-body ODE form (SingleBodyOde),
// now the multibody ODE form's for bodies that are not coupled to one
// another (multibody/multibody_ode.hpp), so that a one-body scene run as a
// system of one body integrates bit for bit as the one-body model did
// (tests/guard/pinned.json's ode_runs; tests/unit/test_body_ode.cpp).
//
//   q' = N(q) v
//   Euler form (and Euler angles): M v' = f           (no multipliers: the
//       kinematics keeps |q| = 1, R^T R = I up to the integration error)
//       with the representation's fixed-size kernel when it has one
//       (Representation::euler_form_rate: J^-1 formed once), else through
//       evaluate() and an LDLT of M (refactorised only when M changes: once
//       per run for the constant J)
//   Lagrange form with constraints: (v', lambda) from
//       [M  G^T] [v'    ]   [f    ]
//       [G  0  ] [lambda] = [gamma]
//     by the Schur complement  S lambda = G M^-1 f - gamma,  S = G M^-1 G^T,
//     v' = M^-1 (f - G^T lambda); when M is singular (linear coordinates of a
//     lamina, J3 = J1 + J2: no second moment along the normal) the
//     saddle-point matrix is solved whole (full-pivoting LU; it stays regular
//     since M is positive definite on ker G).
//
// Invariants (nc > 0): Phi(q) = 0, and in the Lagrange form G v = 0.
// drift(): the 2-norms |Phi| and |G v| (|Phi_q N v| in the Euler form), the
// one-body rule (schemes::block_drift).
// project(): q to the nearest point of Phi = 0 (the representation's own:
// the normalised quaternion, the polar factor of R), then v to G v = 0 in
// the metric of M. project_error(): its linearisation at x (e_q orthogonally
// onto ker Phi_q, e_v onto ker G in the metric of M).
//
// The representation is passed to every call: a body with Euler angles
// changes chart during a run (its owner keeps which). Sizes nq, nv, nc are
// the same in every chart. rate(), accelerations() and drift() allocate
// nothing.
#include "rigidae/coords/representation.hpp"
#include "rigidae/schemes/body_rows.hpp"

#include <Eigen/Cholesky>

namespace rigidae::schemes {

class BodyOde {
 public:
  BodyOde() = default;
  explicit BodyOde(const Representation& rep);

  // x' at (t, x); false when it is not finite.
  bool rate(const Representation& rep, double t, const double* x, double* xdot);
  // v' and (Force kind) lambda at (t, x) through evaluate() (never the
  // kernel), into acceleration() and multipliers(); false when not finite.
  bool accelerations(const Representation& rep, double t, const double* x);
  const VecV& acceleration() const { return acc_; }
  const VecC& multipliers() const { return lambda_; }

  BlockDrift drift(const Representation& rep, double t, const double* x);
  void project(const Representation& rep, double t, double* x);
  void project_error(const Representation& rep, double t, const double* x, double* e);

  int nq() const { return nq_; }
  int nv() const { return nv_; }
  int nc() const { return nc_; }
  // Lagrange form with constraints: multipliers in the state's observation.
  bool force() const { return force_; }

 private:
  // The factorised mass matrix of terms_, reused while M is unchanged.
  const Eigen::LDLT<MatVV>& factorised_mass();
  // [M G^T; G 0] [x; m] = [top; bottom] at terms_, solved whole.
  void saddle_point_solve(const VecV& top, const VecC& bottom, VecV& x, VecC& m) const;

  int nq_ = 0, nv_ = 0, nc_ = 0;
  bool force_ = false;
  Eigen::LDLT<MatVV> mass_ldlt_;
  MatVV mass_factored_;
  bool mass_regular_ = true;  // of mass_ldlt_: false for a lamina in linear coordinates
  StandardTerms terms_;       // scratch of the hot path
  VecQ q_;
  VecV v_, acc_;
  VecC lambda_;
};

}  // namespace rigidae::schemes
