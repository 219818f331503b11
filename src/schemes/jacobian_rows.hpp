#pragma once
// The exact iteration-matrix rows of the residual rows in rigidae/schemes/body_rows.hpp
// (internal header). Each adds dF/dy + cj dF/dy' of its rows into J, which
// starts zeroed; columns are grouped as y = (q | v | lambda | mu).
#include "rigidae/schemes/scheme.hpp"

namespace rigidae::schemes {

inline VecQ coordinates_of(const JacobianInputs& in) { return in.y.segment(in.lay.q_offset(), in.lay.nq); }

// Rows q' - N v (+ Phi_q^T mu).
inline void add_kinematic_jacobian(const JacobianInputs& in, IterationMatrixView& J) {
  const UnknownLayout& lay = in.lay;
  const int r = lay.q_offset(), nq = lay.nq;
  J.state.block(r, lay.q_offset(), nq, nq) -= in.derivs.qdot_q;
  J.state.block(r, lay.q_offset(), nq, nq).diagonal().array() += in.cj;
  J.state.block(r, lay.v_offset(), nq, lay.nv) -= in.derivs.N;
  if (lay.n_mu > 0) {
    MatQQ H;
    in.rep.constraint_hessian_weighted(coordinates_of(in), in.y.segment(lay.mu_offset(), lay.n_mu), H);
    J.state.block(r, lay.q_offset(), nq, nq) += H;
    J.mu += in.terms.phi_q.transpose();
  }
}

// Rows M v' - f (+ G^T lambda); G = Phi_q where lambda exists (Force kind).
inline void add_dynamic_jacobian(const JacobianInputs& in, IterationMatrixView& J) {
  const UnknownLayout& lay = in.lay;
  const int r = lay.v_offset(), nv = lay.nv;
  J.state.block(r, lay.q_offset(), nv, lay.nq) += in.derivs.Ma_q - in.derivs.f_q;
  J.state.block(r, lay.v_offset(), nv, nv) += in.cj * in.terms.M - in.derivs.f_v;
  if (lay.n_lambda > 0) {
    MatQQ H;
    in.rep.constraint_hessian_weighted(coordinates_of(in), in.y.segment(lay.lambda_offset(), lay.n_lambda), H);
    J.state.block(r, lay.q_offset(), nv, lay.nq) += H;
    J.lambda += in.terms.G.transpose();
  }
}

// weight * Phi(q) in the rows starting at `row`.
inline void add_position_level_jacobian(const JacobianInputs& in, int row, double weight, IterationMatrixView& J) {
  J.state.block(row, in.lay.q_offset(), in.terms.phi_q.rows(), in.lay.nq) += weight * in.terms.phi_q;
}

// weight * (G v) (Force kind) or weight * Phi_q q' (Kinematic kind) in the
// rows starting at `row`.
inline void add_velocity_level_jacobian(const JacobianInputs& in, ConstraintKind kind, int row, double weight,
                                        IterationMatrixView& J) {
  const UnknownLayout& lay = in.lay;
  const int nc = in.terms.phi_q.rows();
  MatCQ H;
  if (kind == ConstraintKind::Force) {
    in.rep.constraint_hessian_applied(coordinates_of(in), in.y.segment(lay.v_offset(), lay.nv), H);
    J.state.block(row, lay.v_offset(), nc, lay.nv) += weight * in.terms.G;
  } else {
    in.rep.constraint_hessian_applied(coordinates_of(in), in.yp.segment(lay.q_offset(), lay.nq), H);
    J.state.block(row, lay.q_offset(), nc, lay.nq) += (weight * in.cj) * in.terms.phi_q;
  }
  J.state.block(row, lay.q_offset(), nc, lay.nq) += weight * H;
}

// weight * (G v' - gamma) (Force kind) in the rows starting at `row`.
inline void add_acceleration_level_jacobian(const JacobianInputs& in, int row, double weight, IterationMatrixView& J) {
  const UnknownLayout& lay = in.lay;
  const int nc = in.terms.G.rows();
  MatCQ H;
  in.rep.constraint_hessian_applied(coordinates_of(in), in.yp.segment(lay.v_offset(), lay.nv), H);
  J.state.block(row, lay.q_offset(), nc, lay.nq) += weight * (H - in.derivs.gamma_q);
  J.state.block(row, lay.v_offset(), nc, lay.nv) += weight * (in.cj * in.terms.G - in.derivs.gamma_v);
}

// The iteration-matrix rows of block_rows (rigidae/schemes/body_rows.hpp), levels in the same order.
inline void add_block_jacobian(const JacobianInputs& in, ConstraintKind kind, const LevelWeights& w, int row,
                               IterationMatrixView& J) {
  if (w.acceleration != 0.0) add_acceleration_level_jacobian(in, row, w.acceleration, J);
  if (w.velocity != 0.0) add_velocity_level_jacobian(in, kind, row, w.velocity, J);
  if (w.position != 0.0) add_position_level_jacobian(in, row, w.position, J);
}

}  // namespace rigidae::schemes
