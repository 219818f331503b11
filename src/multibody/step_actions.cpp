// What the multibody problem does between steps: each body with Euler
// angles switches its own chart (a root of margin - threshold, or a check
// after each step), and the projection scheme maps the state back onto the
// constraints when the drift passes its threshold (or after every step).
#include <fmt/format.h>

#include "rigidae/multibody/multibody_problem.hpp"
#include "rigidae/so3/euler_sequence.hpp"

namespace rigidae::multibody {

namespace {
using ConstMap = Eigen::Map<const Eigen::VectorXd>;
}

int MultibodyProblem::event_count() const {
  int n = 0;
  for (const BodyModel& b : bodies_) n += b.rep->has_charts() ? 1 : 0;
  return n;
}

void MultibodyProblem::event_functions(double /*t*/, const double* y, double* g) {
  int k = 0;
  for (const BodyModel& b : bodies_) {
    if (!b.rep->has_charts()) continue;
    const VecQ q = ConstMap(y + groups_[b.q_group].offset + b.nx, b.nqr);
    g[k++] = b.rep->chart_margin(q) - switch_threshold_;
  }
}

bool MultibodyProblem::change_charts(double t, Eigen::VectorXd& y, Eigen::VectorXd& yp, bool at_root) {
  if (!switching_) return false;
  bool changed = false;
  for (BodyModel& b : bodies_) {
    if (!b.rep->has_charts()) continue;
    const int qo = groups_[b.q_group].offset + b.nx, vo = groups_[b.v_group].offset + b.nx;
    VecQ q = y.segment(qo, b.nqr);
    VecV v = y.segment(vo, b.nvr);
    const double margin = b.rep->chart_margin(q);
    // At a root the margin equals the threshold to the root finder's tolerance.
    if (margin > switch_threshold_ * (at_root ? 1.001 : 1.0)) continue;
    const int best = b.rep->most_regular_chart(q);
    if (best == b.rep->chart()) continue;
    const std::string from = b.rep->chart_name();
    // Through the physical state: orientation and body angular velocity are
    // the same in every chart; the body's representation becomes the new chart.
    std::unique_ptr<Representation> next = b.rep->in_chart(best);
    VecQ q_new;
    VecV v_new;
    next->from_physical(b.rep->placement(q), b.rep->body_angular_velocity(q, v), q_new, v_new);
    b.rep = std::move(next);
    b.map->set_sequence(so3::parse_euler_sequence(b.rep->chart_name(), false));
    y.segment(qo, b.nqr) = q_new;
    y.segment(vo, b.nvr) = v_new;
    EventNote note;
    note.t = t;
    note.what = "chart_switch";
    note.body = b.name;
    note.from = from;
    note.to = b.rep->chart_name();
    note.margin = margin;
    events_.push_back(note);
    changed = true;
  }
  if (changed) {
    make_consistent(t, y, yp);
    forget_bridge_history();  // the angles of earlier states are in the old charts
  }
  return changed;
}

StepAction MultibodyProblem::on_event(double t, double h, Eigen::VectorXd& y, Eigen::VectorXd& yp) {
  StepAction a;
  if (!switching_) {
    for (const BodyModel& b : bodies_) {
      if (!b.rep->has_charts()) continue;
      const VecQ q = y.segment(groups_[b.q_group].offset + b.nx, b.nqr);
      const double margin = b.rep->chart_margin(q);
      if (margin > switch_threshold_ * 1.001) continue;
      a.kind = StepAction::Kind::Fail;
      a.message = fmt::format(
          "chart singularity: body '{}': the integrator's root finding found the Euler-angle chart '{}' at its "
          "singularity margin {:.3g} at t = {:.9g} s, "
          "last step size {:.3g} s (gimbal lock ahead; the angle rates would blow up). Chart switching is off: "
          "enable it ([formulation.euler_angles] switching = true), or use quaternion or linear coordinates",
          b.name, b.rep->chart_name(), margin, t, h);
      return a;
    }
    return a;
  }
  // A new chart: the driver's first-step estimate, as for one body.
  if (change_charts(t, y, yp, true)) a.kind = StepAction::Kind::Restart;
  return a;
}

StepAction MultibodyProblem::after_step(double t, double h, Eigen::VectorXd& y, Eigen::VectorXd& yp) {
  StepAction a;
  if (forces_follow_motion_ || !coordinates_.empty()) {
    evaluate(t, y.data(), 2);  // order 2: the Lagrange form's bias terms of the rows
    follow_force_elements();
  }
  // The independent subset of the rows (row_subset.cpp): chosen again, the
  // state is projected onto the new rows (a row that was set aside holds
  // only to the drift: without the projection an index-2 row G v = 0 would
  // ask the first step for a jump of that size, which no step size passes),
  // the multipliers are made consistent and the integrator restarts.
  if (check_row_subset(t, y.data(), true, yp.data())) {
    project(t, y, yp);
    a.kind = StepAction::Kind::Restart;
  }
  if (change_charts(t, y, yp, false)) a.kind = StepAction::Kind::Restart;
  if (scheme_.projection) {
    const auto [pos, vel] = projection_drift(t, y.data());
    if (project_every_step_ || pos > projection_threshold_ || vel > projection_threshold_) {
      project(t, y, yp);
      events_.push_back(EventNote::projection(t, pos, vel));
      a = StepAction::restart_after_projection(h);
    }
  }
  // Last, on the state as the step leaves it: the bridge across a singular
  // pose ahead (pose_bridge.cpp), which restarts the integrator beyond it.
  if (bridge_.enabled && watches_singular_poses()) {  // only loops with rows set aside are watched
    const double landing = bridge_after_step(t, y, yp);
    if (landing > t) {
      a = StepAction{};
      a.kind = StepAction::Kind::Restart;
      a.bridge_to = landing;
    }
  }
  return a;
}

std::vector<EventNote> MultibodyProblem::take_events() {
  std::vector<EventNote> out;
  out.swap(events_);
  return out;
}

}  // namespace rigidae::multibody
