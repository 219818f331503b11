// The table of integrators and ERK methods (see integrators.hpp).
#include "rigidae/solver/integrators.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>

#include "rigidae/core/error.hpp"
#include "butcher_table.hpp"
#include "ode_stepper.hpp"
#include "steppers.hpp"

namespace rigidae {

const std::vector<IntegratorInfo>& integrators() {
  static const std::vector<IntegratorInfo> table = {
      {"ida", "SUNDIALS IDA, BDF orders 1-5 on the DAE", false, {}, nullptr},
      {"cvode-adams", "SUNDIALS CVODE, Adams-Moulton orders 1-12 on the ODE form", true, {"index1", "projection"},
       ode::make_cvode_adams},
      {"cvode-bdf", "SUNDIALS CVODE, BDF orders 1-5 on the ODE form", true, {"index1", "projection"},
       ode::make_cvode_bdf},
      {"arkode-erk", "SUNDIALS ARKODE, explicit Runge-Kutta on the ODE form", true, {"index1", "projection"},
       ode::make_arkode_erk},
  };
  return table;
}

// ARKODE 6.4's eighth-order pair is Fehlberg's 13-stage 7(8), its Verner
// table the 8-stage 6(5); Prince and Dormand's 8(7) is rigidae's own
// (butcher_table.hpp, for the error estimate Fehlberg's lacks).
const std::vector<ErkMethodInfo>& erk_methods() {
  static const std::vector<ErkMethodInfo> table = {
      {"dopri87", "", ode::prince_dormand_87, 8, 13},
      {"fehlberg78", "ARKODE_FEHLBERG_13_7_8", nullptr, 8, 13},
      {"verner65", "ARKODE_VERNER_8_5_6", nullptr, 6, 8},
      {"dopri5", "ARKODE_DORMAND_PRINCE_7_4_5", nullptr, 5, 7},
  };
  return table;
}

std::vector<std::string> integrator_names() {
  std::vector<std::string> out;
  for (const auto& i : integrators()) out.push_back(i.name);
  return out;
}

std::vector<std::string> erk_method_names() {
  std::vector<std::string> out;
  for (const auto& m : erk_methods()) out.push_back(m.name);
  return out;
}

namespace {
std::string prefix(const std::string& where) { return where.empty() ? "" : where + ": "; }
}  // namespace

const IntegratorInfo& find_integrator(const std::string& name, const std::string& where) {
  for (const auto& i : integrators())
    if (i.name == name) return i;
  throw InputError(fmt::format("{}unknown integrator '{}'; valid: {}", prefix(where), name,
                               fmt::join(integrator_names(), ", ")));
}

const ErkMethodInfo& find_erk_method(const std::string& name, const std::string& where) {
  for (const auto& m : erk_methods())
    if (m.name == name) return m;
  throw InputError(fmt::format("{}unknown explicit Runge-Kutta method '{}'; valid: {}", prefix(where), name,
                               fmt::join(erk_method_names(), ", ")));
}

void check_integrator_scheme(const std::string& integrator, const std::string& scheme, const std::string& where) {
  const IntegratorInfo& i = find_integrator(integrator, where);
  // An empty list is every scheme (whose names the scheme setting checks).
  const std::vector<std::string>& valid = i.schemes;
  if (!valid.empty() && std::find(valid.begin(), valid.end(), scheme) == valid.end())
    throw InputError(fmt::format("{}integrator '{}' does not run scheme '{}'; valid schemes with {}: {}", prefix(where),
                                 integrator, scheme, integrator, fmt::join(valid, ", ")));
}

}  // namespace rigidae
