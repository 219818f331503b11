// What every scheme shares: the layout of its unknowns, the assembler that
// loops over constraint blocks, the consistent start and the default note.
#include "rigidae/schemes/scheme.hpp"

#include "jacobian_rows.hpp"
#include "rigidae/schemes/body_rows.hpp"

namespace rigidae {

using schemes::add_block_jacobian;
using schemes::add_dynamic_jacobian;
using schemes::add_kinematic_jacobian;
using schemes::add_constraint_forces;
using schemes::add_kinematic_multipliers;
using schemes::block_rows;
using schemes::dynamic_rows;
using schemes::kinematic_rows;

std::string ConstraintScheme::note(const Representation& rep) const {
  if (rep.nc() == 0) return "Euler angles have no constraints: scheme '" + name() + "' leaves the ODE as it is";
  return constrained_note(rep);
}

UnknownLayout ConstraintScheme::layout(const Representation& rep) const {
  UnknownLayout lay;
  lay.nq = rep.nq();
  lay.nv = rep.nv();
  const KindRows k = rows().of(rep.constraint_kind());
  if (rep.nc() == 0 || !(k.lambda || k.mu)) return lay;
  lay.n_lambda = k.lambda ? rep.nc() : 0;
  lay.n_mu = k.mu ? rep.nc() : 0;
  ConstraintBlockLayout& blk = lay.blocks[lay.n_blocks++];
  blk.kind = rep.constraint_kind();
  blk.nr = rep.nc();
  blk.rows = k;
  if (k.lambda) blk.lambda_row = lay.lambda_offset();
  if (k.mu) blk.mu_row = lay.mu_offset();
  return lay;
}

void ConstraintScheme::residual(const StandardTerms& t, const UnknownLayout& lay, const ConstVecRef& y,
                                const ConstVecRef& yp, VecRef F) const {
  const auto qp = yp.segment(lay.q_offset(), lay.nq);
  const auto v = y.segment(lay.v_offset(), lay.nv), vp = yp.segment(lay.v_offset(), lay.nv);
  kinematic_rows(t, qp, F.segment(lay.q_offset(), lay.nq));
  if (lay.n_mu > 0) add_kinematic_multipliers(t, y.segment(lay.mu_offset(), lay.n_mu), F.segment(lay.q_offset(), lay.nq));
  dynamic_rows(t, vp, F.segment(lay.v_offset(), lay.nv));
  if (lay.n_lambda > 0)
    add_constraint_forces(t, y.segment(lay.lambda_offset(), lay.n_lambda), F.segment(lay.v_offset(), lay.nv));
  for (int b = 0; b < lay.n_blocks; ++b) {
    const ConstraintBlockLayout& blk = lay.blocks[b];
    if (blk.lambda_row >= 0) block_rows(t, blk.kind, blk.rows.lambda_rows, v, qp, vp, F.segment(blk.lambda_row, blk.nr));
    if (blk.mu_row >= 0) block_rows(t, blk.kind, blk.rows.mu_rows, v, qp, vp, F.segment(blk.mu_row, blk.nr));
  }
}

void ConstraintScheme::iteration_matrix(const JacobianInputs& in, IterationMatrixView& J) const {
  add_kinematic_jacobian(in, J);
  add_dynamic_jacobian(in, J);
  for (int b = 0; b < in.lay.n_blocks; ++b) {
    const ConstraintBlockLayout& blk = in.lay.blocks[b];
    if (blk.lambda_row >= 0) add_block_jacobian(in, blk.kind, blk.rows.lambda_rows, blk.lambda_row, J);
    if (blk.mu_row >= 0) add_block_jacobian(in, blk.kind, blk.rows.mu_rows, blk.mu_row, J);
  }
}

void ConstraintScheme::consistent_start(const StandardTerms& t, const UnknownLayout& lay, VecRef y,
                                        VecRef yp) const {
  schemes::consistent_start(t, lay, y, yp);
}

void schemes::consistent_start(const StandardTerms& t, const UnknownLayout& lay, VecRef y, VecRef yp) {
  const int nv = lay.nv;
  const ConstraintBlockLayout* blk = lay.n_blocks > 0 ? &lay.blocks[0] : nullptr;
  if (lay.n_lambda > 0) {
    const int nc = lay.n_lambda;
    BoundedMat<kMaxVelocities + kMaxConstraints, kMaxVelocities + kMaxConstraints> K(nv + nc, nv + nc);
    K.setZero();
    K.topLeftCorner(nv, nv) = t.M;
    K.topRightCorner(nv, nc) = t.G.transpose();
    K.bottomLeftCorner(nc, nv) = t.G;
    // G v' = gamma, or the acceleration the feedback of the lambda rows asks for.
    const LevelWeights& w = blk->rows.lambda_rows;
    const ConstVecRef v = y.segment(lay.v_offset(), nv);
    VecC target = t.gamma;
    if (w.acceleration != 0.0 && (w.velocity != 0.0 || w.position != 0.0))
      target = t.gamma - (w.velocity / w.acceleration) * (t.G * v) - (w.position / w.acceleration) * t.phi;
    BoundedVec<kMaxVelocities + kMaxConstraints> rhs(nv + nc);
    rhs << t.f, target;
    const BoundedVec<kMaxVelocities + kMaxConstraints> sol = K.fullPivLu().solve(rhs);
    yp.segment(lay.v_offset(), nv) = sol.head(nv);
    y.segment(lay.lambda_offset(), nc) = sol.tail(nc);
  } else {
    yp.segment(lay.v_offset(), nv) = t.M.ldlt().solve(t.f);
  }
  yp.segment(lay.q_offset(), lay.nq) = t.qdot;
  if (lay.n_mu > 0) {
    // Phi_q q' = 0 (d/dt Phi on exact data), or the rate the feedback of a
    // Kinematic block's mu rows asks for.
    VecC rate = VecC::Zero(t.phi.size());
    const LevelWeights& w = blk->rows.mu_rows;
    if (blk->kind == ConstraintKind::Kinematic && w.velocity != 0.0 && w.position != 0.0)
      rate = -(w.position / w.velocity) * t.phi;
    const VecC mu = (t.phi_q * t.phi_q.transpose()).ldlt().solve(t.phi_q * t.qdot - rate);
    y.segment(lay.mu_offset(), lay.n_mu) = mu;
    yp.segment(lay.q_offset(), lay.nq) -= t.phi_q.transpose() * mu;
  }
  // Multipliers are algebraic: their derivatives do not enter the residual.
  yp.tail(lay.n_lambda + lay.n_mu).setZero();
}

}  // namespace rigidae
