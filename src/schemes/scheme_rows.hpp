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
