// The column set of a one-body scene's run (record/run_columns.hpp): the
// single-body table of record/columns.hpp, read through OneBodyView.
#include "one_body_columns.hpp"

#include "rigidae/record/error_control.hpp"
#include "rigidae/record/recorder.hpp"

namespace rigidae {

namespace {

nlohmann::json vec_json(const Eigen::Ref<const Eigen::VectorXd>& v) {
  return std::vector<double>(v.data(), v.data() + v.size());
}

nlohmann::json mat_json(const Mat3& M) {
  return {vec_json(M.row(0).transpose()), vec_json(M.row(1).transpose()), vec_json(M.row(2).transpose())};
}

// The units line's addition when the run has multipliers and they are not
// error-controlled (record/error_control.hpp).
std::string multipliers_note(const OneBodyView& view, const Scene& scene) {
  if (view.multiplier_names().empty()) return "";
  const MultiplierErrorControl c = multiplier_error_control(
      scene.solver.integrator, view.system().suppress_algebraic_error_test(), view.system().scheme().name);
  return c.controlled ? std::string() : "; multipliers NOT error-controlled: " + c.note;
}

}  // namespace

OneBodyColumns::OneBodyColumns(multibody::MultibodyProblem& system, const Scene& scene)
    : scene_(scene),
      view_(system, scene),
      step_observer_(view_, scene),
      grid_observer_(view_, scene),
      names_(view_.multiplier_names()),
      units_(columns::units_line() + multipliers_note(view_, scene)),
      events_units_("# units: t s; margin |det B| of the chart left (chart_switch), 1; drift_position |Phi| 1 and "
                    "drift_velocity |dPhi/dt| 1/s just before a projection"),
      events_header_("t,event,from,to,margin,drift_position,drift_velocity") {}

const columns::Table& OneBodyColumns::table() const { return columns::single_body(); }

bool OneBodyColumns::with_chart() const { return view_.representation().has_charts(); }

std::string_view OneBodyColumns::chart() const { return chart_; }

void OneBodyColumns::observe(columns::File f, double t, const Eigen::VectorXd& y, Observation& o,
                             std::span<double> /*values*/) {
  o = (f == columns::kSteps ? step_observer_ : grid_observer_).observe(t, y);
  if (with_chart()) chart_ = view_.representation().chart_name();  // short: no allocation
}

double OneBodyColumns::initial_energy() const { return step_observer_.initial_energy(); }

void OneBodyColumns::append_event(fmt::memory_buffer& b, const EventNote& e) const {
  if (e.what == "chart_switch")
    fmt::format_to(fmt::appender(b), "{},chart_switch,{},{},{},,\n", e.t, e.from, e.to, e.margin);
  else if (e.what == "projection")
    fmt::format_to(fmt::appender(b), "{},projection,,,,{},{}\n", e.t, e.drift_position, e.drift_velocity);
}

void OneBodyColumns::add_summary(nlohmann::json& j, const RunExtremes& x) const {
  const Scene& s = scene_;
  j["configuration"]["body"] = {{"mass_kg", s.body.mass},
                                {"inertia_com_kg_m2", mat_json(s.body.inertia_com)},
                                {"center_of_mass_m", vec_json(s.body.com_B)}};
  j["configuration"]["support"] = s.support == Support::FixedPoint ? "fixed_point" : "free";
  j["configuration"]["gravity_m_s2"] = vec_json(s.gravity_W);
  j["configuration"]["initial"] = {{"R_WB", mat_json(s.R0_WB)}, {"omega_B_rad_s", vec_json(s.omega0_B)}};

  const Observation& f = x.last;
  nlohmann::json multipliers = nlohmann::json::object();
  for (std::size_t i = 0; i < names_.size(); ++i) {
    const bool seen = x.steps_recorded > 0;
    multipliers[names_[i]] = {{"min", seen ? x.multiplier_min(i) : 0.0},
                              {"max", seen ? x.multiplier_max(i) : 0.0},
                              {"final", f.multipliers(i)}};
  }
  j["multipliers"] = multipliers;
  j["maxima"]["abs_vertical_momentum_rel_error"] = x.max_abs_vertical_momentum_error;
  j["final"]["q_WB"] = vec_json(f.q_WB);
  j["final"]["omega_B"] = vec_json(f.omega_B);
  j["final"]["vertical_momentum"] = f.vertical_momentum;
  j["final"]["vertical_momentum_rel_error"] = f.vertical_momentum_error;

  // The last observation as the columns of trajectory.csv.
  nlohmann::json row = nlohmann::json::object();
  const columns::Sample sample{f.t, 0.0, 0, &f, {}, {}};
  for (const columns::Column& c : columns::all()) {
    if (!(c.files & columns::kTrajectory)) continue;
    if (c.kind == columns::Kind::Real) row[std::string(c.name)] = c.value(sample);
    if (c.kind == columns::Kind::Multipliers)
      for (std::size_t i = 0; i < names_.size(); ++i) row[names_[i]] = f.multipliers(static_cast<int>(i));
  }
  j["final_row"] = row;
}

std::string OneBodyColumns::final_report(const RunExtremes& x, double /*t_reached*/) const {
  const Observation& f = x.last;
  std::string s = fmt::format("  final t       {:.9g} s\n", f.t);
  s += fmt::format("  final q_WB    ({:.8f}, {:.8f}, {:.8f}, {:.8f})\n", f.q_WB(0), f.q_WB(1), f.q_WB(2), f.q_WB(3));
  s += fmt::format("  final omega_B ({:.6f}, {:.6f}, {:.6f}) rad/s\n", f.omega_B(0), f.omega_B(1), f.omega_B(2));
  s += fmt::format("  max drift     position {:.2e}, velocity {:.2e}\n", x.max_drift_position, x.max_drift_velocity);
  s += fmt::format("  invariants    max |energy rel. error| {:.2e}, max |vertical momentum rel. error| {:.2e}\n",
                   x.max_abs_energy_error, x.max_abs_vertical_momentum_error);
  for (std::size_t i = 0; i < names_.size() && x.steps_recorded > 0; ++i)
    s += fmt::format("  multiplier    {} in [{:.4g}, {:.4g}]\n", names_[i], x.multiplier_min(i), x.multiplier_max(i));
  return s;
}

}  // namespace rigidae
