#include "rigidae/solver/ida_driver.hpp"

#include <fmt/format.h>
#include <ida/ida.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunlinsol/sunlinsol_klu.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <exception>

#include "dense_lu_solver.hpp"
#include "rigidae/core/error.hpp"
#include "serial_vector.hpp"

namespace rigidae {

std::atomic<bool> g_interrupt_requested{false};

std::string to_string(RunStatus s) {
  switch (s) {
    case RunStatus::Success: return "success";
    case RunStatus::Failed: return "failed";
    case RunStatus::Interrupted: return "interrupted";
  }
  return "?";
}

OutputGrid::OutputGrid(const TimeGrid& grid) : grid_(grid) {
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
  return k < n_inner_ ? grid_.start + static_cast<double>(k) * grid_.output_step : grid_.end;
}

std::vector<double> output_grid(const TimeGrid& grid) {
  const OutputGrid g(grid);
  std::vector<double> ts(g.size());
  for (std::size_t k = 0; k < g.size(); ++k) ts[k] = g[k];
  return ts;
}

namespace {

// Owns the SUNDIALS objects of one run; frees them in any case.
struct IdaSession {
  SUNContext ctx = nullptr;
  N_Vector y = nullptr, yp = nullptr, id = nullptr, atol = nullptr, dky = nullptr;
  SUNMatrix A = nullptr;
  SUNLinearSolver LS = nullptr;
  void* mem = nullptr;

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
    A = nnz > 0 ? SUNSparseMatrix(n, n, nnz, CSC_MAT, ctx) : SUNDenseMatrix(n, n, ctx);
    LS = !A ? nullptr : nnz > 0 ? SUNLinSol_KLU(y, A, ctx) : sun::new_dense_lu_solver(y, A, ctx);
    mem = IDACreate(ctx);
    if (!y || !yp || !id || !atol || !dky || !A || !LS || !mem) throw SolverError("out of memory creating IDA");
  }
  ~IdaSession() {
    if (mem) IDAFree(&mem);
    if (LS) SUNLinSolFree(LS);
    if (A) SUNMatDestroy(A);
    for (N_Vector v : {y, yp, id, atol, dky})
      if (v) N_VDestroy(v);
    if (ctx) SUNContext_Free(&ctx);
  }
  IdaSession(const IdaSession&) = delete;
  IdaSession& operator=(const IdaSession&) = delete;
};

// The iteration matrix's nonzero pattern in compressed sparse columns.
struct SparsePattern {
  std::vector<sunindextype> col_start;  // n + 1
  std::vector<sunindextype> rows;       // nnz, ascending within a column
};

SparsePattern sparse_pattern(const DaeSystem& dae) {
  SparsePattern p;
  const int n = dae.size();
  p.col_start.push_back(0);
  for (int c = 0; c < n; ++c) {
    for (int r = 0; r < n; ++r)
      if (dae.structurally_nonzero(r, c)) p.rows.push_back(r);
    p.col_start.push_back(static_cast<sunindextype>(p.rows.size()));
  }
  return p;
}

struct CallbackData {
  const DaeSystem* dae = nullptr;
  double threshold = 0.0;
  bool exact_jacobian = true;  // else central differences
  SparsePattern pattern;       // empty for dense linear algebra
  std::vector<double> dense;   // n x n scratch when the matrix is sparse
  std::exception_ptr error;    // never thrown through C; rethrown by the driver
};

int residual_callback(realtype t, N_Vector yy, N_Vector yp, N_Vector rr, void* user_data) {
  auto* data = static_cast<CallbackData*>(user_data);
  try {
    data->dae->residual(t, N_VGetArrayPointer(yy), N_VGetArrayPointer(yp), N_VGetArrayPointer(rr));
    const double* F = N_VGetArrayPointer(rr);
    for (int i = 0, n = data->dae->size(); i < n; ++i)
      if (!std::isfinite(F[i])) return 1;  // recoverable: IDA retries with a smaller step
    return 0;
  } catch (...) {
    data->error = std::current_exception();
    return -1;
  }
}

int jacobian_callback(realtype t, realtype cj, N_Vector yy, N_Vector yp, N_Vector /*rr*/, SUNMatrix J,
                      void* user_data, N_Vector /*t1*/, N_Vector /*t2*/, N_Vector /*t3*/) {
  auto* data = static_cast<CallbackData*>(user_data);
  try {
    const bool sparse = !data->pattern.rows.empty();
    double* M = sparse ? data->dense.data() : SUNDenseMatrix_Data(J);
    if (data->exact_jacobian)
      data->dae->iteration_matrix(t, cj, N_VGetArrayPointer(yy), N_VGetArrayPointer(yp), M);
    else
      data->dae->iteration_matrix_central(t, cj, N_VGetArrayPointer(yy), N_VGetArrayPointer(yp), M);
    if (sparse) {
      // IDA zeroes the whole sparse matrix, structure included, before each call.
      const SparsePattern& p = data->pattern;
      const std::size_t n = p.col_start.size() - 1;
      std::copy(p.col_start.begin(), p.col_start.end(), SUNSparseMatrix_IndexPointers(J));
      std::copy(p.rows.begin(), p.rows.end(), SUNSparseMatrix_IndexValues(J));
      double* values = SUNSparseMatrix_Data(J);
      for (std::size_t c = 0; c < n; ++c)
        for (sunindextype k = p.col_start[c]; k < p.col_start[c + 1]; ++k) values[k] = M[c * n + p.rows[k]];
    }
    return 0;
  } catch (...) {
    data->error = std::current_exception();
    return -1;
  }
}

// g = chart margin - threshold: a root where the chart nears its singularity.
int chart_root_callback(realtype /*t*/, N_Vector yy, N_Vector /*yp*/, realtype* g, void* user_data) {
  auto* data = static_cast<CallbackData*>(user_data);
  const DaeSystem& dae = *data->dae;
  g[0] = dae.representation().chart_margin(dae.coordinates(N_VGetArrayPointer(yy))) - data->threshold;
  return 0;
}

// IDA's name for a return flag. IDAGetReturnFlagName mallocs the string and
// leaves freeing it to the caller (found by LeakSanitizer, tools/sanitize.sh).
std::string flag_name(int flag) {
  char* name = IDAGetReturnFlagName(flag);
  std::string s = name ? name : fmt::format("flag {}", flag);
  std::free(name);
  return s;
}

void check(int flag, const char* what) {
  if (flag < 0) throw SolverError(fmt::format("{} failed: {}", what, flag_name(flag)));
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
std::string explain_failure(int flag) {
  switch (flag) {
    case IDA_TOO_MUCH_WORK: return "too much work before reaching the output time";
    case IDA_TOO_MUCH_ACC: return "the requested accuracy is below what round-off allows (raise rtol/atol)";
    case IDA_ERR_FAIL:
      return "repeated error-test failures (the step kept shrinking: a singularity, or tolerances too tight "
             "for this formulation)";
    case IDA_CONV_FAIL:
      return "repeated Newton convergence failures (the iteration matrix is singular or the problem is stiffer "
             "than the step allows; an index-2/3 form without error-test suppression fails like this)";
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
// y'' comes from a difference of consistent y' along a short explicit step.
double first_step_estimate(const DaeSystem& dae, double t0, const Eigen::VectorXd& y, const Eigen::VectorXd& yp,
                           const SolverSettings& opt, double span) {
  const int nd = dae.layout().nq + dae.layout().nv;  // differential unknowns only
  const double rate = yp.head(nd).cwiseAbs().maxCoeff();
  const double delta = rate > 0 ? std::min(1e-4 * span, 1e-3 / rate) : 1e-4 * span;
  Eigen::VectorXd y1 = y + delta * yp, yp1;
  dae.make_consistent(t0 + delta, y1, yp1);
  const Eigen::VectorXd ydd = (yp1.head(nd) - yp.head(nd)) / delta;
  const Eigen::VectorXd w = (opt.rtol * y.head(nd).cwiseAbs()).array() + opt.atol;
  const double norm = std::sqrt((ydd.cwiseQuotient(w)).squaredNorm() / nd);
  const double h = norm > 0 ? std::sqrt(2.0 / norm) : 1e-3 * span;
  return std::min(h, 1e-3 * span);
}

// Re-expresses (y, y') at t in the most regular chart and makes it
// consistent. Returns the switch, with `to` empty if the chart stayed.
ChartSwitch change_chart(DaeSystem& dae, double t, Eigen::VectorXd& y, Eigen::VectorXd& yp) {
  Representation& rep = dae.representation();
  VecQ q = dae.coordinates(y.data());
  VecV v = dae.velocities(y.data());
  ChartSwitch s{t, rep.chart_name(), "", rep.chart_margin(q)};
  if (!rep.change_chart(q, v)) return s;
  s.to = rep.chart_name();
  y.segment(dae.layout().q_offset(), q.size()) = q;
  y.segment(dae.layout().v_offset(), v.size()) = v;
  dae.make_consistent(t, y, yp);
  return s;
}

void record_switch(RunResult& result, StepSink& sink, const ChartSwitch& s) {
  ++result.switch_count;
  if (result.switches.size() < kSwitchesKept) result.switches.push_back(s);
  sink.on_chart_switch(s);
}

}  // namespace

RunResult integrate(DaeSystem& dae, const Scene& scene, StepSink& sink) {
  const int n = dae.size();
  const SolverSettings& opt = scene.solver;
  const TimeGrid& span = scene.time;
  const EulerChartSpec& charts = scene.formulation.euler;
  Representation& rep = dae.representation();
  const bool watch_charts = rep.has_charts();

  RunResult result;
  CallbackData data;
  data.dae = &dae;
  data.threshold = charts.switch_threshold;
  data.exact_jacobian = opt.jacobian == "exact";
  const bool klu = opt.linear_solver == "klu";
  if (klu) {
    if (opt.jacobian == "ida_dq")
      throw InputError("solver.linear_solver = \"klu\" needs solver.jacobian = \"exact\" or \"central\": IDA's "
                       "difference quotients fill dense and banded matrices only");
    data.pattern = sparse_pattern(dae);
    data.dense.resize(static_cast<std::size_t>(n) * n);
  }
  IdaSession ida(n, static_cast<long>(data.pattern.rows.size()));

  Eigen::VectorXd y, yp;
  dae.consistent_state(span.start, scene.R0_WB, scene.omega0_B, y, yp);

  // A chart that starts too close to its singularity.
  if (watch_charts && rep.chart_margin(dae.coordinates(y.data())) <= charts.switch_threshold) {
    if (!charts.switching)
      throw InputError(fmt::format(
          "{}: the Euler-angle sequence '{}' is within its singularity margin at t = {} (margin {:.3g} <= "
          "switch_threshold {}); choose another sequence, 'auto', or enable switching",
          scene.source, rep.chart_name(), span.start, rep.chart_margin(dae.coordinates(y.data())),
          charts.switch_threshold));
    const ChartSwitch s = change_chart(dae, span.start, y, yp);
    if (!s.to.empty()) {
      // Rebuilt from the physical start in the new chart: velocities that
      // went through the old chart (angle rates B^-1 omega) are lost at its
      // singularity, e.g. a top that starts exactly upright in z-x-z.
      dae.consistent_state(span.start, scene.R0_WB, scene.omega0_B, y, yp);
      record_switch(result, sink, s);
    }
  }

  Eigen::Map<Eigen::VectorXd>(N_VGetArrayPointer(ida.y), n) = y;
  Eigen::Map<Eigen::VectorXd>(N_VGetArrayPointer(ida.yp), n) = yp;
  Eigen::Map<Eigen::VectorXd>(N_VGetArrayPointer(ida.id), n) = dae.differential_id();
  // Absolute tolerances by group. Coordinates and velocities: the user's
  // atol. Multipliers never enter the error test of an index-2 scheme, but
  // their weights still enter IDA's Newton convergence test, where an index-2
  // multiplier cannot meet a tight tolerance: round-off in the dynamics rows
  // reaches it amplified by 1/h, so Newton fails, the step shrinks and the
  // amplification grows. Too loose a weight lets GGL's mu pollute q' instead.
  // rtol^(3/4) relative to their start size was measured best on the heavy
  // top (rtol^(1/2): 2x the steps; rtol^(0.9): Newton failures at 1e-12).
  {
    Eigen::Map<Eigen::VectorXd> atol(N_VGetArrayPointer(ida.atol), n);
    const UnknownLayout& lay = dae.layout();
    const int nm = lay.n_lambda + lay.n_mu;
    atol.head(lay.nq + lay.nv).setConstant(opt.atol);
    if (nm > 0) {
      const double scale = std::max(1.0, y.tail(nm).cwiseAbs().maxCoeff());
      atol.tail(nm).setConstant(std::max(opt.atol, std::pow(opt.rtol, 0.75)) * scale);
    }
  }

  {
    Eigen::VectorXd F(n);
    dae.residual(span.start, y.data(), yp.data(), F.data());
    result.initial_residual = F.cwiseAbs().maxCoeff();
  }

  check(IDAInit(ida.mem, residual_callback, span.start, ida.y, ida.yp), "IDAInit");
  check(IDASVtolerances(ida.mem, opt.rtol, ida.atol), "IDASVtolerances");
  check(IDASetUserData(ida.mem, &data), "IDASetUserData");
  check(IDASetId(ida.mem, ida.id), "IDASetId");
  check(IDASetSuppressAlg(ida.mem, dae.scheme().suppress_multiplier_error_test() ? SUNTRUE : SUNFALSE),
        "IDASetSuppressAlg");
  check(IDASetLinearSolver(ida.mem, ida.LS, ida.A), "IDASetLinearSolver");
  if (opt.jacobian != "ida_dq") check(IDASetJacFn(ida.mem, jacobian_callback), "IDASetJacFn");
  check(IDASetMaxOrd(ida.mem, opt.max_order), "IDASetMaxOrd");
  check(IDASetStopTime(ida.mem, span.end), "IDASetStopTime");
  const double h0 =
      opt.initial_step > 0 ? opt.initial_step : first_step_estimate(dae, span.start, y, yp, opt, span.end - span.start);
  check(IDASetInitStep(ida.mem, h0), "IDASetInitStep");
  if (watch_charts) check(IDARootInit(ida.mem, 1, chart_root_callback), "IDARootInit");

  const OutputGrid grid(span);
  std::size_t next_out = 0;
  sink.on_output(span.start, y);
  ++next_out;

  // Output-grid points up to t, interpolated from IDA's last step.
  Eigen::VectorXd yout(n);
  auto emit_grid_until = [&](double t) {
    while (next_out < grid.size() && grid[next_out] <= t) {
      const double t_out = grid[next_out];
      if (IDAGetDky(ida.mem, t_out, 0, ida.dky) < 0) break;
      yout = Eigen::Map<const Eigen::VectorXd>(N_VGetArrayPointer(ida.dky), n);
      sink.on_output(t_out, yout);
      ++next_out;
    }
  };

  IdaCounters before_restart;  // counters of the segments before the last IDAReInit
  double t = span.start;
  Eigen::Map<Eigen::VectorXd> y_ida(N_VGetArrayPointer(ida.y), n);
  Eigen::Map<Eigen::VectorXd> yp_ida(N_VGetArrayPointer(ida.yp), n);
  long steps_total = 0;
  const ProjectionPolicy projection = dae.scheme().projection();

  // Hands the state (y, yp) at t back to IDA as a new start.
  auto restart = [&](double h0) {
    y_ida = y;
    yp_ida = yp;
    add_counters(ida.mem, before_restart);
    check(IDAReInit(ida.mem, t, ida.y, ida.yp), "IDAReInit");
    check(IDASetInitStep(ida.mem, h0), "IDASetInitStep");
    ++before_restart.restarts;
  };

  // The size of the last step taken (0 before the first).
  auto last_step = [&] {
    double h = 0.0;
    IDAGetLastStep(ida.mem, &h);
    return h;
  };

  while (t < span.end) {
    if (g_interrupt_requested.load()) {
      result.status = RunStatus::Interrupted;
      result.message = fmt::format("interrupted by a signal (Ctrl-C or SIGTERM) at t = {:.9g} s, last step size "
                                   "{:.3g} s, after {} steps; the steps so far are kept",
                                   t, last_step(), steps_total);
      break;
    }
    if (steps_total >= opt.max_steps) {
      // IDA's own limit (IDA_TOO_MUCH_WORK) counts steps per call; one step per call, rigidae counts the run.
      const double h = last_step();
      result.status = RunStatus::Failed;
      result.message = fmt::format(
          "too much work (IDA_TOO_MUCH_WORK): max_steps = {} internal steps taken and t = {:.9g} s of {:.9g} s "
          "reached, last step size {:.3g} s; at that step size the rest would take about {:.3g} more steps. "
          "Likely cause: {}",
          opt.max_steps, t, span.end, h, h > 0 ? (span.end - t) / h : 0.0,
          h > 0 && h < 1e-9 * (span.end - span.start)
              ? "the step size has collapsed (a near-singularity, or tolerances too tight for this formulation)"
              : "the run is longer or faster than max_steps allows (raise --max-steps or solver.max_steps)");
      break;
    }
    const int flag = IDASolve(ida.mem, span.end, &t, ida.y, ida.yp, IDA_ONE_STEP);
    if (data.error) std::rethrow_exception(data.error);
    if (flag < 0) {
      double h = 0.0, tcur = t;
      IDAGetCurrentStep(ida.mem, &h);
      IDAGetCurrentTime(ida.mem, &tcur);
      result.status = RunStatus::Failed;
      result.message = fmt::format("IDA failed with {} at t = {:.9g} s, step size {:.3g} s: {}",
                                   flag_name(flag), tcur, h, explain_failure(flag));
      t = tcur;
      break;
    }
    emit_grid_until(t);
    if (flag == IDA_ROOT_RETURN) {
      // The chart nears its singularity: re-express the state and restart.
      y = y_ida;
      if (!charts.switching) {
        const double margin = rep.chart_margin(dae.coordinates(y.data()));
        result.status = RunStatus::Failed;
        result.message = fmt::format(
            "chart singularity: IDA's root finding (IDA_ROOT_RETURN) found the Euler-angle chart '{}' at its "
            "singularity margin {:.3g} at t = {:.9g} s, last step size {:.3g} s (gimbal lock ahead; the angle "
            "rates would blow up). Chart switching is off: enable it ([formulation.euler_angles] switching = "
            "true), or use quaternion or linear coordinates",
            rep.chart_name(), margin, t, last_step());
        break;
      }
      const ChartSwitch s = change_chart(dae, t, y, yp);
      if (s.to.empty()) continue;  // already the most regular chart
      restart(first_step_estimate(dae, t, y, yp, opt, span.end - span.start));
      record_switch(result, sink, s);
      continue;
    }
    ++steps_total;
    double h = 0.0;
    int order = 0;
    IDAGetLastStep(ida.mem, &h);
    IDAGetLastOrder(ida.mem, &order);
    y = y_ida;
    sink.on_step(t, h, order, y);
    if (projection.enabled && t < span.end) {
      const ConstraintDrift before = dae.drift(t, y.data());
      if (projection.every_step || before.position > projection.threshold ||
          before.velocity > projection.threshold) {
        // IDA keeps no memory across the restart: the step size is carried
        // over, the order and the history are lost.
        dae.project(t, y, yp);
        restart(h);
        ++before_restart.projections;
        sink.on_projection(t, before);
      }
    }
  }

  result.t_reached = t;
  result.counters = before_restart;
  add_counters(ida.mem, result.counters);
  result.counters.jacobian_residual_evals += dae.jacobian_residual_evaluations();
  IDAGetLastStep(ida.mem, &result.counters.last_step);
  IDAGetLastOrder(ida.mem, &result.counters.last_order);
  return result;
}

}  // namespace rigidae
