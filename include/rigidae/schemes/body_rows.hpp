#pragma once
// One body's own constraint rows from its standard-form terms
// (representation.hpp), as the multibody assembler evaluates a body's own
// constraint block (src/multibody/multibody_problem.cpp,
// internal_block_rows), and the dense one-body kernels it runs for bodies
// not joined to others (src/multibody/consistent_start.cpp). They are the
// deleted one-body model's expressions, kept on the same types in the same
// order: floating-point sums depend on their order, and a one-body scene
// gives the one-body pins' numbers (tests/guard/pinned.json) bit for bit only
// while they do. The assembler's rotation rows q' - N v and M v' - f are
// loops there in the same order (M v' summed first, then - f).
//
//   added to the kinematic rows   Phi_q^T mu   (add_kinematic_multipliers)
//   added to the dynamic rows     G^T lambda   (add_constraint_forces)
//   a multiplier group's rows of a block of the body's own constraints
//                    w_A (G v' - gamma) + w_V (velocity level) + w_P Phi
//   velocity level   G v (Force kind) or Phi_q q' (Kinematic kind)
// Each sum is formed first and then added (G^T lambda is a product, then
// added to the dynamic row), and a block's levels are taken in the order
// acceleration, velocity, position. Arguments are the body's own segments:
// q' (nq), v and v' (nv), lambda and mu (nc each). Hot path: allocates
// nothing.
#include <Eigen/Core>

#include "rigidae/coords/representation.hpp"
#include "rigidae/schemes/block_rows.hpp"

namespace rigidae::schemes {

using VecRef = Eigen::Ref<Eigen::VectorXd>;
using ConstVecRef = Eigen::Ref<const Eigen::VectorXd>;

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

// One body's unknowns y = (q | v | lambda | mu) and the rows of its own
// constraint block (none for Euler angles, and no multiplier group when the
// scheme writes no rows for its kind: index 1 in the Euler form).
struct BodyLayout {
  int nq = 0, nv = 0, n_lambda = 0, n_mu = 0;  // n_lambda, n_mu: 0 or the block's rows
  ConstraintKind kind = ConstraintKind::None;  // of the body's own block
  LevelWeights lambda_rows, mu_rows;           // the scheme's rows for that kind
  int q_offset() const { return 0; }
  int v_offset() const { return nq; }
  int lambda_offset() const { return nq + nv; }
  int mu_offset() const { return nq + nv + n_lambda; }
  int size() const { return nq + nv + n_lambda + n_mu; }
};

// The consistent start of one body's unknowns laid out as `lay`, dense (the
// saddle system of one body has at most 15 rows). Given q, v in y (on the
// constraint manifold), fills the multipliers of y and all of yp so that
// the body's rows vanish to round-off:
// (v', lambda) from the constrained-acceleration system
//   [M G^T; G 0] (v', lambda) = (f, gamma),
// mu from d/dt Phi = Phi_q (N v - Phi_q^T mu) = 0 (zero on exact data),
// q' = N v - Phi_q^T mu. A scheme with feedback starts on its own rows:
// with lambda rows w_A (G v' - gamma) + w_V G v + w_P Phi = 0, the target
// of G v' is gamma - (w_V G v + w_P Phi) / w_A; with mu rows of a
// Kinematic block w_V Phi_q q' + w_P Phi = 0, Phi_q q' = -w_P Phi / w_V.
void consistent_start(const StandardTerms& terms, const BodyLayout& lay, VecRef y, VecRef yp);

// v moved onto G v = 0 (Force kind), the nearest such v in kinetic energy:
//   v - M^-1 G^T (G M^-1 G^T)^-1 G v
// (terms evaluated at the body's q). M must be positive definite.
void project_velocities(const StandardTerms& terms, VecV& v);

}  // namespace rigidae::schemes
