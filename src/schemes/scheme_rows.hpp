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

// The constraint rows of one level, written into the multiplier group that
// level determines (lambda for the Force kind, mu for the Kinematic kind).
// Position level: Phi(q).
inline void position_level_rows(const StandardTerms& t, VecRef rows) { rows = t.phi; }

// Velocity level: G v (Force kind, the layout carries lambda) or Phi_q q'
// (Kinematic kind, where q' carries mu through the kinematic rows).
inline void velocity_level_rows(const StandardTerms& t, const UnknownLayout& lay, const ConstVecRef& y,
                                const ConstVecRef& yp, VecRef rows) {
  if (lay.n_lambda > 0)
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

// Layouts. A single-level scheme has one multiplier group: lambda (force)
// in the Lagrange form, mu (kinematic) in the Euler form.
inline UnknownLayout single_level_layout(const Representation& rep) {
  const bool force = rep.constraint_kind() == ConstraintKind::Force;
  return {rep.nq(), rep.nv(), force ? rep.nc() : 0, force ? 0 : rep.nc()};
}
// Index 1 keeps lambda in the Lagrange form and no multiplier in the Euler form.
inline UnknownLayout acceleration_level_layout(const Representation& rep) {
  const bool force = rep.constraint_kind() == ConstraintKind::Force;
  return {rep.nq(), rep.nv(), force ? rep.nc() : 0, 0};
}

// The multiplier group a single-level scheme solves for.
inline VecRef constraint_rows(const UnknownLayout& lay, VecRef F) {
  return lay.n_lambda > 0 ? F.segment(lay.lambda_offset(), lay.n_lambda) : F.segment(lay.mu_offset(), lay.n_mu);
}

// The whole index-1 residual (index1, and projection between projections):
// kinematics, dynamics and, in the Lagrange form, G v' = gamma.
inline void index1_residual(const StandardTerms& t, const UnknownLayout& lay, const ConstVecRef& y,
                            const ConstVecRef& yp, VecRef F) {
  kinematic_rows(t, lay, y, yp, F);
  dynamic_rows(t, lay, y, yp, F);
  if (lay.n_lambda > 0) acceleration_level_rows(t, lay, yp, F.segment(lay.lambda_offset(), lay.n_lambda));
}

}  // namespace rigidae::schemes
