#include "rigidae/dae/single_body_problem.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include "rigidae/core/error.hpp"

namespace rigidae {

SingleBodyProblem::SingleBodyProblem(const DaeSystem& dae, const EulerChartSpec& charts, const Mat3& R0_WB,
                                     const Vec3& omega0_B, std::string source)
    : dae_(dae), chart_(dae.start_chart()), charts_(charts), R0_WB_(R0_WB), omega0_B_(omega0_B), source_(std::move(source)),
      projection_(dae.scheme().projection()) {}

void SingleBodyProblem::initial_state(double t0, Eigen::VectorXd& y, Eigen::VectorXd& yp) {
  chart_ = dae_.start_chart();
  dae_.consistent_state(chart_, t0, R0_WB_, omega0_B_, y, yp);
  const Representation& rep = representation();
  // A chart that starts too close to its singularity.
  if (!rep.has_charts() || rep.chart_margin(dae_.coordinates(y.data())) > charts_.switch_threshold) return;
  if (!charts_.switching)
    throw InputError(fmt::format(
        "{}: the Euler-angle sequence '{}' is within its singularity margin at t = {} (margin {:.3g} <= "
        "switch_threshold {}); choose another sequence, 'auto', or enable switching",
        source_, rep.chart_name(), t0, rep.chart_margin(dae_.coordinates(y.data())), charts_.switch_threshold));
  // Rebuilt from the physical start in the new chart: velocities that went
  // through the old chart (angle rates B^-1 omega) are lost at its
  // singularity, e.g. a top that starts exactly upright in z-x-z.
  if (change_chart(t0, y, yp)) dae_.consistent_state(chart_, t0, R0_WB_, omega0_B_, y, yp);
}

// Coordinates and velocities: the user's atol. Multipliers never enter the
// error test of an index-2 scheme, but their weights still enter IDA's
// Newton convergence test, where an index-2 multiplier cannot meet a tight
// tolerance: round-off in the dynamics rows reaches it amplified by 1/h, so
// Newton fails, the step shrinks and the amplification grows. Too loose a
// weight lets GGL's mu pollute q' instead. rtol^(3/4) relative to their start
// size was measured best on the heavy top (rtol^(1/2): 2x the steps;
// rtol^(0.9): Newton failures at 1e-12).
void SingleBodyProblem::absolute_tolerances(double rtol, double atol, const Eigen::VectorXd& y0,
                                            Eigen::Ref<Eigen::VectorXd> out) const {
  const UnknownLayout& lay = dae_.layout();
  const int nm = lay.n_lambda + lay.n_mu;
  out.head(lay.nq + lay.nv).setConstant(atol);
  if (nm > 0) {
    const double scale = std::max(1.0, y0.tail(nm).cwiseAbs().maxCoeff());
    out.tail(nm).setConstant(std::max(atol, std::pow(rtol, 0.75)) * scale);
  }
}

bool SingleBodyProblem::residual(double t, const double* y, const double* yp, double* F) {
  dae_.residual(chart_, t, y, yp, F);
  for (int i = 0, n = dae_.size(); i < n; ++i)
    if (!std::isfinite(F[i])) return false;
  return true;
}

// g = chart margin - threshold: a root where the chart nears its singularity.
void SingleBodyProblem::event_functions(double /*t*/, const double* y, double* g) {
  g[0] = representation().chart_margin(dae_.coordinates(y)) - charts_.switch_threshold;
}

StepAction SingleBodyProblem::on_event(double t, double h, Eigen::VectorXd& y, Eigen::VectorXd& yp) {
  const Representation& rep = representation();
  if (!charts_.switching) {
    StepAction fail;
    fail.kind = StepAction::Kind::Fail;
    fail.message = fmt::format(
        "chart singularity: IDA's root finding (IDA_ROOT_RETURN) found the Euler-angle chart '{}' at its "
        "singularity margin {:.3g} at t = {:.9g} s, last step size {:.3g} s (gimbal lock ahead; the angle "
        "rates would blow up). Chart switching is off: enable it ([formulation.euler_angles] switching = "
        "true), or use quaternion or linear coordinates",
        rep.chart_name(), rep.chart_margin(dae_.coordinates(y.data())), t, h);
    return fail;
  }
  // The chart nears its singularity: re-express the state and restart with
  // the driver's first-step estimate.
  if (!change_chart(t, y, yp)) return StepAction::proceed();  // already the most regular chart
  StepAction restart;
  restart.kind = StepAction::Kind::Restart;
  return restart;
}

StepAction SingleBodyProblem::after_step(double t, double h, Eigen::VectorXd& y, Eigen::VectorXd& yp) {
  if (!projection_.enabled) return StepAction::proceed();
  const ConstraintDrift before = dae_.drift(chart_, t, y.data());
  if (!projection_.every_step && before.position <= projection_.threshold &&
      before.velocity <= projection_.threshold)
    return StepAction::proceed();
  dae_.project(chart_, t, y, yp);
  events_.push_back(EventNote::projection(t, before.position, before.velocity));
  return StepAction::restart_after_projection(h);
}

std::vector<EventNote> SingleBodyProblem::take_events() {
  std::vector<EventNote> out;
  out.swap(events_);
  return out;
}

bool SingleBodyProblem::change_chart(double t, Eigen::VectorXd& y, Eigen::VectorXd& yp) {
  const Representation& from = representation();
  EventNote note;
  note.t = t;
  note.what = "chart_switch";
  note.from = from.chart_name();
  note.margin = from.chart_margin(dae_.coordinates(y.data()));
  const int to = dae_.change_chart(chart_, t, y, yp);
  if (to == chart_) return false;
  chart_ = to;
  note.to = representation().chart_name();
  events_.push_back(std::move(note));
  return true;
}

}  // namespace rigidae
