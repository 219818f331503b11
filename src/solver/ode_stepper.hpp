#pragma once
// What the ODE driver (ode_driver.cpp) and the integrators behind it share
// (internal to src/solver): the callbacks' data, the SUNDIALS callbacks that
// call the OdeProblem, and the Stepper interface each integrator implements
// in its own file (cvode_steppers.cpp, arkode_stepper.cpp), registered by a
// row of the table in integrators.cpp (its factory declared in steppers.hpp).
#include <fmt/format.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>

#include <cstdlib>
#include <exception>
#include <string>

#include <Eigen/Core>

#include "rigidae/core/error.hpp"
#include "rigidae/solver/ode_driver.hpp"

namespace rigidae::ode {

struct CallbackData {
  OdeProblem* problem = nullptr;
  OdeProjection projection;
  std::exception_ptr error;  // never thrown through C; rethrown by the driver
  Eigen::VectorXd scratch;
  // Set by a projection inside the integrator (CVODE-BDF, ARKODE) during
  // the step just taken; the loop records it once the step is accepted.
  bool projected = false;
  OdeDrift drift_before;
  // The error weights' tolerances, for a stepper that computes the weights
  // itself (arkode_stepper.cpp).
  double rtol = 0.0;
  N_Vector atol = nullptr;
};

inline CallbackData& cb(void* user_data) { return *static_cast<CallbackData*>(user_data); }

// x' = f(t, x) and the event functions g(t, x): the problem's, errors kept in
// CallbackData::error (never thrown through C). Defined in ode_driver.cpp.
int rhs_callback(realtype t, N_Vector x, N_Vector xdot, void* user_data);
int root_callback(realtype t, N_Vector x, realtype* g, void* user_data);

inline bool needs_projection(const CallbackData& d, const OdeDrift& drift) {
  return d.projection.every_step || drift.position > d.projection.threshold ||
         drift.velocity > d.projection.threshold;
}

inline void check(int flag, const char* what) {
  if (flag < 0) throw SolverError(fmt::format("{} failed: flag {}", what, flag));
}

// SUNDIALS' flag names are malloc'ed; freed here.
inline std::string take_name(char* name, int flag) {
  std::string s = name ? name : fmt::format("flag {}", flag);
  std::free(name);
  return s;
}

// The integrator behind the loop.
class Stepper {
 public:
  virtual ~Stepper() = default;
  // One internal step towards t_end: the SUNDIALS flag (< 0 failure).
  virtual int step(double t_end, N_Vector x, double& t) = 0;
  virtual bool root_found(int flag) const = 0;
  virtual std::string flag_name(int flag) const = 0;
  virtual int dky(double t, N_Vector out) = 0;
  virtual double last_step() = 0;
  virtual int last_order() = 0;
  virtual double current_time() = 0;
  virtual void reinit(double t, N_Vector x) = 0;
  // The time the integrator stops at (the end, or short of a singular pose).
  virtual void set_stop_time(double t) = 0;
  virtual void add_counters(IdaCounters& c) = 0;
  // Whether a projection happens inside the step (the integrator's own
  // projection or post-step hook); else the loop projects after an
  // accepted step and restarts the integrator (CVODE-Adams).
  virtual bool projects_inside_step() const { return true; }
};

// What a stepper's factory receives: the method, SUNDIALS' context, the
// initial state and absolute tolerances, the run settings, the callbacks' data.
struct StepperArgs {
  const OdeMethod& method;
  SUNContext ctx;
  N_Vector x0, atol;
  const SolverSettings& opt;
  const TimeGrid& span;
  CallbackData& data;
  int n_events;
};

// The functions of CVODE and of ARKODE's ERKStep that differ only in their
// prefix (SUNDIALS 6.4: the same arguments, the same flags), with the names
// that errors report; for SundialsStepper.
#define RIGIDAE_SHARED_CALLS(PREFIX)                                   \
  static constexpr auto tolerances = &PREFIX##SVtolerances;            \
  static constexpr auto user_data = &PREFIX##SetUserData;              \
  static constexpr auto stop_time = &PREFIX##SetStopTime;              \
  static constexpr auto root_init = &PREFIX##RootInit;                 \
  static constexpr const char* kTolerances = #PREFIX "SVtolerances";   \
  static constexpr const char* kUserData = #PREFIX "SetUserData";      \
  static constexpr const char* kStopTime = #PREFIX "SetStopTime";      \
  static constexpr const char* kRootInit = #PREFIX "RootInit";         \
  static constexpr auto flag_name = &PREFIX##GetReturnFlagName;        \
  static constexpr auto dky = &PREFIX##GetDky;                         \
  static constexpr auto last_step = &PREFIX##GetLastStep;              \
  static constexpr auto current_time = &PREFIX##GetCurrentTime;        \
  static constexpr auto num_steps = &PREFIX##GetNumSteps;              \
  static constexpr auto num_rhs_evals = &PREFIX##GetNumRhsEvals;       \
  static constexpr auto num_error_test_fails = &PREFIX##GetNumErrTestFails; \
  static constexpr auto num_root_evals = &PREFIX##GetNumGEvals;

// What CVODE and ERKStep do alike, once: the shared settings, the step, the
// interpolant, the step size and time, the shared counters. `Calls` names the
// integrator's functions (compile-time constants: direct calls).
template <typename Calls>
class SundialsStepper : public Stepper {
 public:
  int step(double t_end, N_Vector x, double& t) override { return Calls::one_step(mem_, t_end, x, t); }
  bool root_found(int flag) const override { return flag == Calls::kRootReturn; }
  std::string flag_name(int flag) const override { return take_name(Calls::flag_name(flag), flag); }
  int dky(double t, N_Vector out) override { return Calls::dky(mem_, t, 0, out); }
  double last_step() override {
    double h = 0.0;
    Calls::last_step(mem_, &h);
    return h;
  }
  double current_time() override {
    double t = 0.0;
    Calls::current_time(mem_, &t);
    return t;
  }
  void set_stop_time(double t) override { check(Calls::stop_time(mem_, t), Calls::kStopTime); }

 protected:
  // The tolerances, the callbacks' data and the stop time.
  void set_common(N_Vector atol, const SolverSettings& opt, const TimeGrid& span, CallbackData& data) {
    check(Calls::tolerances(mem_, opt.rtol, atol), Calls::kTolerances);
    check(Calls::user_data(mem_, &data), Calls::kUserData);
    check(Calls::stop_time(mem_, span.end), Calls::kStopTime);
  }
  // The event functions (chart switches), when there are any.
  void set_roots(int n_events) {
    has_roots_ = n_events > 0;
    if (has_roots_) check(Calls::root_init(mem_, n_events, root_callback), Calls::kRootInit);
  }
  void add_common_counters(IdaCounters& c) {
    long v = 0;
    Calls::num_steps(mem_, &v), c.steps += v;
    Calls::num_rhs_evals(mem_, &v), c.residual_evals += v;
    Calls::num_error_test_fails(mem_, &v), c.error_test_fails += v;
    if (has_roots_) Calls::num_root_evals(mem_, &v), c.root_evals += v;
  }

  void* mem_ = nullptr;
  bool has_roots_ = false;
};

}  // namespace rigidae::ode
