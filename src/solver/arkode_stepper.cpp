// ARKODE's explicit Runge-Kutta (ERKStep) behind the ODE driver: the
// Butcher table the run names (erk_method, integrators.cpp), the projection
// as a post-step hook. One row of the integrators' table (integrators.cpp).
#include <arkode/arkode_erkstep.h>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "butcher_table.hpp"
#include "ode_stepper.hpp"
#include "rigidae/core/hermite.hpp"
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

// The error weights w_i = 1 / (rtol |y_i| + atol_i), the arithmetic of
// ARKODE's own (arkEwtSetSV: N_VAbs, N_VLinearSum with factor 1, N_VInv),
// hence the same bits, in one pass here instead of four vector calls through
// Debian's unoptimised ARKODE (1.4 % of the heavy top's instructions).
// Non-positive rtol |y_i| + atol_i: -1, as ARKODE's.
int arkode_error_weights(N_Vector y, N_Vector w, void* user_data) {
  const CallbackData& d = cb(user_data);
  const double* yd = NV_DATA_S(y);
  const double* ad = NV_DATA_S(d.atol);
  double* wd = NV_DATA_S(w);
  bool positive = true;
  for (sunindextype i = 0, n = NV_LENGTH_S(y); i < n; ++i) {
    const double s = d.rtol * std::fabs(yd[i]) + ad[i];
    positive &= s > 0.0;
    wd[i] = 1.0 / s;
  }
  return positive ? 0 : -1;
}

// The run's Butcher table on an ERKStep memory: one of ARKODE's by name, or
// one of rigidae's own (butcher_table.hpp), which ARKODE copies.
void set_table(void* mem, const ErkMethodInfo& method, const char* what) {
  if (!method.own_table) {
    check(ERKStepSetTableName(mem, method.arkode_name.c_str()), what);
    return;
  }
  const ButcherTable& t = method.own_table();
  ARKodeButcherTable B = ARKodeButcherTable_Create(t.stages, t.order, t.embedded_order, const_cast<double*>(t.c.data()),
                                                   const_cast<double*>(t.a.data()), const_cast<double*>(t.b.data()),
                                                   const_cast<double*>(t.d.data()));
  if (!B) throw SolverError(fmt::format("{}: ARKodeButcherTable_Create failed", what));
  const int flag = ERKStepSetTable(mem, B);
  ARKodeButcherTable_Free(B);
  check(flag, what);
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
      if (order_ > kHermiteExactOrder) make_restep(method, x0, ctx, data);  // its tolerances: data.rtol, data.atol
    } catch (...) {
      free_all();
      throw;
    }
  }
  void configure(const ErkMethodInfo& method, N_Vector atol, const SolverSettings& opt, const TimeGrid& span,
                 CallbackData& data, int n_events) {
    set_common(atol, opt, span, data);
    data.rtol = opt.rtol;
    data.atol = atol;
    check(ERKStepWFtolerances(mem_, arkode_error_weights), "ERKStepWFtolerances");
    set_table(mem_, method, "ERKStepSetTable");
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
  ~ArkodeStepper() override { free_all(); }
  int last_order() override { return order_; }
  void reinit(double t, N_Vector x) override { check(ERKStepReInit(mem_, rhs_callback, t, x), "ERKStepReInit"); }
  void add_counters(IdaCounters& c) override {
    add_common_counters(c);
    c.residual_evals += restep_rhs_;  // the output grid's steps are work of the run too
    restep_rhs_ = 0;                  // counted: a restart's caller adds the counters once
  }

  // Each step's start is kept for the dense output (below).
  int step(double t_end, N_Vector x, double& t) override {
    if (restep_) {
      N_VScale(1.0, x, start_y_);
      start_t_ = current_time();
    }
    return SundialsStepper::step(t_end, x, t);
  }

  // Dense output. ARKODE's Hermite interpolant has degree 5 at most (error
  // ~ h^6): for tables of higher order it is less accurate than the steps
  // (particle_pendulum.toml, Fehlberg 7(8) at rtol 1e-10 over 10 periods:
  // 1.7e-6 m off on the grid, 1.8e-9 m at the last step). Inside a step,
  // such a table integrates again from the step's start to t, with the same
  // table and tolerances, trying the whole way in one step: shorter than the
  // accepted step, so one step almost always passes, and error-controlled
  // where it does not (a fixed step would not be: the run's steps can be
  // long, 0.49 s across singular_linkage's collinear pose in euler/lagrange
  // at rtol 1e-6, and the stages of a shorter one fall elsewhere). The
  // run's own steps are left as they were: stopping at each output time
  // instead changed the step-size controller's sequence and made the steps'
  // own error 7x larger on particle_pendulum.
  int dky(double t, N_Vector out) override {
    const double t_now = current_time();
    if (!restep_ || !(t > start_t_) || t >= t_now) return SundialsStepper::dky(t, out);
    if (integrate_to(t, out) >= 0) return 0;
    // A right-hand side that cannot be evaluated at t itself (singular_linkage
    // in euler/lagrange at rtol 1e-6: the run steps from 0.12 s to 0.61 s over
    // its Euler charts' lock at 0.25 s, where the Lagrange form's matrix is
    // singular and the grid has a row): the cubic Hermite interpolant
    // (core/hermite.hpp) between two integrated points 1 % of the step to
    // either side, their derivatives from the right-hand side (error
    // ~ (0.02 h)^4 / 384 x^(4)).
    // ARKODE's own interpolant over the whole step put that row 2.8e-2 m off.
    const double d = 0.01 * (t_now - start_t_);
    const double ta = std::max(start_t_, t - d), tb = std::min(t_now, t + d);
    if (ta < t && t < tb && integrate_to(ta, ya_) >= 0 && integrate_to(tb, yb_) >= 0 &&
        rhs_callback(ta, ya_, fa_, data_) == 0 && rhs_callback(tb, yb_, fb_, data_) == 0) {
      restep_rhs_ += 2;
      const auto vec = [](N_Vector v) {
        return Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(NV_DATA_S(v), NV_LENGTH_S(v)));
      };
      const Eigen::VectorXd ya = vec(ya_), yb = vec(yb_), fa = vec(fa_), fb = vec(fb_);
      std::vector<double> z;
      std::vector<Eigen::VectorXd> c;
      hermite_coefficients({ta, tb}, {&ya, &yb}, {&fa, &fb}, static_cast<int>(ya.size()), z, c);
      Eigen::VectorXd value;
      hermite_value(z, c, t, value, nullptr);
      Eigen::Map<Eigen::VectorXd>(NV_DATA_S(out), NV_LENGTH_S(out)) = value;
      return 0;
    }
    return SundialsStepper::dky(t, out);  // nothing better: the interpolant
  }

 private:
  // ARKODE's Hermite interpolant is exact for polynomials of degree 5.
  static constexpr int kHermiteExactOrder = 5;

  // The dense output's integration from the last step's start to t, with
  // the run's table and tolerances, the whole way as the first try.
  int integrate_to(double t, N_Vector out) {
    check(ERKStepReInit(restep_, rhs_callback, start_t_, start_y_), "ERKStepReInit (dense output)");
    check(ERKStepSetInitStep(restep_, t - start_t_), "ERKStepSetInitStep (dense output)");
    check(ERKStepSetStopTime(restep_, t), "ERKStepSetStopTime (dense output)");
    double reached = start_t_;
    const int flag = ERKStepEvolve(restep_, t, out, &reached, ARK_NORMAL);
    long evals = 0;
    ERKStepGetNumRhsEvals(restep_, &evals);
    restep_rhs_ += evals;
    return flag;
  }

  void make_restep(const ErkMethodInfo& method, N_Vector x0, SUNContext ctx, CallbackData& data) {
    data_ = &data;
    start_y_ = N_VClone(x0);
    ya_ = N_VClone(x0);
    yb_ = N_VClone(x0);
    fa_ = N_VClone(x0);
    fb_ = N_VClone(x0);
    if (!start_y_ || !ya_ || !yb_ || !fa_ || !fb_) throw SolverError("N_VClone failed (dense output)");
    restep_ = ERKStepCreate(rhs_callback, 0.0, x0, ctx);
    if (!restep_) throw SolverError("ERKStepCreate failed (dense output)");
    set_table(restep_, method, "ERKStepSetTable (dense output)");
    check(ERKStepSetUserData(restep_, &data), "ERKStepSetUserData (dense output)");
    check(ERKStepWFtolerances(restep_, arkode_error_weights), "ERKStepWFtolerances (dense output)");
    // Its failures fall back to the interpolant (dky): not printed.
    check(ERKStepSetErrHandlerFn(restep_, ignore_arkode_message, nullptr), "ERKStepSetErrHandlerFn (dense output)");
  }
  static void ignore_arkode_message(int, const char*, const char*, char*, void*) {}
  void free_all() {
    if (mem_) ERKStepFree(&mem_);
    if (restep_) ERKStepFree(&restep_);
    for (N_Vector* v : {&start_y_, &ya_, &yb_, &fa_, &fb_}) {
      if (*v) N_VDestroy(*v);
      *v = nullptr;
    }
  }

  int order_;
  void* restep_ = nullptr;      // the dense output's own integrator (tables above kHermiteExactOrder)
  N_Vector start_y_ = nullptr;  // the last step's start
  N_Vector ya_ = nullptr, yb_ = nullptr, fa_ = nullptr, fb_ = nullptr;  // the fallback's two points
  CallbackData* data_ = nullptr;
  double start_t_ = 0.0;
  long restep_rhs_ = 0;         // right-hand sides of the dense output, not yet counted
};

}  // namespace

std::unique_ptr<Stepper> make_arkode_erk(const StepperArgs& a) {
  return std::make_unique<ArkodeStepper>(find_erk_method(a.method.erk_method), a.ctx, a.x0, a.atol, a.opt, a.span,
                                         a.data, a.n_events);
}

}  // namespace rigidae::ode
