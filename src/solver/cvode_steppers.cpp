// CVODE behind the ODE driver: Adams-Moulton (orders 1-12, fixed-point
// iteration, no Jacobian; a projection restarts it after the step) and BDF
// (orders 1-5, Newton with CVODE's difference-quotient Jacobian and
// rigidae's dense LU; projection inside the step with its error estimate).
// Two rows of the integrators' table (integrators.cpp).
#include <cvode/cvode.h>
#include <cvode/cvode_ls.h>
#include <cvode/cvode_proj.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include <algorithm>
#include <memory>

#include "dense_lu_solver.hpp"
#include "ode_stepper.hpp"
#include "steppers.hpp"

namespace rigidae::ode {

namespace {

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

struct CvodeCalls {
  RIGIDAE_SHARED_CALLS(CVode)
  static int one_step(void* mem, double t_end, N_Vector x, double& t) { return CVode(mem, t_end, x, &t, CV_ONE_STEP); }
  static constexpr int kRootReturn = CV_ROOT_RETURN;
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
  bool projects_inside_step() const override { return bdf_; }
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

}  // namespace

std::unique_ptr<Stepper> make_cvode_adams(const StepperArgs& a) {
  return std::make_unique<CvodeStepper>(false, a.ctx, a.x0, a.atol, a.opt, a.span, a.data, a.n_events);
}

std::unique_ptr<Stepper> make_cvode_bdf(const StepperArgs& a) {
  return std::make_unique<CvodeStepper>(true, a.ctx, a.x0, a.atol, a.opt, a.span, a.data, a.n_events);
}

}  // namespace rigidae::ode
