#include "rigidae/solver/ida_driver.hpp"

#include <fmt/format.h>
#include <ida/ida.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_config.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunlinsol/sunlinsol_klu.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include <algorithm>
#include <chrono>
#include <limits>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <exception>
#include <optional>
#include <utility>

#include "dense_lu_solver.hpp"
#include "ida_newton_test.hpp"
#include "central_differences.hpp"
#include "rigidae/core/error.hpp"
#include "serial_vector.hpp"
#include "stall_watch.hpp"
#include "stop_time.hpp"
#include "rigidae/solver/version.hpp"

namespace rigidae {

std::atomic<bool> g_interrupt_requested{false};
std::atomic<int> g_interrupt_signal{0};

std::string interrupt_cause() {
  switch (g_interrupt_signal.load()) {
    case 0: return "a request to stop";
    case SIGINT: return "SIGINT (Ctrl-C)";
    case SIGTERM: return "SIGTERM";
    default: return fmt::format("signal {}", g_interrupt_signal.load());
  }
}

std::string timeout_message(double limit_s, double t, double t_end, double last_step, long steps) {
  return fmt::format("timed out: the wall-time limit of {:g} s per run (compare --run-timeout) was reached at t = "
                     "{:.9g} s of {:.9g} s, last step size {:.3g} s, after {} steps; the steps so far are kept",
                     limit_s, t, t_end, last_step, steps);
}

double step_floor(const SolverSettings& s, const TimeGrid& span, double t) {
  return s.min_step_fraction * std::max(span.end - span.start, std::abs(t));
}

std::string stall_message(const SolverSettings& s, const TimeGrid& span, double t, double h, long steps,
                          const std::string& integrator, const std::string& problem_says) {
  const double floor = step_floor(s, span, t);
  return fmt::format(
      "step size collapsed ({}): {} or more steps in a row below the floor at t = {:.9g} s of {:.9g} s, last step size "
      "{:.3g} s < floor {:.3g} s (solver.min_step_fraction = {:g} x max(|end - start|, |t|) = {:.3g} s), after {} "
      "steps; at that step size the rest would take about {:.3g} more steps.{}{} Likely cause: a singularity of the "
      "formulation near this state (a gimbal lock, a mechanism at a dead point, constraint rows losing rank), or "
      "tolerances too tight for it; try another coordinates/scheme, looser tolerances, or --min-step-fraction 0 to "
      "let it creep on",
      integrator, kStalledSteps, t, span.end, h, floor, s.min_step_fraction,
      std::max(span.end - span.start, std::abs(t)), steps, h > 0 ? (span.end - t) / h : 0.0,
      problem_says.empty() ? "" : " ", problem_says);
}

std::string interrupt_message(double t, double last_step, long steps) {
  return fmt::format("interrupted by {} at t = {:.9g} s, last step size {:.3g} s, after {} steps; the steps so far "
                     "are kept",
                     interrupt_cause(), t, last_step, steps);
}

std::string sundials_version() { return SUNDIALS_VERSION; }

std::string to_string(RunStatus s) {
  switch (s) {
    case RunStatus::Success: return "success";
    case RunStatus::Failed: return "failed";
    case RunStatus::Interrupted: return "interrupted";
  }
  return "?";
}

OutputGrid::OutputGrid(const TimeGrid& grid) : grid_(grid) {
  if (!grid.output_times.empty()) {  // given times: exactly those
    n_inner_ = grid.output_times.size() - 1;
    return;
  }
  const double span = grid.end - grid.start;
  const long n = static_cast<long>(std::floor(span / grid.output_step * (1 + 1e-12)));
  // Points start + k step for k = 0..n, less any that falls on (or within
  // round-off of) the end, which is always the last point.
  long inner = n + 1;
  while (inner > 1 && grid.start + static_cast<double>(inner - 1) * grid.output_step >= grid.end - 1e-9 * grid.output_step)
    --inner;
  n_inner_ = static_cast<std::size_t>(inner);
}

double OutputGrid::operator[](std::size_t k) const {
  if (!grid_.output_times.empty()) return grid_.output_times[k];
  return k < n_inner_ ? grid_.start + static_cast<double>(k) * grid_.output_step : grid_.end;
}

std::vector<double> output_grid(const TimeGrid& grid) {
  const OutputGrid g(grid);
  std::vector<double> ts(g.size());
  for (std::size_t k = 0; k < g.size(); ++k) ts[k] = g[k];
  return ts;
}

namespace {

using solver::CentralDifferences;

// Owns the SUNDIALS objects of one run; frees them in any case.
struct IdaSession {
  SUNContext ctx = nullptr;
  N_Vector y = nullptr, yp = nullptr, id = nullptr, atol = nullptr, dky = nullptr;
  N_Vector unchecked = nullptr;  // 1 - id: the algebraic unknowns (ida_newton_test.hpp)
  SUNMatrix A = nullptr;
  SUNLinearSolver LS = nullptr;
  void* mem = nullptr;
  SUNNonlinearSolver NLS = nullptr;  // Newton with rigidae's convergence test (ida_newton_test.hpp)
  sun::IdaNewtonTest newton_test;

  // nnz > 0: a sparse (CSC) matrix with that many entries and KLU.
  IdaSession(int n, long nnz) {
    if (SUNContext_Create(nullptr, &ctx) != 0) throw SolverError("SUNContext_Create failed");
    // rigidae's serial vectors and dense LU (compiled with our flags; same
    // arithmetic as SUNDIALS' serial vector and dense solver); KLU for sparse.
    y = sun::new_serial_vector(n, ctx);
    yp = sun::new_serial_vector(n, ctx);
    id = sun::new_serial_vector(n, ctx);
    atol = sun::new_serial_vector(n, ctx);
    dky = sun::new_serial_vector(n, ctx);
    unchecked = sun::new_serial_vector(n, ctx);
    A = nnz > 0 ? SUNSparseMatrix(n, n, nnz, CSC_MAT, ctx) : SUNDenseMatrix(n, n, ctx);
    LS = !A ? nullptr : nnz > 0 ? SUNLinSol_KLU(y, A, ctx) : sun::new_dense_lu_solver(y, A, ctx);
    // KLU's fill-reducing ordering: AMD on A + A^T, not SUNDIALS' default
    // COLAMD, whose fill on the multibody saddle-point matrices grew faster
    // than the number of bodies (docs/benchmarks.md, "N-link chain").
    if (LS && nnz > 0) SUNLinSol_KLUSetOrdering(LS, 0);
    mem = IDACreate(ctx);
    if (!y || !yp || !id || !atol || !dky || !unchecked || !A || !LS || !mem)
      throw SolverError("out of memory creating IDA");
  }
  ~IdaSession() {
    if (mem) IDAFree(&mem);
    if (NLS) SUNNonlinSolFree(NLS);
    if (LS) SUNLinSolFree(LS);
    if (A) SUNMatDestroy(A);
    for (N_Vector v : {y, yp, id, atol, dky, unchecked})
      if (v) N_VDestroy(v);
    if (ctx) SUNContext_Free(&ctx);
  }
  IdaSession(const IdaSession&) = delete;
  IdaSession& operator=(const IdaSession&) = delete;
};

static_assert(sizeof(sunindextype) == sizeof(std::int64_t), "SparsityPattern holds 64-bit indices (Debian's SUNDIALS)");

// What IDA's callbacks reach through user_data.
struct CallbackData {
  DaeProblem* problem = nullptr;
  const SparsityPattern* pattern = nullptr;   // null: dense linear algebra
  CentralDifferences* differences = nullptr;  // null: the problem's exact matrix
  std::exception_ptr error;                   // never thrown through C; rethrown by the driver
};

int residual_callback(realtype t, N_Vector yy, N_Vector yp, N_Vector rr, void* user_data) {
  auto* data = static_cast<CallbackData*>(user_data);
  try {
    DaeProblem& p = *data->problem;
    const bool finite = p.residual(t, N_VGetArrayPointer(yy), N_VGetArrayPointer(yp), N_VGetArrayPointer(rr));
    return finite ? 0 : 1;  // 1 is recoverable: IDA retries with a smaller step
  } catch (...) {
    data->error = std::current_exception();
    return -1;
  }
}

int jacobian_callback(realtype t, realtype cj, N_Vector yy, N_Vector yp, N_Vector /*rr*/, SUNMatrix J,
                      void* user_data, N_Vector /*t1*/, N_Vector /*t2*/, N_Vector /*t3*/) {
  auto* data = static_cast<CallbackData*>(user_data);
  try {
    DaeProblem& p = *data->problem;
    const double* y = N_VGetArrayPointer(yy);
    const double* ypp = N_VGetArrayPointer(yp);
    if (!data->pattern) {
      double* M = SUNDenseMatrix_Data(J);
      if (data->differences)
        data->differences->dense(p, t, cj, y, ypp, M);
      else
        p.iteration_matrix_dense(t, cj, y, ypp, M);
      return 0;
    }
    // IDA zeroes the whole sparse matrix, structure included, before each call.
    const SparsityPattern& pattern = *data->pattern;
    std::copy(pattern.col_start.begin(), pattern.col_start.end(), SUNSparseMatrix_IndexPointers(J));
    std::copy(pattern.rows.begin(), pattern.rows.end(), SUNSparseMatrix_IndexValues(J));
    double* values = SUNSparseMatrix_Data(J);
    if (data->differences)
      data->differences->sparse(p, pattern, t, cj, y, ypp, values);
    else
      p.iteration_matrix_sparse(t, cj, y, ypp, values);
    return 0;
  } catch (...) {
    data->error = std::current_exception();
    return -1;
  }
}

int event_callback(realtype t, N_Vector yy, N_Vector /*yp*/, realtype* g, void* user_data) {
  auto* data = static_cast<CallbackData*>(user_data);
  try {
    data->problem->event_functions(t, N_VGetArrayPointer(yy), g);
    return 0;
  } catch (...) {
    data->error = std::current_exception();
    return -1;
  }
}

// IDA's own messages. Left alone, IDA prints "[IDA ERROR] ..." to stderr
// beside rigidae's explanation; instead the handler keeps the latest text
// (IDA calls it synchronously, on the thread inside IDASolve) and it is
// folded into rigidae's failure message.
thread_local std::string t_ida_said;

void keep_ida_message(int code, const char* /*module*/, const char* function, char* msg, void* /*data*/) {
  try {
    t_ida_said = fmt::format("{}{}: {}", code == IDA_WARNING ? "warning in " : "", function ? function : "IDA",
                             msg ? msg : "");
  } catch (...) {  // nothing may be thrown through C
  }
}

// " (IDA: ...)" when IDA said something, else nothing.
std::string what_ida_said() { return t_ida_said.empty() ? "" : fmt::format(" (IDA: {})", t_ida_said); }

// IDA's name for a return flag. IDAGetReturnFlagName mallocs the string and
// leaves freeing it to the caller (found by LeakSanitizer, tools/sanitize.sh).
std::string flag_name(int flag) {
  char* name = IDAGetReturnFlagName(flag);
  std::string s = name ? name : fmt::format("flag {}", flag);
  std::free(name);
  return s;
}

void check(int flag, const char* what) {
  if (flag < 0) throw SolverError(fmt::format("{} failed: {}{}", what, flag_name(flag), what_ida_said()));
}

void add_counters(void* mem, IdaCounters& c) {
  long v = 0;
  IDAGetNumSteps(mem, &v), c.steps += v;
  IDAGetNumResEvals(mem, &v), c.residual_evals += v;
  IDAGetNumJacEvals(mem, &v), c.jacobian_evals += v;
  IDAGetNumLinResEvals(mem, &v), c.jacobian_residual_evals += v;
  IDAGetNumNonlinSolvIters(mem, &v), c.nonlinear_iters += v;
  IDAGetNumNonlinSolvConvFails(mem, &v), c.nonlinear_conv_fails += v;
  IDAGetNumErrTestFails(mem, &v), c.error_test_fails += v;
  IDAGetNumLinSolvSetups(mem, &v), c.linear_setups += v;
  IDAGetNumGEvals(mem, &v), c.root_evals += v;
}

// Plain words for IDA's failure flags, with the usual cause.
// `suppressed`: whether the run leaves its algebraic unknowns out of the
// error test (every shipped scheme does); the index-2/3 hint fits only a run
// that does not.
std::string explain_failure(int flag, bool suppressed) {
  switch (flag) {
    case IDA_TOO_MUCH_WORK: return "too much work before reaching the output time";
    case IDA_TOO_MUCH_ACC: return "the requested accuracy is below what round-off allows (raise rtol/atol)";
    case IDA_ERR_FAIL:
      return "repeated error-test failures (the step kept shrinking: a singularity, or tolerances too tight "
             "for this formulation)";
    case IDA_CONV_FAIL:
      return suppressed ? "repeated Newton convergence failures (the iteration matrix is singular or the problem is "
                          "stiffer than the step allows)"
                        : "repeated Newton convergence failures (the iteration matrix is singular or the problem is "
                          "stiffer than the step allows; an index-2/3 form without error-test suppression fails like "
                          "this)";
    case IDA_LSETUP_FAIL: return "the linear solver setup failed (singular iteration matrix)";
    case IDA_LSOLVE_FAIL: return "the linear solve failed";
    case IDA_RES_FAIL: return "the residual reported an unrecoverable error";
    case IDA_REP_RES_ERR: return "the residual kept returning non-finite values";
    case IDA_CONSTR_FAIL: return "an inequality constraint could not be met";
    case IDA_ILL_INPUT:
      return "IDA rejected an input it cannot use (weighted norms overflow with an extremely small atol)";
    case IDA_BAD_EWT: return "an error weight became zero or negative (rtol |y| + atol = 0 for some unknown)";
    case IDA_FIRST_RES_FAIL: return "the residual failed at the first call (an impossible start)";
    case IDA_NO_RECOVERY: return "the residual failed recoverably and IDA could not recover";
    case IDA_LINIT_FAIL: return "the linear solver could not be initialised";
    case IDA_NLS_INIT_FAIL:
    case IDA_NLS_SETUP_FAIL:
    case IDA_NLS_FAIL: return "the nonlinear solver failed unrecoverably";
    case IDA_MEM_FAIL: return "out of memory";
    default: return "IDA stopped";
  }
}

// A first step whose order-1 local error, h^2/2 |y''|, meets the tolerance.
// IDA's own guess (0.5 / |y'| in the weighted norm) is far smaller on a fast
// spinning body (|y'| / rtol ~ 1e10), and index-2 iteration matrices become
// numerically singular at tiny steps (their condition grows like 1/h^2).
// y'' of the state comes from a difference of consistent y' along a short
// explicit step.
double first_step_estimate(DaeProblem& p, double t0, const Eigen::VectorXd& y, const Eigen::VectorXd& yp,
                           const SolverSettings& opt, double span) {
  const int nd = p.state_size();
  const double rate = yp.head(nd).cwiseAbs().maxCoeff();
  const double delta = rate > 0 ? std::min(1e-4 * span, 1e-3 / rate) : 1e-4 * span;
  Eigen::VectorXd y1 = y + delta * yp, yp1;
  p.make_consistent(t0 + delta, y1, yp1);
  const Eigen::VectorXd ydd = (yp1.head(nd) - yp.head(nd)) / delta;
  const Eigen::VectorXd w = (opt.rtol * y.head(nd).cwiseAbs()).array() + opt.atol;
  const double norm = std::sqrt((ydd.cwiseQuotient(w)).squaredNorm() / nd);
  const double h = norm > 0 ? std::sqrt(2.0 / norm) : 1e-3 * span;
  return std::min(h, 1e-3 * span);
}

// One run of IDA over the time grid: the steps of the method as methods.
class IdaRun {
 public:
  IdaRun(DaeProblem& problem, const SolverSettings& opt, const TimeGrid& span, StepSink& sink)
      : problem_(problem), opt_(opt), span_(span), sink_(sink), n_(problem.size()),
        ida_(n_, opt.linear_solver == "klu" ? problem.sparsity().nnz() : 0),
        y_ida_(N_VGetArrayPointer(ida_.y), n_), yp_ida_(N_VGetArrayPointer(ida_.yp), n_), grid_(span),
        yout_(n_) {
    data_.problem = &problem_;
    if (opt.linear_solver == "klu") data_.pattern = &problem_.sparsity();
    if (opt.jacobian == "central") {
      differences_.emplace(n_);
      data_.differences = &*differences_;
    }
  }

  // A consistent start, IDA set up on it, the first output point.
  void start();
  // Whether the run goes on: not at the end, not interrupted, within max_steps.
  bool running();
  // One internal IDA step; false when IDA failed (the result says why).
  bool advance_one_step();
  // Whether that step stopped at a root of the problem's event functions.
  bool at_event() const { return flag_ == IDA_ROOT_RETURN; }
  // The problem's event (a root of its event functions) at t.
  void handle_event();
  // After an accepted step: record it, then the problem's after-step action.
  void after_step();
  RunResult finish();

 private:
  // Carries out what the problem asked for at t, then forwards its events.
  void apply(const StepAction& action);
  // Hands (y, y') at t back to IDA as a new start with first step h0.
  void restart(double h0);
  // The problem bridged (t, t_landing]: the output grid inside from its
  // bridged states, the landing recorded as a step of order 0.
  void land_bridge(double t_landing);
  // IDA's stop time: the problem's hint (a singular pose ahead) or the end.
  void follow_stop_hint();
  // Output-grid points up to t, interpolated from IDA's last step.
  void emit_grid_until(double t);
  void forward_events();
  double last_step() const;
  void fail(std::string message) {
    result_.status = RunStatus::Failed;
    result_.message = std::move(message);
    stopped_ = true;
  }

  DaeProblem& problem_;
  const SolverSettings& opt_;
  const TimeGrid& span_;
  StepSink& sink_;
  const int n_;
  IdaSession ida_;
  Eigen::Map<Eigen::VectorXd> y_ida_, yp_ida_;  // IDA's own y and y'
  std::optional<CentralDifferences> differences_;
  CallbackData data_;
  const OutputGrid grid_;
  std::size_t next_out_ = 0;

  RunResult result_;
  Eigen::VectorXd y_, yp_, yout_;
  double t_ = 0.0;
  int flag_ = 0;                // of the last IDASolve
  long steps_total_ = 0;
  IdaCounters before_restart_;  // counters of the segments before the last IDAReInit
  double stop_time_ = 0.0;      // IDA's stop time as last set
  bool stopped_ = false;
  StallWatch stall_;  // accepted steps below the step-size floor
  std::chrono::steady_clock::time_point started_ = std::chrono::steady_clock::now();
};

void IdaRun::start() {
  t_ = span_.start;
  problem_.initial_state(t_, y_, yp_);
  forward_events();  // a chart chosen at the start

  y_ida_ = y_;
  yp_ida_ = yp_;
  problem_.differential_id(Eigen::Map<Eigen::VectorXd>(N_VGetArrayPointer(ida_.id), n_));
  problem_.absolute_tolerances(opt_.rtol, opt_.atol, y_, Eigen::Map<Eigen::VectorXd>(N_VGetArrayPointer(ida_.atol), n_));
  {
    Eigen::VectorXd F(n_);
    problem_.residual(t_, y_.data(), yp_.data(), F.data());
    result_.initial_residual = F.cwiseAbs().maxCoeff();
  }

  void* mem = ida_.mem;
  t_ida_said.clear();
  check(IDASetErrHandlerFn(mem, keep_ida_message, nullptr), "IDASetErrHandlerFn");
  check(IDAInit(mem, residual_callback, t_, ida_.y, ida_.yp), "IDAInit");
  const bool suppressed = problem_.suppress_algebraic_error_test();
  if (suppressed) {
    N_VScale(-1.0, ida_.id, ida_.unchecked);
    N_VAddConst(ida_.unchecked, 1.0, ida_.unchecked);
  }
  ida_.NLS = sun::attach_newton(mem, ida_.y, ida_.ctx, suppressed ? ida_.unchecked : nullptr, ida_.newton_test);
  if (!ida_.NLS) throw SolverError("IDA: attaching the Newton solver failed");
  // Unknowns held at a fixed value count in IDA's root-mean-square norms
  // without ever carrying an error: tighten rtol and atol by the square root
  // of their share so that the norms over the others are as without them.
  const double held_share = std::sqrt(static_cast<double>(n_ - problem_.held_unknowns()) / n_);
  if (held_share < 1.0)
    Eigen::Map<Eigen::VectorXd>(N_VGetArrayPointer(ida_.atol), n_) *= held_share;
  check(IDASVtolerances(mem, opt_.rtol * held_share, ida_.atol), "IDASVtolerances");
  check(IDASetUserData(mem, &data_), "IDASetUserData");
  check(IDASetId(mem, ida_.id), "IDASetId");
  check(IDASetSuppressAlg(mem, problem_.suppress_algebraic_error_test() ? SUNTRUE : SUNFALSE), "IDASetSuppressAlg");
  check(IDASetLinearSolver(mem, ida_.LS, ida_.A), "IDASetLinearSolver");
  if (opt_.jacobian != "ida_dq") check(IDASetJacFn(mem, jacobian_callback), "IDASetJacFn");
  check(IDASetMaxOrd(mem, opt_.max_order), "IDASetMaxOrd");
  check(IDASetStopTime(mem, span_.end), "IDASetStopTime");
  stop_time_ = span_.end;
  const double h0 = opt_.initial_step > 0 ? opt_.initial_step
                                          : first_step_estimate(problem_, t_, y_, yp_, opt_, span_.end - span_.start);
  check(IDASetInitStep(mem, h0), "IDASetInitStep");
  if (problem_.event_count() > 0) check(IDARootInit(mem, problem_.event_count(), event_callback), "IDARootInit");

  sink_.on_output(t_, y_);  // the start, always (a recorder writes it when it is an output time)
  next_out_ = grid_[0] <= t_ ? 1 : 0;
}

bool IdaRun::running() {
  if (stopped_ || t_ >= span_.end) return false;
  if (g_interrupt_requested.load()) {
    result_.status = RunStatus::Interrupted;
    result_.message = interrupt_message(t_, last_step(), steps_total_);
    return false;
  }
  if (opt_.wall_time_limit > 0 &&
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count() >= opt_.wall_time_limit) {
    fail(timeout_message(opt_.wall_time_limit, t_, span_.end, last_step(), steps_total_));
    return false;
  }
  if (steps_total_ >= opt_.max_steps) {
    // IDA's own limit (IDA_TOO_MUCH_WORK) counts steps per call; one step per call, rigidae counts the run.
    const double h = last_step();
    fail(fmt::format(
        "too much work (IDA_TOO_MUCH_WORK): max_steps = {} internal steps taken and t = {:.9g} s of {:.9g} s "
        "reached, last step size {:.3g} s; at that step size the rest would take about {:.3g} more steps. "
        "Likely cause: {}",
        opt_.max_steps, t_, span_.end, h, h > 0 ? (span_.end - t_) / h : 0.0,
        h > 0 && h < 1e-9 * (span_.end - span_.start)
            ? "the step size has collapsed (a near-singularity, or tolerances too tight for this formulation)"
            : "the run is longer or faster than max_steps allows (raise --max-steps or solver.max_steps)"));
    return false;
  }
  return true;
}

bool IdaRun::advance_one_step() {
  flag_ = IDASolve(ida_.mem, span_.end, &t_, ida_.y, ida_.yp, IDA_ONE_STEP);
  if (data_.error) std::rethrow_exception(data_.error);
  if (flag_ < 0) {
    double h = 0.0, tcur = t_;
    IDAGetCurrentStep(ida_.mem, &h);
    IDAGetCurrentTime(ida_.mem, &tcur);
    t_ = tcur;
    // Repeated Newton failures: what the problem knows at the last accepted
    // state (a mechanism names the joints whose rows lost rank there).
    std::string why;
    if (flag_ == IDA_CONV_FAIL || flag_ == IDA_ERR_FAIL) {
      const std::string d = problem_.describe_stall(t_, N_VGetArrayPointer(ida_.y));
      if (!d.empty()) why = " " + d;
    }
    fail(fmt::format("IDA failed with {} at t = {:.9g} s, step size {:.3g} s: {}{}{}", flag_name(flag_), tcur, h,
                     explain_failure(flag_, problem_.suppress_algebraic_error_test()), what_ida_said(), why));
    return false;
  }
  emit_grid_until(t_);
  return true;
}

void IdaRun::handle_event() {
  y_ = y_ida_;
  yp_ = yp_ida_;
  apply(problem_.on_event(t_, last_step(), y_, yp_));
  if (!stopped_) follow_stop_hint();
}

void IdaRun::after_step() {
  ++steps_total_;
  double h = 0.0;
  int order = 0;
  IDAGetLastStep(ida_.mem, &h);
  IDAGetLastOrder(ida_.mem, &order);
  y_ = y_ida_;
  sink_.on_step(t_, h, order, y_);
  // The step-size floor: steps this small make no progress on the scene's
  // time scale; a run creeping at them would take max_steps to fail.
  if (stall_.stalled(h, step_floor(opt_, span_, t_), t_ >= span_.end)) {
    fail(stall_message(opt_, span_, t_, h, steps_total_, "ida", problem_.describe_stall(t_, y_.data())));
    return;
  }
  if (t_ < span_.end) {
    yp_ = yp_ida_;
    apply(problem_.after_step(t_, h, y_, yp_));
    if (!stopped_) follow_stop_hint();
  }
}

void IdaRun::follow_stop_hint() {
  const double stop = next_stop_time(problem_.stop_time_hint(), t_, span_.end);
  // IDA forgets its stop time once it returns there (IDA_TSTOP_RETURN) and
  // keeps it across IDAReInit: set again when it was reached or changes.
  if (stop == stop_time_ && flag_ != IDA_TSTOP_RETURN) return;
  check(IDASetStopTime(ida_.mem, stop), "IDASetStopTime");
  stop_time_ = stop;
}

void IdaRun::land_bridge(double t_landing) {
  const bool every = sink_.needs_every_output();
  while (next_out_ < grid_.size() && grid_[next_out_] <= t_landing) {
    if (!every && next_out_ + 1 < grid_.size()) {
      ++next_out_;
      continue;
    }
    problem_.bridged_state(grid_[next_out_], yout_);
    sink_.on_output(grid_[next_out_], yout_);
    ++next_out_;
  }
  const double h = t_landing - t_;
  t_ = t_landing;
  sink_.on_step(t_, h, 0, y_);
}

void IdaRun::apply(const StepAction& action) {
  switch (action.kind) {
    case StepAction::Kind::Continue: break;
    case StepAction::Kind::Fail: fail(action.message); break;
    case StepAction::Kind::Restart:
      if (action.bridge_to > t_) land_bridge(action.bridge_to);
      // IDA keeps no memory across the restart: the order and the history
      // are lost; the problem says whether the step size is carried over.
      restart(action.restart_step > 0
                  ? action.restart_step
                  : first_step_estimate(problem_, t_, y_, yp_, opt_, span_.end - span_.start));
      if (action.projected) ++before_restart_.projections;
      break;
  }
  forward_events();
}

void IdaRun::restart(double h0) {
  y_ida_ = y_;
  yp_ida_ = yp_;
  add_counters(ida_.mem, before_restart_);
  check(IDAReInit(ida_.mem, t_, ida_.y, ida_.yp), "IDAReInit");
  check(IDASetInitStep(ida_.mem, h0), "IDASetInitStep");
  stop_time_ = std::numeric_limits<double>::quiet_NaN();  // set again after the restart
  ++before_restart_.restarts;
}

void IdaRun::emit_grid_until(double t) {
  const bool every = sink_.needs_every_output();
  while (next_out_ < grid_.size() && grid_[next_out_] <= t) {
    if (!every && next_out_ + 1 < grid_.size()) {  // not the last point: not wanted
      ++next_out_;
      continue;
    }
    const double t_out = grid_[next_out_];
    if (IDAGetDky(ida_.mem, t_out, 0, ida_.dky) < 0) break;
    yout_ = Eigen::Map<const Eigen::VectorXd>(N_VGetArrayPointer(ida_.dky), n_);
    sink_.on_output(t_out, yout_);
    ++next_out_;
  }
}

void IdaRun::forward_events() {
  for (const EventNote& note : problem_.take_events()) {
    if (note.what == "chart_switch") {
      ++result_.switch_count;
      if (result_.switches.size() < kSwitchesKept) result_.switches.push_back({note.t, note.from, note.to, note.margin});
    }
    sink_.on_event(note);
  }
}

double IdaRun::last_step() const {
  double h = 0.0;
  IDAGetLastStep(ida_.mem, &h);
  return h;
}

RunResult IdaRun::finish() {
  result_.t_reached = t_;
  result_.counters = before_restart_;
  add_counters(ida_.mem, result_.counters);
  result_.counters.jacobian_residual_evals += problem_.own_residual_evaluations();
  if (differences_) result_.counters.jacobian_residual_evals += differences_->residual_evaluations();
  IDAGetLastStep(ida_.mem, &result_.counters.last_step);
  IDAGetLastOrder(ida_.mem, &result_.counters.last_order);
  result_.linear_solver = opt_.linear_solver;
  // The fill of KLU's factors: with the matrix's own nonzeros, what tells a
  // good ordering from a bad one as the mechanism grows (bench/chain.sh).
  if (opt_.linear_solver == "klu")
    if (const auto* numeric = SUNLinSol_KLUGetNumeric(ida_.LS))
      result_.factor_nonzeros = static_cast<long>(numeric->lnz + numeric->unz);
  return result_;
}

}  // namespace

std::string resolve_linear_solver(const SolverSettings& settings, const DaeProblem& problem) {
  if (settings.linear_solver != "auto") return settings.linear_solver;
  if (settings.jacobian == "ida_dq") return "dense";
  return problem.size() >= kKluFromUnknowns ? "klu" : "dense";
}

RunResult integrate(DaeProblem& problem, const SolverSettings& requested, const TimeGrid& time, StepSink& sink) {
  if (requested.linear_solver == "klu" && requested.jacobian == "ida_dq")
    throw InputError("solver.linear_solver = \"klu\" needs solver.jacobian = \"exact\" or \"central\": IDA's "
                     "difference quotients fill dense and banded matrices only");
  SolverSettings settings = requested;
  settings.linear_solver = resolve_linear_solver(requested, problem);
  IdaRun run(problem, settings, time, sink);
  run.start();
  while (run.running()) {
    if (!run.advance_one_step()) break;
    if (run.at_event())
      run.handle_event();
    else
      run.after_step();
  }
  return run.finish();
}

}  // namespace rigidae
