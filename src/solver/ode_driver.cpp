// CVODE and ARKODE on an OdeProblem, one internal step at a time (see
// include/rigidae/solver/ode_driver.hpp). The loop mirrors the IDA
// driver's: step, emit the output grid from the integrator's interpolant,
// handle a root (chart switch: restart), record the step, project.
#include "rigidae/solver/ode_driver.hpp"

#include <arkode/arkode_erkstep.h>
#include <cvode/cvode.h>
#include <cvode/cvode_ls.h>
#include <cvode/cvode_proj.h>
#include <fmt/format.h>
#include <sundials/sundials_context.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <memory>

#include "dense_lu_solver.hpp"
#include "rigidae/core/error.hpp"
#include "rigidae/solver/integrators.hpp"
#include "serial_vector.hpp"
#include "stall_watch.hpp"

namespace rigidae {

namespace {

struct CallbackData {
  OdeProblem* problem = nullptr;
  OdeProjection projection;
  std::exception_ptr error;  // never thrown through C; rethrown by the driver
  Eigen::VectorXd scratch;
  // Set by a projection inside the integrator (CVODE-BDF, ARKODE) during
  // the step just taken; the loop records it once the step is accepted.
  bool projected = false;
  OdeDrift drift_before;
};

CallbackData& cb(void* user_data) { return *static_cast<CallbackData*>(user_data); }

int rhs_callback(realtype t, N_Vector x, N_Vector xdot, void* user_data) {
  CallbackData& d = cb(user_data);
  try {
    // The serial layout's data directly (every vector here is serial_vector.hpp's):
    // N_VGetArrayPointer is two calls into Debian's unoptimised library per evaluation.
    return d.problem->rhs(t, NV_DATA_S(x), NV_DATA_S(xdot)) ? 0 : 1;  // 1: retry smaller
  } catch (...) {
    d.error = std::current_exception();
    return -1;
  }
}

int root_callback(realtype t, N_Vector x, realtype* g, void* user_data) {
  CallbackData& d = cb(user_data);
  try {
    d.problem->event_functions(t, N_VGetArrayPointer(x), g);
    return 0;
  } catch (...) {
    d.error = std::current_exception();
    return -1;
  }
}

bool needs_projection(const CallbackData& d, const OdeDrift& drift) {
  return d.projection.every_step || drift.position > d.projection.threshold ||
         drift.velocity > d.projection.threshold;
}

// CVODE-BDF: corr = P(x) - x, and the error estimate onto the tangent space.
int cvode_projection_callback(realtype t, N_Vector ycur, N_Vector corr, realtype /*eps*/, N_Vector err,
                              void* user_data) {
  CallbackData& d = cb(user_data);
  try {
    const double* x = N_VGetArrayPointer(ycur);
    const int n = d.problem->size();
    const OdeDrift drift = d.problem->drift(t, x);
    double* c = N_VGetArrayPointer(corr);
    if (!needs_projection(d, drift)) {
      for (int i = 0; i < n; ++i) c[i] = 0.0;
      return 0;
    }
    d.scratch = Eigen::Map<const Eigen::VectorXd>(x, n);
    d.problem->project(t, d.scratch.data());
    for (int i = 0; i < n; ++i) c[i] = d.scratch[i] - x[i];
    if (err) d.problem->project_error(t, d.scratch.data(), N_VGetArrayPointer(err));
    d.projected = true;
    d.drift_before = drift;
    return 0;
  } catch (...) {
    d.error = std::current_exception();
    return -1;
  }
}

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

// SUNDIALS' flag names are malloc'ed; freed here.
std::string take_name(char* name, int flag) {
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
  virtual void add_counters(IdaCounters& c) = 0;
};

void check(int flag, const char* what) {
  if (flag < 0) throw SolverError(fmt::format("{} failed: flag {}", what, flag));
}

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

struct CvodeCalls {
  RIGIDAE_SHARED_CALLS(CVode)
  static int one_step(void* mem, double t_end, N_Vector x, double& t) { return CVode(mem, t_end, x, &t, CV_ONE_STEP); }
  static constexpr int kRootReturn = CV_ROOT_RETURN;
};

struct ErkStepCalls {
  RIGIDAE_SHARED_CALLS(ERKStep)
  static int one_step(void* mem, double t_end, N_Vector x, double& t) {
    return ERKStepEvolve(mem, t_end, x, &t, ARK_ONE_STEP);
  }
  static constexpr int kRootReturn = ARK_ROOT_RETURN;
};

#undef RIGIDAE_SHARED_CALLS

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

class CvodeStepper final : public SundialsStepper<CvodeCalls> {
 public:
  CvodeStepper(bool bdf, SUNContext ctx, N_Vector x0, N_Vector atol, const SolverSettings& opt, const TimeGrid& span,
               CallbackData& data, int n_events)
      : bdf_(bdf) {
    try {
      create(ctx, x0, atol, opt, span, data, n_events);
    } catch (...) {
      release();
      throw;
    }
  }
  ~CvodeStepper() override { release(); }
  void create(SUNContext ctx, N_Vector x0, N_Vector atol, const SolverSettings& opt, const TimeGrid& span,
              CallbackData& data, int n_events) {
    const double t0 = span.start;
    const bool bdf = bdf_;
    mem_ = CVodeCreate(bdf ? CV_BDF : CV_ADAMS, ctx);
    if (!mem_) throw SolverError("CVodeCreate failed");
    check(CVodeInit(mem_, rhs_callback, t0, x0), "CVodeInit");
    set_common(atol, opt, span, data);
    const int n = static_cast<int>(N_VGetLength(x0));
    if (bdf) {
      // Newton with CVODE's difference-quotient Jacobian and rigidae's LU.
      A_ = SUNDenseMatrix(n, n, ctx);
      LS_ = A_ ? sun::new_dense_lu_solver(x0, A_, ctx) : nullptr;
      if (!LS_) throw SolverError("out of memory creating CVODE's linear solver");
      check(CVodeSetLinearSolver(mem_, LS_, A_), "CVodeSetLinearSolver");
      check(CVodeSetMaxOrd(mem_, std::min(5, opt.max_order)), "CVodeSetMaxOrd");
      if (data.projection.enabled) {
        check(CVodeSetProjFn(mem_, cvode_projection_callback), "CVodeSetProjFn");
        check(CVodeSetProjErrEst(mem_, SUNTRUE), "CVodeSetProjErrEst");
      }
    } else {
      // Adams on a non-stiff ODE: fixed-point iteration, no Jacobian.
      NLS_ = SUNNonlinSol_FixedPoint(x0, 0, ctx);
      if (!NLS_) throw SolverError("out of memory creating CVODE's fixed-point solver");
      check(CVodeSetNonlinearSolver(mem_, NLS_), "CVodeSetNonlinearSolver");
      check(CVodeSetMaxOrd(mem_, 12), "CVodeSetMaxOrd");
    }
    set_roots(n_events);
  }
  void release() {
    if (mem_) CVodeFree(&mem_);
    if (LS_) SUNLinSolFree(LS_);
    if (A_) SUNMatDestroy(A_);
    if (NLS_) SUNNonlinSolFree(NLS_);
  }
  int last_order() override {
    int q = 0;
    CVodeGetLastOrder(mem_, &q);
    return q;
  }
  void reinit(double t, N_Vector x) override { check(CVodeReInit(mem_, t, x), "CVodeReInit"); }
  void add_counters(IdaCounters& c) override {
    add_common_counters(c);
    long v = 0;
    CVodeGetNumNonlinSolvIters(mem_, &v), c.nonlinear_iters += v;
    CVodeGetNumNonlinSolvConvFails(mem_, &v), c.nonlinear_conv_fails += v;
    if (bdf_) {
      CVodeGetNumJacEvals(mem_, &v), c.jacobian_evals += v;
      CVodeGetNumLinRhsEvals(mem_, &v), c.jacobian_residual_evals += v;
      CVodeGetNumLinSolvSetups(mem_, &v), c.linear_setups += v;
    }
  }

 private:
  bool bdf_;
  SUNMatrix A_ = nullptr;
  SUNLinearSolver LS_ = nullptr;
  SUNNonlinearSolver NLS_ = nullptr;
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

struct Vectors {
  SUNContext ctx = nullptr;
  N_Vector x = nullptr, atol = nullptr, dky = nullptr;
  explicit Vectors(int n) {
    if (SUNContext_Create(nullptr, &ctx) != 0) throw SolverError("SUNContext_Create failed");
    x = sun::new_serial_vector(n, ctx);
    atol = sun::new_serial_vector(n, ctx);
    dky = sun::new_serial_vector(n, ctx);
    if (!x || !atol || !dky) throw SolverError("out of memory creating the ODE vectors");
  }
  ~Vectors() {
    for (N_Vector v : {x, atol, dky})
      if (v) N_VDestroy(v);
    if (ctx) SUNContext_Free(&ctx);
  }
  Vectors(const Vectors&) = delete;
  Vectors& operator=(const Vectors&) = delete;
};

void forward_events(OdeProblem& problem, RunResult& result, StepSink& sink, IdaCounters& counters) {
  for (const EventNote& e : problem.take_events()) {
    if (e.what == "chart_switch") {
      ++result.switch_count;
      if (result.switches.size() < kSwitchesKept) result.switches.push_back({e.t, e.from, e.to, e.margin});
    } else if (e.what == "projection") {
      ++counters.projections;
    }
    sink.on_event(e);
  }
}

EventNote projection_note(double t, const OdeDrift& before) {
  EventNote e;
  e.t = t;
  e.what = "projection";
  e.drift_position = before.position;
  e.drift_velocity = before.velocity;
  return e;
}

}  // namespace

RunResult integrate_ode(OdeProblem& problem, const SolverSettings& opt, const TimeGrid& span, const OdeMethod& method,
                        StepSink& sink) {
  const IntegratorInfo& info = find_integrator(method.integrator);
  if (!info.is_ode) throw InputError(fmt::format("integrate_ode: '{}' is not an ODE integrator", method.integrator));
  const int n = problem.size();

  RunResult result;
  CallbackData data;
  data.problem = &problem;
  data.projection = method.projection;
  if (!problem.has_invariants()) data.projection.enabled = false;
  data.scratch.resize(n);

  Vectors vec(n);
  Eigen::VectorXd x;
  problem.initial_state(span.start, x);
  Eigen::Map<Eigen::VectorXd> x_sun(N_VGetArrayPointer(vec.x), n);
  x_sun = x;
  {
    Eigen::VectorXd atol(n);
    problem.absolute_tolerances(opt.rtol, opt.atol, x, atol);
    Eigen::Map<Eigen::VectorXd>(N_VGetArrayPointer(vec.atol), n) = atol;
  }
  {
    Eigen::VectorXd f(n);
    problem.rhs(span.start, x.data(), f.data());  // an ODE start is consistent by construction
    result.initial_residual = 0.0;
  }

  const bool adams = method.integrator == "cvode-adams";
  std::unique_ptr<Stepper> stepper;
  if (method.integrator == "arkode-erk")
    stepper = std::make_unique<ArkodeStepper>(find_erk_method(method.erk_method), vec.ctx, vec.x, vec.atol, opt, span,
                                              data, problem.event_count());
  else
    stepper = std::make_unique<CvodeStepper>(!adams, vec.ctx, vec.x, vec.atol, opt, span, data,
                                             problem.event_count());

  IdaCounters before_restart;
  forward_events(problem, result, sink, before_restart);

  const OutputGrid grid(span);
  std::size_t next_out = 0;
  Eigen::VectorXd y_obs;
  problem.observe(span.start, x.data(), y_obs);
  sink.on_output(span.start, y_obs);  // the start, always (a recorder writes it when it is an output time)
  if (grid[0] <= span.start) ++next_out;

  Eigen::VectorXd xout(n);
  const bool every_output = sink.needs_every_output();
  auto emit_grid_until = [&](double t) {
    while (next_out < grid.size() && grid[next_out] <= t) {
      if (!every_output && next_out + 1 < grid.size()) {  // not the last point: not wanted
        ++next_out;
        continue;
      }
      const double t_out = grid[next_out];
      if (stepper->dky(t_out, vec.dky) < 0) break;
      xout = Eigen::Map<const Eigen::VectorXd>(N_VGetArrayPointer(vec.dky), n);
      problem.observe(t_out, xout.data(), y_obs);
      sink.on_output(t_out, y_obs);
      ++next_out;
    }
  };
  auto restart = [&](double t) {
    x_sun = x;
    stepper->add_counters(before_restart);
    stepper->reinit(t, vec.x);
    ++before_restart.restarts;
  };

  double t = span.start;
  long steps_total = 0;
  StallWatch stall;  // accepted steps below the step-size floor
  double last_accepted_h = 0.0;
  const auto started = std::chrono::steady_clock::now();
  while (t < span.end) {
    if (g_interrupt_requested.load()) {
      result.status = RunStatus::Interrupted;
      result.message = interrupt_message(t, last_accepted_h, steps_total);
      break;
    }
    if (opt.wall_time_limit > 0 &&
        std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count() >= opt.wall_time_limit) {
      result.status = RunStatus::Failed;
      result.message = timeout_message(opt.wall_time_limit, t, span.end, last_accepted_h, steps_total);
      break;
    }
    if (steps_total >= opt.max_steps) {
      // The last accepted step: after a restart (Adams' projection) the integrator's own is 0.
      const double h = last_accepted_h;
      result.status = RunStatus::Failed;
      result.message = fmt::format(
          "too much work: max_steps = {} internal steps taken and t = {:.9g} s of {:.9g} s reached, last step "
          "size {:.3g} s (raise --max-steps or solver.max_steps, or loosen the tolerances)",
          opt.max_steps, t, span.end, h);
      break;
    }
    data.projected = false;
    const int flag = stepper->step(span.end, vec.x, t);
    if (data.error) std::rethrow_exception(data.error);
    if (flag < 0) {
      const double tcur = stepper->current_time();
      result.status = RunStatus::Failed;
      result.message = fmt::format("{} failed with {} at t = {:.9g} s, last step size {:.3g} s", method.integrator,
                                   stepper->flag_name(flag), tcur, stepper->last_step());
      t = tcur;
      break;
    }
    emit_grid_until(t);
    x = x_sun;
    if (stepper->root_found(flag)) {
      const StepAction a = problem.on_event(t, x);
      if (a.kind == StepAction::Kind::Fail) {
        result.status = RunStatus::Failed;
        result.message = a.message;
        break;
      }
      forward_events(problem, result, sink, before_restart);
      if (a.kind == StepAction::Kind::Restart) restart(t);
      continue;
    }
    ++steps_total;
    problem.after_step(t, x.data());
    forward_events(problem, result, sink, before_restart);  // a mechanism's row_subset / singular_pose notes
    if (data.projected) {  // inside the step (CVODE-BDF, ARKODE)
      ++before_restart.projections;
      sink.on_event(projection_note(t, data.drift_before));
    }
    problem.observe(t, x.data(), y_obs);
    sink.on_step(t, stepper->last_step(), stepper->last_order(), y_obs);
    const double h_taken = stepper->last_step();
    last_accepted_h = h_taken;
    if (stall.stalled(h_taken, step_floor(opt, span, t), t >= span.end)) {
      result.status = RunStatus::Failed;
      result.message = stall_message(opt, span, t, h_taken, steps_total, method.integrator,
                                     problem.describe_stall(t, x.data()));
      break;
    }
    if (adams && data.projection.enabled && t < span.end) {
      // CVODE projects inside the step for BDF only: Adams restarts.
      const OdeDrift d = problem.drift(t, x.data());
      if (d.position > data.projection.threshold || d.velocity > data.projection.threshold) {
        problem.project(t, x.data());
        restart(t);
        ++before_restart.projections;
        sink.on_event(projection_note(t, d));
      }
    }
  }

  result.t_reached = t;
  result.counters = before_restart;
  stepper->add_counters(result.counters);
  result.counters.last_step = stepper->last_step();
  result.counters.last_order = stepper->last_order();
  return result;
}

}  // namespace rigidae
