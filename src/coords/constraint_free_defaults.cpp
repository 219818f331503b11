// The defaults of a representation without constraints and with one chart.
#include "rigidae/coords/representation.hpp"

#include <stdexcept>

namespace rigidae {

void Representation::constraint_hessian_weighted(const VecQ& /*q*/, const VecC& /*m*/, MatQQ& out) const {
  out.setZero(nq(), nq());
}

void Representation::constraint_hessian_applied(const VecQ& /*q*/, const VecQ& /*w*/, MatCQ& out) const {
  out.resize(0, nq());
}

std::unique_ptr<Representation> Representation::in_chart(int /*c*/) const {
  throw std::logic_error(name() + " has one chart only");
}

}  // namespace rigidae
