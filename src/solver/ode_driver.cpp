// CVODE and ARKODE on an OdeProblem, one internal step at a time (see
// include/rigidae/solver/ode_driver.hpp). The loop mirrors the IDA
// driver's: step, emit the output grid from the integrator's interpolant,
// handle a root (chart switch: restart), record the step, project.
#include "rigidae/solver/ode_driver.hpp"

#include <fmt/format.h>
#include <sundials/sundials_context.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <limits>
#include <memory>

#include "ode_stepper.hpp"
#include "rigidae/core/error.hpp"
#include "rigidae/solver/integrators.hpp"
#include "serial_vector.hpp"
#include "stall_watch.hpp"
#include "stop_time.hpp"

namespace rigidae {

namespace ode {

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

}  // namespace ode

namespace {

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
  ode::CallbackData data;
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

  const std::unique_ptr<ode::Stepper> stepper =
      info.make_stepper({method, vec.ctx, vec.x, vec.atol, opt, span, data, problem.event_count()});

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
  // The stop time as last set (NaN: set again): the end, or the problem's
  // hint short of a singular pose, which the integrator forgets once there.
  double stop_time = span.end;
  auto follow_stop_hint = [&](double t_now) {
    const double stop = next_stop_time(problem.stop_time_hint(), t_now, span.end);
    if (stop == stop_time && t_now != stop_time) return;
    stepper->set_stop_time(stop);
    stop_time = stop;
  };

  auto restart = [&](double t) {
    x_sun = x;
    stepper->add_counters(before_restart);
    stepper->reinit(t, vec.x);
    ++before_restart.restarts;
    stop_time = std::numeric_limits<double>::quiet_NaN();
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
      follow_stop_hint(t);
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
    if (!stepper->projects_inside_step() && data.projection.enabled && t < span.end) {
      // CVODE projects inside the step for BDF only: Adams restarts.
      const OdeDrift d = problem.drift(t, x.data());
      if (d.position > data.projection.threshold || d.velocity > data.projection.threshold) {
        problem.project(t, x.data());
        restart(t);
        ++before_restart.projections;
        sink.on_event(projection_note(t, d));
      }
    }
    if (t < span.end) {
      // A bridge across a singular pose ahead: the grid inside from the
      // problem, the landing recorded as a step of order 0, a restart there.
      const double landing = problem.bridge(t, x);
      forward_events(problem, result, sink, before_restart);
      if (landing > t) {
        while (next_out < grid.size() && grid[next_out] <= landing) {
          if (every_output || next_out + 1 == grid.size()) {
            problem.bridged_observation(grid[next_out], y_obs);
            sink.on_output(grid[next_out], y_obs);
          }
          ++next_out;
        }
        const double h_bridge = landing - t;
        t = landing;
        problem.observe(t, x.data(), y_obs);
        sink.on_step(t, h_bridge, 0, y_obs);
        restart(t);
      }
      follow_stop_hint(t);
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
