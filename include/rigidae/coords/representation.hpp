#pragma once
// A coordinate representation of a rotating rigid body in standard form.
//
// Every representation, in either equation form, writes its equations as
//
//   q' = N(q) v                       kinematics          (nq rows)
//   M(q) v' = f(t, q, v) - G^T lambda dynamics            (nv rows)
//   Phi(q) = 0                        position constraints (nc rows)
//
// Lagrange form: v = q', N = I, M the mass matrix in the coordinates, and the
// constraints are held by forces: G = Phi_q, with the velocity level G v = 0
// and the acceleration level G v' = gamma(q, v).
// Euler form: v = omega_B, M = J, and the constraints (|q| = 1, R^T R = I)
// are kept by the kinematic relation itself (Phi_q N = 0 on the manifold):
// they take no force multiplier. A scheme enforces them through the
// kinematics instead (q' = N v - Phi_q^T mu).
//
// The multibody assembler (multibody/) turns these terms into IDA residual
// rows, and a constraint scheme (schemes/) says which rows a constraint block
// gets.
#include <memory>
#include <string>
#include <vector>

#include "rigidae/core/types.hpp"
#include "rigidae/model/rigid_body.hpp"
#include "rigidae/model/scene.hpp"
#include "rigidae/so3/euler_sequence.hpp"

namespace rigidae {

enum class ConstraintKind {
  None,       // no constraints (Euler angles)
  Force,      // held by multiplier forces in the dynamics (Lagrange form)
  Kinematic,  // kept by the kinematic relation (Euler form)
};

// The standard-form terms at one (t, q, v). Sizes: qdot nq; M nv x nv;
// f nv; phi nc; phi_q nc x nq; G nc x nv and gamma nc (Force kind only).
struct StandardTerms {
  VecQ qdot;    // N(q) v
  MatVV M;      // generalized mass
  VecV f;       // applied and velocity-dependent generalized forces
  VecC phi;     // position constraint residual
  MatCQ phi_q;  // d(phi)/dq
  MatCV G;      // velocity-level constraint Jacobian: G v = 0
  VecC gamma;   // acceleration level: G v' = gamma
};

// Derivatives of the standard terms at one (t, q, v), for the exact
// iteration matrix. Sizes: qdot_q nq x nq; N nq x nv; Ma_q, f_q nv x nq;
// f_v nv x nv; gamma_q nc x nq and gamma_v nc x nv (Force kind only).
struct TermDerivatives {
  MatQQ qdot_q;   // d(N(q) v)/dq
  MatQV N;        // d(N(q) v)/dv
  MatVQ Ma_q;     // d(M(q) a)/dq for the acceleration a given to differentiate()
  MatVQ f_q;      // df/dq
  MatVV f_v;      // df/dv
  MatCQ gamma_q;  // d(gamma)/dq
  MatCV gamma_v;  // d(gamma)/dv
};

// The Euler form as an ODE in one fixed-size call, for the explicit and
// multistep integrators (schemes/body_ode.hpp): with x = (q, omega_B),
//   q'       = N(q) omega_B
//   omega_B' = J^-1 (tau(R(q)) - omega_B x J omega_B),   tau = c x (m R(q)^T g)
// the same function evaluate() and a solve with M = J give, written for one
// representation's sizes (coords/euler_form_rate.hpp): no dynamic-size
// temporaries, J^-1 formed once. Hot path: allocates nothing.
class EulerFormRate {
 public:
  virtual ~EulerFormRate() = default;
  virtual void rate(const double* x, double* xdot) const = 0;
};

class Representation {
 public:
  virtual ~Representation() = default;

  // e.g. "quaternion/lagrange".
  virtual std::string name() const = 0;
  virtual int nq() const = 0;
  virtual int nv() const = 0;
  virtual int nc() const = 0;
  virtual ConstraintKind constraint_kind() const = 0;
  // One short name per position constraint, e.g. "norm" or "c12".
  virtual std::vector<std::string> constraint_names() const = 0;

  // The hot path: called once per residual evaluation; must not allocate.
  virtual void evaluate(double t, const VecQ& q, const VecV& v, StandardTerms& out) const = 0;

  // The derivatives of evaluate()'s terms at (t, q, v), with the mass
  // matrix's applied to the acceleration a (v' of the state). Hot path: must
  // not allocate.
  virtual void differentiate(double t, const VecQ& q, const VecV& v, const VecV& a, TermDerivatives& out) const = 0;
  // Second derivatives of the constraints, contracted (hot path, no
  // allocation): d(Phi_q^T m)/dq (nq x nq) for multipliers m, which is also
  // d(G^T m)/dq in the Force kind (G = Phi_q there) ...
  virtual void constraint_hessian_weighted(const VecQ& q, const VecC& m, MatQQ& out) const;
  // ... and d(Phi_q w)/dq (nc x nq) for a vector w of coordinate rates
  // (d(G w)/dq in the Force kind). The defaults are for nc = 0.
  virtual void constraint_hessian_applied(const VecQ& q, const VecQ& w, MatCQ& out) const;

  // The Euler form's right-hand side as one fixed-size kernel (see
  // EulerFormRate), or nullptr where the representation offers none (the
  // Lagrange forms, Euler angles): the caller then goes through evaluate().
  virtual const EulerFormRate* euler_form_rate() const { return nullptr; }

  // Coordinates and velocities of a physical state (R_WB an exact rotation).
  virtual void from_physical(const Mat3& R_WB, const Vec3& omega_B, VecQ& q, VecV& v) const = 0;
  // The orientation the coordinates describe, as a unit quaternion (w >= 0 not
  // implied). Off the constraint manifold: the nearest rotation.
  virtual Vec4 orientation(const VecQ& q) const = 0;
  // The matrix R(q) of the placement x = R(q) X that defines kinetic and
  // potential energy in the Lagrange form (|q|^2 times a rotation for
  // non-unit quaternions; the raw 3x3 for linear coordinates).
  virtual Mat3 placement(const VecQ& q) const = 0;
  // Body angular velocity the state describes.
  virtual Vec3 body_angular_velocity(const VecQ& q, const VecV& v) const = 0;
  // Moves q to the nearest point of the constraint manifold (a unit
  // quaternion; the orthogonal polar factor of R). No-op without constraints.
  virtual void project_coordinates(VecQ& /*q*/) const {}

  // Charts. A representation with singular charts (Euler angles) is one
  // chart of a numbered family (chart()) and never changes: which chart a
  // run is in is the run's state (MultibodyProblem's workspace), not the
  // representation's. It reports a margin in [0, 1] (1 far from the
  // singularity, 0 at it), the chart most regular at an orientation, and
  // builds the same representation in another chart of the family. A state
  // moves between charts through the physical state:
  //   other.from_physical(placement(q), body_angular_velocity(q, v), q', v').
  virtual int chart() const { return 0; }
  virtual bool has_charts() const { return false; }
  virtual double chart_margin(const VecQ& /*q*/) const { return 1.0; }
  virtual std::string chart_name() const { return {}; }
  // The chart most regular at q's orientation (chart() when this one is).
  virtual int most_regular_chart(const VecQ& /*q*/) const { return chart(); }
  // This representation in chart `c` of the family (a chart() or
  // most_regular_chart() of it).
  virtual std::unique_ptr<Representation> in_chart(int c) const;
};

// The registered representation by name ("quaternion/lagrange"), starting
// in chart `start_chart` where it has charts (Euler angles). Throws
// InputError naming the valid names for an unknown one.
std::unique_ptr<Representation> make_representation(const std::string& name, const RigidBodyModel& body,
                                                    const so3::EulerSequence& start_chart);
// Every registered name, in the registry's order: "<coordinates>/<form>".
std::vector<std::string> representation_names();
// The registry name of a (coordinates, equations) pair.
std::string representation_name(const Coordinates& c, Equations e);

// The registered coordinates ("euler", "quaternion", "linear"), in the
// registry's order: the valid values of formulation.coordinates, of
// --coordinates and of a multibody body's `coordinates`.
std::vector<std::string> coordinates_names();
std::vector<Coordinates> all_coordinates();
// Whether the coordinates carry position constraints (Phi(q) = 0): all but
// Euler angles. Throws InputError for a name not in the registry.
bool has_constraints(const Coordinates& c);
// What each registered set of coordinates is, one phrase each, joined for
// --help: "Euler angles (3, ...), unit quaternions (4, 1 constraint) or ...".
std::string coordinates_help();
// The representation a scene's formulation names, in the chart it starts in
// (the scene's sequence, or the most regular at the initial orientation).
std::unique_ptr<Representation> make_representation(const Scene& scene, const RigidBodyModel& body);

// Names for messages and reports.
std::string to_string(const Coordinates& c);
std::string to_string(Equations e);

}  // namespace rigidae
