#pragma once
// Residual rows shared by several schemes (internal header).
#include "rigidae/schemes/scheme.hpp"

namespace rigidae::schemes {

// q' - N v (+ Phi_q^T mu when the layout carries mu).
inline void kinematic_rows(const StandardTerms& t, const UnknownLayout& lay, const ConstVecRef& y,
                           const ConstVecRef& yp, VecRef F) {
  F.segment(lay.q_offset(), lay.nq) = yp.segment(lay.q_offset(), lay.nq) - t.qdot;
  if (lay.n_mu > 0)
    F.segment(lay.q_offset(), lay.nq).noalias() += t.phi_q.transpose() * y.segment(lay.mu_offset(), lay.n_mu);
}

// M v' - f (+ G^T lambda when the layout carries lambda).
inline void dynamic_rows(const StandardTerms& t, const UnknownLayout& lay, const ConstVecRef& y,
                         const ConstVecRef& yp, VecRef F) {
  F.segment(lay.v_offset(), lay.nv).noalias() = t.M * yp.segment(lay.v_offset(), lay.nv);
  F.segment(lay.v_offset(), lay.nv) -= t.f;
  if (lay.n_lambda > 0)
    F.segment(lay.v_offset(), lay.nv).noalias() += t.G.transpose() * y.segment(lay.lambda_offset(), lay.n_lambda);
}

}  // namespace rigidae::schemes

namespace rigidae::schemes {

// The constraint rows of one level, for a block of the given kind.
// Position level: Phi(q).
inline void position_level_rows(const StandardTerms& t, VecRef rows) { rows = t.phi; }

// Velocity level: G v (Force kind) or Phi_q q' (Kinematic kind, where q'
// carries mu through the kinematic rows).
inline void velocity_level_rows(const StandardTerms& t, ConstraintKind kind, const UnknownLayout& lay,
                                const ConstVecRef& y, const ConstVecRef& yp, VecRef rows) {
  if (kind == ConstraintKind::Force)
    rows.noalias() = t.G * y.segment(lay.v_offset(), lay.nv);
  else
    rows.noalias() = t.phi_q * yp.segment(lay.q_offset(), lay.nq);
}

// Acceleration level (Force kind): G v' - gamma.
inline void acceleration_level_rows(const StandardTerms& t, const UnknownLayout& lay, const ConstVecRef& yp,
                                    VecRef rows) {
  rows.noalias() = t.G * yp.segment(lay.v_offset(), lay.nv);
  rows -= t.gamma;
}

// One multiplier group's rows of a block:
//   w_A (G v' - gamma) + w_V (velocity level) + w_P Phi,
// levels in that order; the first level present is written, the others
// added, and a weight of one is not multiplied in.
inline void block_rows(const StandardTerms& t, ConstraintKind kind, const LevelWeights& w, const UnknownLayout& lay,
                       const ConstVecRef& y, const ConstVecRef& yp, VecRef rows) {
  bool written = false;
  if (w.acceleration != 0.0) {
    acceleration_level_rows(t, lay, yp, rows);
    if (w.acceleration != 1.0) rows *= w.acceleration;
    written = true;
  }
  if (w.velocity != 0.0) {
    if (!written) {
      velocity_level_rows(t, kind, lay, y, yp, rows);
      if (w.velocity != 1.0) rows *= w.velocity;
    } else if (kind == ConstraintKind::Force) {
      rows.noalias() += w.velocity * (t.G * y.segment(lay.v_offset(), lay.nv));
    } else {
      rows.noalias() += w.velocity * (t.phi_q * yp.segment(lay.q_offset(), lay.nq));
    }
    written = true;
  }
  if (w.position != 0.0) {
    if (!written) {
      position_level_rows(t, rows);
      if (w.position != 1.0) rows *= w.position;
    } else {
      rows += w.position * t.phi;
    }
    written = true;
  }
  if (!written) rows.setZero();
}

}  // namespace rigidae::schemes
