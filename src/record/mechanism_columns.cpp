// The column set of a mechanism's run (see mechanism_columns.hpp).
#include "mechanism_columns.hpp"

#include <algorithm>
#include <cmath>

#include "rigidae/record/error_control.hpp"
#include "rigidae/core/text.hpp"
#include "rigidae/record/recorder.hpp"

// Rows name only the fields they set; the others keep their defaults by design.
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"

namespace rigidae {

namespace {

// The trajectory's units line: one entry per kind of column (the body and
// joint names vary).
std::string grid_units(const multibody::MultibodyProblem& p, const RecordedParts& parts,
                       const std::string& not_controlled) {
  const std::vector<std::string> names = p.output_names(parts), units = p.output_units(parts);
  std::string s = "# units: t s";
  std::vector<std::string> seen;
  for (std::size_t i = 0; i < names.size(); ++i) {
    const std::size_t dot = names[i].rfind('.');
    const std::string kind = dot == std::string::npos ? names[i] : "*." + names[i].substr(dot + 1);
    if (std::find(seen.begin(), seen.end(), kind) != seen.end()) continue;
    seen.push_back(kind);
    s += "; " + kind + " " + units[i];
  }
  return s + "; q* unit quaternion of R_WB (scalar first); w* space angular velocity; JOINT.force/torque on "
             "body b (on a when b is the ground) at its joint point, space frame; residual_position |Phi| (m for "
             "point rows, 1 for angular rows), residual_velocity |G v|; JOINT.angle* (rad, unwrapped: whole turns "
             "counted) and JOINT.displacement (m) the joint's coordinates, *_rate their rates" +
         (parts.joints.empty() ? std::string() : not_controlled);
}

// The units of the step file's per-part columns (after the table's own).
std::string step_part_units(const RecordedParts& parts, bool any_column, const std::string& not_controlled) {
  if (!any_column) return "";
  std::string s;
  if (!parts.bodies.empty())
    s += "; BODY.lambda_* J, BODY.mu_* 1/s (multipliers of a body's own constraints, e.g. the quaternion norm)";
  if (!parts.joints.empty())
    s += "; JOINT.lambda_* N (point rows) or N m (angular rows), JOINT.mu_* m/s or 1/s (multipliers of the joint's "
         "rows, named by row); JOINT.force_* N, JOINT.torque_* N m the reaction on body b (on a when b is the "
         "ground) at its joint point, space frame; JOINT.residual_position |Phi| m or 1, JOINT.residual_velocity |G v| m/s or "
         "1/s; JOINT.angle* rad (unwrapped), JOINT.displacement m, *_rate rad/s or m/s: the joint's coordinates";
  return s + not_controlled;
}

std::string not_controlled_note(const multibody::MultibodyProblem& p, const std::string& integrator) {
  const MultiplierErrorControl c =
      multiplier_error_control(integrator, p.suppress_algebraic_error_test(), p.scheme().name);
  return c.controlled ? std::string() : "; multipliers and reactions NOT error-controlled: " + c.note;
}

const Observation& obs(const columns::Sample& s) { return *s.observation; }

// steps.csv / steps.npy: a row per accepted step, drift the largest over the
// constraint rows, energy the total H with its error against the start, then
// the recorded parts; trajectory.csv: t and MultibodyProblem::output_row.
const columns::Column kColumns[] = {
    {"t", "t s", columns::kSteps | columns::kTrajectory, columns::Kind::Real,
     [](const columns::Sample& s) { return s.t; }, nullptr},
    {"h", "h s", columns::kSteps, columns::Kind::Real, [](const columns::Sample& s) { return s.h; }, nullptr},
    {"order", "", columns::kSteps, columns::Kind::Integer, nullptr,
     [](const columns::Sample& s) { return static_cast<long>(s.order); }},
    {"drift_position", "drift_position max |Phi| (m or 1)", columns::kSteps, columns::Kind::Real,
     [](const columns::Sample& s) { return obs(s).drift.position; }, nullptr},
    {"drift_velocity", "drift_velocity max |G v|", columns::kSteps, columns::Kind::Real,
     [](const columns::Sample& s) { return obs(s).drift.velocity; }, nullptr},
    {"energy", "energy J", columns::kSteps, columns::Kind::Real, [](const columns::Sample& s) { return obs(s).energy; },
     nullptr},
    {"energy_rel_error", "energy_rel_error (H - H0 - W)/max(|H0|, 1 J), W the work of drivers and loads",
     columns::kSteps, columns::Kind::Real, [](const columns::Sample& s) { return obs(s).energy_error; }, nullptr},
    {"parts", "", columns::kSteps, columns::Kind::Values, nullptr, nullptr},
    {"grid", "", columns::kTrajectory, columns::Kind::Values, nullptr, nullptr},
};

// Numbers in fmt's layout (the mechanism files have always been written so).
const columns::Table kTable{kColumns, columns::Digits::Fmt};

}  // namespace

MechanismColumns::MechanismColumns(multibody::MultibodyProblem& problem, const Scene& scene)
    : problem_(problem),
      step_parts_(recorded_parts(problem.spec())),
      grid_parts_(recorded_parts(problem.spec(), false)),
      step_names_(problem.step_part_names(step_parts_)),
      grid_names_(problem.output_names(grid_parts_)),
      events_units_("# units: t s; margin |det B| of the chart left (chart_switch), 1; drift_position and "
                    "drift_velocity just before a projection; row_subset: body the joints whose rows moved, from/to "
                    "the rows set aside before/after, margin the largest dependency coefficient; singular_pose: body "
                    "the joints whose rows nearly lose rank, margin their conditioning relative to the start"),
      events_header_("t,event,body,from,to,margin,drift_position,drift_velocity") {
  const std::string note = not_controlled_note(problem, scene.solver.integrator);
  step_units_ = columns::units_line(kTable) + step_part_units(step_parts_, !step_names_.empty(), note);
  grid_units_ = grid_units(problem, grid_parts_, note);
  energy_column_ = static_cast<int>(std::find(grid_names_.begin(), grid_names_.end(), "energy") - grid_names_.begin());
  has_work_ = problem.has_work();
}

const columns::Table& MechanismColumns::table() const { return kTable; }

double MechanismColumns::energy_error(double t, const Eigen::VectorXd& y, double H) {
  if (!have_H0_) H0_ = H, have_H0_ = true;
  if (has_work_)
    work_.follow(t, y.data(), y.size(), problem_.size(), [&] { return problem_.work_rate(t, y.data()); });
  return (H - H0_ - work_.value()) / std::max(std::abs(H0_), 1.0);
}

void MechanismColumns::observe(columns::File f, double t, const Eigen::VectorXd& y, Observation& o,
                               std::span<double> values) {
  o.t = t;
  if (f == columns::kSteps) {
    const auto [pos, vel] = problem_.drift(t, y.data());
    o.drift = {pos, vel};
    o.energy = problem_.kinetic_energy(y.data()) + problem_.potential_energy(y.data());
    o.energy_error = energy_error(t, y, o.energy);
    if (!values.empty()) problem_.step_part_row(t, y.data(), step_parts_, values.data());
    return;
  }
  // A grid point: the energy from the row when there is one. The work's
  // quadrature takes the accepted steps only (and the start); an
  // observation that carries W (ODE integrators) gives it at the point.
  if (!values.empty()) {
    problem_.output_row(t, y.data(), grid_parts_, values.data());
    o.energy = values[energy_column_];
  } else {
    o.energy = problem_.kinetic_energy(y.data()) + problem_.potential_energy(y.data());
  }
  if (!have_H0_)
    o.energy_error = energy_error(t, y, o.energy);
  else
    o.energy_error =
        (o.energy - H0_ - work_.value_at(y.data(), y.size(), problem_.size())) / std::max(std::abs(H0_), 1.0);
}

void MechanismColumns::append_event(fmt::memory_buffer& b, const EventNote& n) const {
  fmt::format_to(fmt::appender(b), "{},{},{},{},{},{},{},{}\n", n.t, n.what, n.body, n.from, n.to, n.margin,
                 n.drift_position, n.drift_velocity);
}

std::string MechanismColumns::note(const std::string& /*scheme_note*/) const {
  const MultibodySpec& spec = problem_.spec();
  std::string note = fmt::format("{}, {}, {} unknowns", text::count(problem_.bodies().size(), "body", "bodies"),
                                 text::count(spec.joints.size(), "joint", "joints"), problem_.size());
  const multibody::RedundancyReport& rr = problem_.redundancy();
  note += fmt::format("; mobility {} (rank), {} (Gruebler-Kutzbach)", rr.rank_dof, rr.gruebler_dof);
  if (!spec.drivers.empty())
    note += fmt::format(", {} driver{} counted as constraints", spec.drivers.size(), spec.drivers.size() == 1 ? "" : "s");
  if (!rr.dropped.empty())
    note += ", " + text::count(rr.dropped.size(), "redundant row", "redundant rows") + " set aside";
  if (const multibody::AssemblyReport& ar = problem_.assembly(); ar.done) note += "; " + ar.note;
  return note;
}

std::string MechanismColumns::final_report(const RunExtremes& x, double t_reached) const {
  // Many bodies: no one body's final state to print; each body's is in
  // trajectory.csv, and a vertical momentum is not tracked.
  std::string s = fmt::format("  final t       {:.9g} s (each body's state: trajectory.csv)\n", t_reached);
  s += fmt::format("  max drift     position {:.2e}, velocity {:.2e}\n", x.max_drift_position, x.max_drift_velocity);
  s += fmt::format("  invariants    max |energy rel. error| {:.2e}{}\n", x.max_abs_energy_error,
                   problem_.energy_balance_known()
                       ? ""
                       : " (not an error here: the dampers' dissipation is not counted; the energy check is off)");
  // Singular poses passed (multibody/row_subset.cpp, pose_bridge.cpp).
  const auto& poses = problem_.singular_poses();
  if (!poses.empty()) {
    int bridged = 0, switched = 0;
    double estimate = 0.0;
    std::string at;
    for (const multibody::SingularPose& sp : poses) {
      bridged += sp.bridged ? 1 : 0;
      switched += sp.branch_switch ? 1 : 0;
      if (sp.bridged) estimate = std::max(estimate, sp.estimate);
      at += fmt::format("{}{:.6g}", at.empty() ? "" : ", ", sp.t);
    }
    s += fmt::format("  singular      {} pose(s) at t = {} s; {} bridged{}{} (events.csv)\n", poses.size(), at, bridged,
                     bridged ? fmt::format(", extrapolation estimate up to {:.3g} x the tolerance", estimate) : "",
                     switched ? fmt::format("; {} changed branch", switched) : "");
  }
  return s;
}

namespace {

// Which bodies and joints have columns in the step file and trajectory.csv
// (model/recorded_parts.hpp), and why when the default left them out.
nlohmann::json recorded_parts_json(const multibody::MultibodyProblem& p, const RecordedParts& s,
                                   const RecordedParts& grid) {
  const auto names = [&](const RecordedParts& parts) {
    nlohmann::json b = nlohmann::json::array(), j = nlohmann::json::array();
    for (int i : parts.bodies) b.push_back(p.bodies()[i].name);
    for (int i : parts.joints) j.push_back(p.spec().joints[i].name);
    return nlohmann::json{{"bodies", b}, {"joints", j}};
  };
  nlohmann::json out = {{"steps", names(s)},
                        {"trajectory", names(grid)},
                        {"chosen_by_scene", {{"bodies", !s.bodies_by_default}, {"joints", !s.joints_by_default}}}};
  if (s.cut_by_size)
    out["note"] = fmt::format(
        "{} joints (more than {}): the step file holds only the global columns for the parts the scene does not "
        "name; choose them with [output] bodies = [...] and joints = [...] (or \"all\")",
        p.spec().joints.size(), kAllPartsUpToJoints);
  return out;
}

}  // namespace

void MechanismColumns::add_summary(nlohmann::json& j, const RunExtremes& /*x*/) const {
  const MultibodySpec& spec = problem_.spec();
  j["bodies"] = problem_.bodies().size();
  j["joints"] = spec.joints.size();
  j["nonzeros"] = problem_.sparsity().nnz();
  j["start_warnings"] = problem_.warnings();
  j["recorded_parts"] = recorded_parts_json(problem_, step_parts_, grid_parts_);

  // Redundant constraints and mobility (multibody_problem.hpp, "Redundant constraints").
  const multibody::RedundancyReport& rr = problem_.redundancy();
  nlohmann::json rows = nlohmann::json::array(), joints = nlohmann::json::array();
  for (int k = 0; k < static_cast<int>(rr.dropped.size()); ++k)
    rows.push_back({{"joint", spec.joints[rr.dropped[k].joint].name},
                    {"row", rr.dropped[k].row},
                    {"source", problem_.dropped_row_source(k)}});
  for (int jt : rr.indeterminate_joints) joints.push_back(spec.joints[jt].name);
  j["mobility"] = {{"rank_dof", rr.rank_dof},
                   {"gruebler_dof", rr.gruebler_dof},
                   {"redundant_rows", rr.dropped.size()},
                   {"rank", rr.rank},
                   {"rows", rr.rows},
                   {"velocities", rr.velocities},
                   {"expected_dof", spec.expected_dof ? nlohmann::json(*spec.expected_dof) : nlohmann::json(nullptr)},
                   {"drivers", spec.drivers.size()},
                   {"singular_start", rr.singular_start}};
  j["redundant_rows"] = rows;
  j["reactions_determined"] = rr.indeterminate_joints.empty();
  j["reactions_indeterminate_joints"] = joints;
  // multibody/minimum_norm_reactions.cpp: what the force and torque columns hold.
  j["reactions_method"] =
      rr.indeterminate_joints.empty()
          ? "multipliers of the joints' rows (determined by the constraints)"
          : fmt::format("minimum-norm split over the rows of the joints in the dependency (kept and set aside), "
                        "torques weighed divided by L = {:.6g} m; determined joints: their multipliers; the lambda "
                        "columns of steps.csv are the kept rows' multipliers (a particular solution)",
                        rr.length_scale);
  // The subset during the run (multibody/row_subset.cpp).
  nlohmann::json now = nlohmann::json::array(), poses = nlohmann::json::array();
  for (const multibody::RedundantRow& d : problem_.set_aside())
    now.push_back({{"joint", spec.joints[d.joint].name}, {"row", d.row}});
  for (const multibody::SingularPose& sp : problem_.singular_poses()) {
    nlohmann::json pose = {
        {"t", sp.t},
        {"joints", sp.joints},
        {"condition", sp.condition},
        // the branch check (branch_check.cpp); null: the run ended inside the pose
        {"velocity_jump", std::isnan(sp.velocity_jump) ? nlohmann::json() : nlohmann::json(sp.velocity_jump)},
        {"branch_switch", sp.branch_switch}};
    // Crossed by a bridge (multibody/pose_bridge.cpp): from, to, and the
    // extrapolation's estimate in units of the tolerance.
    if (sp.bridged)
      pose["bridge"] = {{"from_t", sp.bridged_from}, {"to_t", sp.bridged_to}, {"estimate_tolerances", sp.estimate}};
    poses.push_back(pose);
  }
  j["row_subset"] = {{"singular_poses_mode", problem_.bridges_singular_poses() ? "bridge" : "integrate"},
                     {"changes", problem_.subset_changes()},
                     {"largest_dependency", problem_.largest_dependency()},
                     {"largest_amplification", problem_.largest_amplification()},
                     {"set_aside_at_end", now},
                     {"singular_poses", poses}};
  if (!rr.mobility_warning.empty())
    j["warnings"].push_back({{"quantity", "mobility"}, {"message", rr.mobility_warning}});

  // An assembled start (multibody/assembly.hpp): what was held, the misses
  // before and after, and how far each other body was moved.
  if (const multibody::AssemblyReport& ar = problem_.assembly(); ar.done) {
    nlohmann::json held = nlohmann::json::array(), moved = nlohmann::json::array();
    for (int b : ar.held) held.push_back(spec.bodies[b].name);
    for (const multibody::AssembledBody& a : ar.bodies)
      moved.push_back({{"body", spec.bodies[a.body].name},
                       {"moved_m", a.moved_m},
                       {"turned_rad", a.turned_rad},
                       {"velocity_change_m_s", a.velocity_change},
                       {"angular_velocity_change_rad_s", a.angular_velocity_change}});
    j["assembly"] = {{"held", held},
                     {"iterations", ar.iterations},
                     {"initial_miss", ar.initial_miss},
                     {"final_miss", ar.final_miss},
                     {"initial_velocity_miss", ar.initial_velocity_miss},
                     {"final_velocity_miss", ar.final_velocity_miss},
                     {"bodies", moved}};
  }
  // URDF limits (model/multibody_spec.hpp, JointLimits): data, never enforced.
  nlohmann::json limits = nlohmann::json::array();
  const auto opt = [](const std::optional<double>& x) { return x ? nlohmann::json(*x) : nlohmann::json(nullptr); };
  for (const JointSpec& js : spec.joints)
    if (js.limits)
      limits.push_back({{"joint", js.name},
                        {"lower", opt(js.limits->lower)},
                        {"upper", opt(js.limits->upper)},
                        {"effort", opt(js.limits->effort)},
                        {"velocity", opt(js.limits->velocity)}});
  if (!limits.empty())
    j["joint_limits"] = {{"enforced", false},
                         {"note", "kept as data from the URDF: rigidae has no joint stops, so joints may pass them"},
                         {"joints", limits}};
}

}  // namespace rigidae
