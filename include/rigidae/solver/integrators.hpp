#pragma once
// The integrators rigidae offers, and which constraint schemes and explicit
// Runge-Kutta tables go with which: the one place that says so.
//
//   ida          every scheme (the DAE forms)
//   cvode-adams  index1, projection (the ODE form; see ode_driver.hpp)
//   cvode-bdf    index1, projection
//   arkode-erk   index1, projection; --erk-method one of erk_method_names()
//
// index1 on an ODE integrator is the plain ODE (drift recorded, never
// removed); projection adds the projection onto the invariants.
#include <memory>
#include <string>
#include <vector>

namespace rigidae {

namespace ode {
class Stepper;      // an ODE integrator behind the driver (src/solver/ode_stepper.hpp)
struct StepperArgs;
struct ButcherTable;
}  // namespace ode

struct IntegratorInfo {
  std::string name;
  std::string description;
  bool is_ode = false;              // runs the ODE form (OdeProblem), not the DAE
  std::vector<std::string> schemes;  // valid schemes; empty = every registered scheme
  // The ODE driver's stepper (its own file in src/solver); null for IDA.
  std::unique_ptr<ode::Stepper> (*make_stepper)(const ode::StepperArgs&) = nullptr;
};

struct ErkMethodInfo {
  std::string name;         // rigidae's name
  std::string arkode_name;  // ARKODE 6.4's table (ARKodeButcherTable_LoadERK), or empty and:
  const ode::ButcherTable& (*own_table)() = nullptr;  // a table ARKODE is given (src/solver/butcher_table.hpp)
  int order = 0;            // of the propagated solution
  int stages = 0;
};

const std::vector<IntegratorInfo>& integrators();
const std::vector<ErkMethodInfo>& erk_methods();
std::vector<std::string> integrator_names();
std::vector<std::string> erk_method_names();

// InputError (naming `where`, the valid values) for an unknown integrator,
// an unknown ERK method, or a scheme the integrator does not run.
const IntegratorInfo& find_integrator(const std::string& name, const std::string& where = "");
const ErkMethodInfo& find_erk_method(const std::string& name, const std::string& where = "");
void check_integrator_scheme(const std::string& integrator, const std::string& scheme, const std::string& where = "");

}  // namespace rigidae
