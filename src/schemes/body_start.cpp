// One body's dense consistent start (equations in
// include/rigidae/schemes/body_rows.hpp): the multibody model's start for
// the bodies of a system without joints, a one-body scene's among them. Its
// arithmetic is the deleted one-body model's, which the single-body pins
// were recorded with.
#include "rigidae/schemes/body_rows.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>

namespace rigidae::schemes {

void consistent_start(const StandardTerms& t, const BodyLayout& lay, VecRef y, VecRef yp) {
  const int nv = lay.nv;
  if (lay.n_lambda > 0) {
    const int nc = lay.n_lambda;
    BoundedMat<kMaxVelocities + kMaxConstraints, kMaxVelocities + kMaxConstraints> K(nv + nc, nv + nc);
    K.setZero();
    K.topLeftCorner(nv, nv) = t.M;
    K.topRightCorner(nv, nc) = t.G.transpose();
    K.bottomLeftCorner(nc, nv) = t.G;
    // G v' = gamma, or the acceleration the feedback of the lambda rows asks for.
    const LevelWeights& w = lay.lambda_rows;
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
    const LevelWeights& w = lay.mu_rows;
    if (lay.kind == ConstraintKind::Kinematic && w.velocity != 0.0 && w.position != 0.0)
      rate = -(w.position / w.velocity) * t.phi;
    const VecC mu = (t.phi_q * t.phi_q.transpose()).ldlt().solve(t.phi_q * t.qdot - rate);
    y.segment(lay.mu_offset(), lay.n_mu) = mu;
    yp.segment(lay.q_offset(), lay.nq) -= t.phi_q.transpose() * mu;
  }
  // Multipliers are algebraic: their derivatives do not enter the residual.
  yp.tail(lay.n_lambda + lay.n_mu).setZero();
}

}  // namespace rigidae::schemes
