// The single rigid body as an ODE (equations and conventions in
// include/rigidae/dae/single_body_ode.hpp).
#include "rigidae/dae/single_body_ode.hpp"

#include <fmt/format.h>

#include <cmath>

#include "rigidae/core/error.hpp"

namespace rigidae {

SingleBodyOde::SingleBodyOde(const DaeSystem& dae, const Scene& scene)
    : dae_(dae), chart_(dae.start_chart()), scene_(scene) {
  const Representation& r = rep();
  nq_ = r.nq();
  nv_ = r.nv();
  nc_ = r.nc();
  force_ = r.constraint_kind() == ConstraintKind::Force;
  const UnknownLayout& lay = dae.layout();
  if (lay.nq != nq_ || lay.nv != nv_ || lay.n_mu != 0 || lay.n_lambda != (force_ ? nc_ : 0))
    throw InputError(fmt::format("the ODE form of {} needs an acceleration-level scheme (index1 or projection), "
                                 "not '{}'",
                                 r.name(), dae.scheme().name()));
  body_ = schemes::BodyOde(r);
}

void SingleBodyOde::initial_state(double t0, Eigen::VectorXd& x) {
  chart_ = dae_.start_chart();
  Eigen::VectorXd y, yp;
  dae_.consistent_state(chart_, t0, scene_.R0_WB, scene_.omega0_B, y, yp);
  const EulerChartSpec& charts = scene_.formulation.euler;
  const double margin = rep().chart_margin(dae_.coordinates(y.data()));
  if (rep().has_charts() && margin <= charts.switch_threshold) {
    if (!charts.switching)
      throw InputError(fmt::format(
          "{}: the Euler-angle sequence '{}' is within its singularity margin at t = {} (margin {:.3g} <= "
          "switch_threshold {}); choose another sequence, 'auto', or enable switching",
          scene_.source, rep().chart_name(), t0, margin, charts.switch_threshold));
    x = y.head(nq_ + nv_);
    // Rebuilt from the physical start in the new chart (as SingleBodyProblem
    // does: rates through the old chart are lost at its singularity).
    if (change_chart(t0, x)) {
      dae_.consistent_state(chart_, t0, scene_.R0_WB, scene_.omega0_B, y, yp);
      x = y.head(nq_ + nv_);
    }
    return;
  }
  x = y.head(nq_ + nv_);
}

void SingleBodyOde::absolute_tolerances(double /*rtol*/, double atol, const Eigen::VectorXd& /*x0*/,
                                        Eigen::Ref<Eigen::VectorXd> out) const {
  out.setConstant(atol);
}

bool SingleBodyOde::rhs(double t, const double* x, double* xdot) { return body_.rate(rep(), t, x, xdot); }

OdeDrift SingleBodyOde::drift(double t, const double* x) const {
  // q and v sit at the same offsets in x and in the DAE's y.
  const ConstraintDrift d = dae_.drift(chart_, t, x);
  return {d.position, d.velocity};
}

void SingleBodyOde::project(double t, double* x) { body_.project(rep(), t, x); }

void SingleBodyOde::project_error(double t, const double* x, double* e) { body_.project_error(rep(), t, x, e); }

void SingleBodyOde::observe(double t, const double* x, Eigen::VectorXd& y) {
  y.setZero(dae_.size());
  y.head(nq_ + nv_) = Eigen::Map<const Eigen::VectorXd>(x, nq_ + nv_);
  if (force_ && nc_ > 0) {
    body_.accelerations(rep(), t, x);
    y.segment(dae_.layout().lambda_offset(), nc_) = body_.multipliers();
  }
}

int SingleBodyOde::event_count() const { return rep().has_charts() ? 1 : 0; }

void SingleBodyOde::event_functions(double /*t*/, const double* x, double* g) {
  const VecQ q = Eigen::Map<const Eigen::VectorXd>(x, nq_);
  g[0] = rep().chart_margin(q) - scene_.formulation.euler.switch_threshold;
}

StepAction SingleBodyOde::on_event(double t, Eigen::VectorXd& x) {
  StepAction a;
  if (!scene_.formulation.euler.switching) {
    const VecQ q = x.head(nq_);
    a.kind = StepAction::Kind::Fail;
    a.message = fmt::format(
        "chart singularity: root finding found the Euler-angle chart '{}' at its singularity margin {:.3g} at "
        "t = {:.9g} s (gimbal lock ahead; the angle rates would blow up). Chart switching is off: enable it "
        "([formulation.euler_angles] switching = true), or use quaternion or linear coordinates",
        rep().chart_name(), rep().chart_margin(q), t);
    return a;
  }
  if (!change_chart(t, x)) return a;  // already the most regular chart
  a.kind = StepAction::Kind::Restart;
  return a;
}

// Through the DAE's layout: DaeSystem::change_chart re-expresses (y, y') via
// the physical state (R, omega); the ODE keeps q and v of the result.
bool SingleBodyOde::change_chart(double t, Eigen::VectorXd& x) {
  const VecQ q = x.head(nq_);
  EventNote note;
  note.t = t;
  note.what = "chart_switch";
  note.from = rep().chart_name();
  note.margin = rep().chart_margin(q);
  Eigen::VectorXd y = Eigen::VectorXd::Zero(dae_.size()), yp = Eigen::VectorXd::Zero(dae_.size());
  y.head(nq_ + nv_) = x;
  const int to = dae_.change_chart(chart_, t, y, yp);
  if (to == chart_) return false;
  chart_ = to;
  x = y.head(nq_ + nv_);
  note.to = rep().chart_name();
  notes_.push_back(std::move(note));
  return true;
}

std::vector<EventNote> SingleBodyOde::take_events() {
  std::vector<EventNote> out;
  out.swap(notes_);
  return out;
}

}  // namespace rigidae
