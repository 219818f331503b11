// The constraint second derivatives of a representation without constraints.
#include "rigidae/coords/representation.hpp"

namespace rigidae {

void Representation::constraint_hessian_weighted(const VecQ& /*q*/, const VecC& /*m*/, MatQQ& out) const {
  out.setZero(nq(), nq());
}

void Representation::constraint_hessian_applied(const VecQ& /*q*/, const VecQ& /*w*/, MatCQ& out) const {
  out.resize(0, nq());
}

}  // namespace rigidae
