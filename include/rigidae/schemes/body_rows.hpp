#pragma once
// One body's residual rows from its standard-form terms (representation.hpp),
// written once for both assemblers: the one-body schemes (src/schemes/
// scheme.cpp) and the multibody assembler's bodies' own constraint blocks
// (src/multibody/multibody_problem.cpp, whose rotation rows q' - N v and
// M v' - f are loops in this same order: cheaper on its small blocks, and
// equal bit for bit, test_pivot_bitwise.cpp). Floating-point sums depend on
// their order, so a one-body scene run as a system of one body gives the
// one-body model's numbers bit for bit only if both evaluate every row by the
// same expressions on the same types; these are they.
//
//   kinematic rows   q' - N v          (+ Phi_q^T mu: add_kinematic_multipliers)
//   dynamic rows     M v' - f          (+ G^T lambda: add_constraint_forces)
//   a multiplier group's rows of a block of the body's own constraints
//                    w_A (G v' - gamma) + w_V (velocity level) + w_P Phi
//   velocity level   G v (Force kind) or Phi_q q' (Kinematic kind)
// Each sum is formed first and then added (M v' is a product, then f is
// subtracted; G^T lambda is a product, then added to the dynamic row), and
// a block's levels are taken in the order acceleration, velocity, position.
// Arguments are the body's own segments: q' (nq), v and v' (nv), lambda and
// mu (nc each). Hot path: allocates nothing.
#include "rigidae/schemes/scheme.hpp"

namespace rigidae::schemes {

// F += Phi_q^T mu (GGL's mu in q' = N v - Phi_q^T mu).
inline void add_kinematic_multipliers(const StandardTerms& t, const ConstVecRef& mu, VecRef F) {
  F.noalias() += t.phi_q.transpose() * mu;
}

// F += G^T lambda (the constraint forces of a Force-kind block).
inline void add_constraint_forces(const StandardTerms& t, const ConstVecRef& lambda, VecRef F) {
  F.noalias() += t.G.transpose() * lambda;
}

// Velocity level: G v (Force kind) or Phi_q q' (Kinematic kind, where q'
// carries mu through the kinematic rows).
inline void velocity_level_rows(const StandardTerms& t, ConstraintKind kind, const ConstVecRef& v,
                                const ConstVecRef& qp, VecRef rows) {
  if (kind == ConstraintKind::Force)
    rows.noalias() = t.G * v;
  else
    rows.noalias() = t.phi_q * qp;
}

// Acceleration level (Force kind): G v' - gamma.
inline void acceleration_level_rows(const StandardTerms& t, const ConstVecRef& vp, VecRef rows) {
  rows.noalias() = t.G * vp;
  rows -= t.gamma;
}

// One multiplier group's rows of the body's block:
//   w_A (G v' - gamma) + w_V (velocity level) + w_P Phi,
// levels in that order; the first level present is written, the others
// added, and a weight of one is not multiplied in.
inline void block_rows(const StandardTerms& t, ConstraintKind kind, const LevelWeights& w, const ConstVecRef& v,
                       const ConstVecRef& qp, const ConstVecRef& vp, VecRef rows) {
  bool written = false;
  if (w.acceleration != 0.0) {
    acceleration_level_rows(t, vp, rows);
    if (w.acceleration != 1.0) rows *= w.acceleration;
    written = true;
  }
  if (w.velocity != 0.0) {
    if (!written) {
      velocity_level_rows(t, kind, v, qp, rows);
      if (w.velocity != 1.0) rows *= w.velocity;
    } else if (kind == ConstraintKind::Force) {
      rows.noalias() += w.velocity * (t.G * v);
    } else {
      rows.noalias() += w.velocity * (t.phi_q * qp);
    }
    written = true;
  }
  if (w.position != 0.0) {
    if (!written) {
      rows = t.phi;
      if (w.position != 1.0) rows *= w.position;
    } else {
      rows += w.position * t.phi;
    }
    written = true;
  }
  if (!written) rows.setZero();
}

// The drift of the body's own constraints at (q, v) (terms evaluated there):
// |Phi| and |G v| (Force kind) or |Phi_q N v| (Kinematic kind, d/dt Phi),
// 2-norms over the block's rows. What the projection scheme compares with
// its threshold.
struct BlockDrift {
  double position = 0.0, velocity = 0.0;
};
inline BlockDrift block_drift(const StandardTerms& t, ConstraintKind kind, const VecV& v) {
  BlockDrift d;
  d.position = t.phi.norm();
  if (kind == ConstraintKind::Force)
    d.velocity = (t.G * v).norm();
  else
    d.velocity = (t.phi_q * t.qdot).norm();
  return d;
}

// The consistent start of one body's unknowns laid out as `lay` (y = (q | v
// | lambda | mu)): see ConstraintScheme::consistent_start. Dense (the
// saddle system of one body has at most 15 rows).
void consistent_start(const StandardTerms& terms, const UnknownLayout& lay, VecRef y, VecRef yp);

// v moved onto G v = 0 (Force kind), the nearest such v in kinetic energy:
//   v - M^-1 G^T (G M^-1 G^T)^-1 G v
// (terms evaluated at the body's q). M must be positive definite.
void project_velocities(const StandardTerms& terms, VecV& v);

}  // namespace rigidae::schemes
