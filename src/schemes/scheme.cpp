// What every scheme shares: the default note.
#include "rigidae/schemes/scheme.hpp"

namespace rigidae {

std::string ConstraintScheme::note(const Representation& rep) const {
  if (rep.nc() == 0) return "Euler angles have no constraints: scheme '" + name() + "' leaves the ODE as it is";
  return constrained_note(rep);
}

}  // namespace rigidae
