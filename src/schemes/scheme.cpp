// What every scheme shares: the consistent start and the default note.
#include "rigidae/schemes/scheme.hpp"

namespace rigidae {

std::string ConstraintScheme::note(const Representation& rep) const {
  if (rep.nc() == 0) return "Euler angles have no constraints: scheme '" + name() + "' leaves the ODE as it is";
  return constrained_note(rep);
}

VecC ConstraintScheme::acceleration_target(const StandardTerms& t, const ConstVecRef& /*v*/) const { return t.gamma; }

VecC ConstraintScheme::rate_target(const StandardTerms& t) const { return VecC::Zero(t.phi.size()); }

void ConstraintScheme::consistent_start(const StandardTerms& t, const UnknownLayout& lay, VecRef y,
                                        VecRef yp) const {
  const int nv = lay.nv;
  if (lay.n_lambda > 0) {
    const int nc = lay.n_lambda;
    BoundedMat<kMaxVelocities + kMaxConstraints, kMaxVelocities + kMaxConstraints> K(nv + nc, nv + nc);
    K.setZero();
    K.topLeftCorner(nv, nv) = t.M;
    K.topRightCorner(nv, nc) = t.G.transpose();
    K.bottomLeftCorner(nc, nv) = t.G;
    BoundedVec<kMaxVelocities + kMaxConstraints> rhs(nv + nc);
    rhs << t.f, acceleration_target(t, y.segment(lay.v_offset(), nv));
    const BoundedVec<kMaxVelocities + kMaxConstraints> sol = K.fullPivLu().solve(rhs);
    yp.segment(lay.v_offset(), nv) = sol.head(nv);
    y.segment(lay.lambda_offset(), nc) = sol.tail(nc);
  } else {
    yp.segment(lay.v_offset(), nv) = t.M.ldlt().solve(t.f);
  }
  yp.segment(lay.q_offset(), lay.nq) = t.qdot;
  if (lay.n_mu > 0) {
    const VecC mu = (t.phi_q * t.phi_q.transpose()).ldlt().solve(t.phi_q * t.qdot - rate_target(t));
    y.segment(lay.mu_offset(), lay.n_mu) = mu;
    yp.segment(lay.q_offset(), lay.nq) -= t.phi_q.transpose() * mu;
  }
  // Multipliers are algebraic: their derivatives do not enter the residual.
  yp.tail(lay.n_lambda + lay.n_mu).setZero();
}

}  // namespace rigidae
