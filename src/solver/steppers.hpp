#pragma once
// The ODE integrators' factories (one file each: cvode_steppers.cpp,
// arkode_stepper.cpp), for the table in integrators.cpp (internal to src/solver).
#include <memory>

namespace rigidae::ode {

class Stepper;
struct StepperArgs;

std::unique_ptr<Stepper> make_cvode_adams(const StepperArgs& args);
std::unique_ptr<Stepper> make_cvode_bdf(const StepperArgs& args);
std::unique_ptr<Stepper> make_arkode_erk(const StepperArgs& args);

}  // namespace rigidae::ode
