// ARKODE's explicit Runge-Kutta (ERKStep) behind the ODE driver: the
// Butcher table the run names (erk_method, integrators.cpp), the projection
// as a post-step hook. One row of the integrators' table (integrators.cpp).
#include <arkode/arkode_erkstep.h>

#include <memory>

#include "ode_stepper.hpp"
#include "rigidae/solver/integrators.hpp"
#include "steppers.hpp"

namespace rigidae::ode {

namespace {

// ARKODE: after each accepted step, in place (installed for every ERK run: see configure()).
int arkode_postprocess_callback(realtype t, N_Vector y, void* user_data) {
  CallbackData& d = cb(user_data);
  try {
    if (!d.projection.enabled) return 0;
    double* x = N_VGetArrayPointer(y);
    const OdeDrift drift = d.problem->drift(t, x);
    if (!needs_projection(d, drift)) return 0;
    d.problem->project(t, x);
    d.projected = true;
    d.drift_before = drift;
    return 0;
  } catch (...) {
    d.error = std::current_exception();
    return -1;
  }
}

struct ErkStepCalls {
  RIGIDAE_SHARED_CALLS(ERKStep)
  static int one_step(void* mem, double t_end, N_Vector x, double& t) {
    return ERKStepEvolve(mem, t_end, x, &t, ARK_ONE_STEP);
  }
  static constexpr int kRootReturn = ARK_ROOT_RETURN;
};


class ArkodeStepper final : public SundialsStepper<ErkStepCalls> {
 public:
  ArkodeStepper(const ErkMethodInfo& method, SUNContext ctx, N_Vector x0, N_Vector atol, const SolverSettings& opt,
                const TimeGrid& span, CallbackData& data, int n_events)
      : order_(method.order) {
    mem_ = ERKStepCreate(rhs_callback, span.start, x0, ctx);
    if (!mem_) throw SolverError("ERKStepCreate failed");
    try {
      configure(method, atol, opt, span, data, n_events);
    } catch (...) {
      ERKStepFree(&mem_);
      throw;
    }
  }
  void configure(const ErkMethodInfo& method, N_Vector atol, const SolverSettings& opt, const TimeGrid& span,
                 CallbackData& data, int n_events) {
    set_common(atol, opt, span, data);
    check(ERKStepSetTableName(mem_, method.arkode_name.c_str()), "ERKStepSetTableName");
    // Installed also without a projection (then a no-op): with a step
    // postprocess ARKODE 6.4 evaluates f afresh at each step's start instead
    // of reusing the last one, and its error estimates and step sizes are
    // then those of the projected runs. Without it the plain ODE (index1)
    // took 1.7-2.3x the steps on the heavy top (1,085 / 2,146 / 2,562 steps at
    // rtol 1e-7 / 1e-8 / 1e-9 against 732 / 944 / 1,140; docs/benchmarks.md,
    // issue 23), for one more evaluation per step.
    check(ERKStepSetPostprocessStepFn(mem_, arkode_postprocess_callback), "ERKStepSetPostprocessStepFn");
    set_roots(n_events);
  }
  ~ArkodeStepper() override { ERKStepFree(&mem_); }
  int last_order() override { return order_; }
  void reinit(double t, N_Vector x) override { check(ERKStepReInit(mem_, rhs_callback, t, x), "ERKStepReInit"); }
  void add_counters(IdaCounters& c) override { add_common_counters(c); }

 private:
  int order_;
};

}  // namespace

std::unique_ptr<Stepper> make_arkode_erk(const StepperArgs& a) {
  return std::make_unique<ArkodeStepper>(find_erk_method(a.method.erk_method), a.ctx, a.x0, a.atol, a.opt, a.span,
                                         a.data, a.n_events);
}

}  // namespace rigidae::ode
