#include "rigidae/app/solve.hpp"

#include "solve_multibody.hpp"
#include "counters_json.hpp"
#include "summary_common.hpp"
#include "machine_record.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <algorithm>
#include <variant>
#include <optional>
#include <nlohmann/json.hpp>

#include "rigidae/core/error.hpp"
#include "rigidae/model/one_body_system.hpp"
#include "rigidae/multibody/multibody_problem.hpp"
#include "rigidae/multibody/one_body_view.hpp"
#include "rigidae/io/checked_file.hpp"
#include "rigidae/record/columns.hpp"
#include "rigidae/settings/settings.hpp"
#include "rigidae/so3/rotation.hpp"
#include "rigidae/solver/version.hpp"

namespace rigidae {

namespace {

nlohmann::json vec_json(const Eigen::Ref<const Eigen::VectorXd>& v) {
  return std::vector<double>(v.data(), v.data() + v.size());
}

nlohmann::json mat_json(const Mat3& M) {
  return {vec_json(M.row(0).transpose()), vec_json(M.row(1).transpose()), vec_json(M.row(2).transpose())};
}

// A parameter as the scheme used it; a scheme that does not use it leaves
// the scene's setting (null when unset: the default is resolved by the
// scheme that uses it).
nlohmann::json used_or_set(const std::vector<SchemeParameter>& used, const std::string& name,
                           const std::optional<double>& set) {
  for (const auto& p : used)
    if (p.name == name) return p.value;
  return set ? nlohmann::json(*set) : nlohmann::json(nullptr);
}

// The scene's body and initial state, then every run setting of the table
// (rigidae/settings) at its dotted key, and the scheme's parameters as the
// scheme used them.
nlohmann::json configuration_json(const Scene& s, const std::vector<SchemeParameter>& used) {
  nlohmann::json j = {
      {"scene", s.source},
      {"name", s.name},
      {"body",
       {{"mass_kg", s.body.mass},
        {"inertia_com_kg_m2", mat_json(s.body.inertia_com)},
        {"center_of_mass_m", vec_json(s.body.com_B)}}},
      {"support", s.support == Support::FixedPoint ? "fixed_point" : "free"},
      {"gravity_m_s2", vec_json(s.gravity_W)},
      {"initial", {{"R_WB", mat_json(s.R0_WB)}, {"omega_B_rad_s", vec_json(s.omega0_B)}}},
  };
  for (const settings::Setting& setting : settings::all()) {
    if (setting.scene_key.empty() || !setting.get) continue;
    nlohmann::json value;
    std::visit([&](const auto& v) { value = v; }, setting.get(s));
    std::string pointer = "/" + std::string(setting.scene_key);
    std::replace(pointer.begin(), pointer.end(), '.', '/');
    j[nlohmann::json::json_pointer(pointer)] = value;
  }
  if (!s.time.output_times.empty()) j["output"]["times"] = s.time.output_times;
  j["formulation"]["baumgarte"]["a"] = used_or_set(used, "a", s.formulation.baumgarte.a);
  j["formulation"]["baumgarte"]["b"] = used_or_set(used, "b", s.formulation.baumgarte.b);
  j["formulation"]["projection"]["threshold"] = used_or_set(used, "threshold", s.formulation.projection.threshold);
  return j;
}

// The last observation as the columns of trajectory.csv (record/columns.hpp).
nlohmann::json final_row_json(const Observation& o, const std::vector<std::string>& multiplier_names) {
  nlohmann::json j = nlohmann::json::object();
  const columns::Sample sample{o.t, 0.0, 0, &o, {}, {}};
  for (const columns::Column& c : columns::all()) {
    if (!(c.files & columns::kTrajectory)) continue;
    if (c.kind == columns::Kind::Real) j[std::string(c.name)] = c.value(sample);
    if (c.kind == columns::Kind::Multipliers)
      for (std::size_t i = 0; i < multiplier_names.size(); ++i) j[multiplier_names[i]] = o.multipliers(static_cast<int>(i));
  }
  return j;
}

// JSON has no NaN: a measure not checked is null.
nlohmann::json number_or_null(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); }

nlohmann::json accuracy_check_json(const SolveOutcome& o) {
  const InvariantDrifts& d = o.drifts;
  return {{"tolerance", d.tolerance},
          {"energy", number_or_null(d.energy)},
          {"angular_momentum", number_or_null(d.angular_momentum)},
          {"vertical_angular_momentum", number_or_null(d.vertical_angular_momentum)},
          {"constraint_position", number_or_null(d.constraint_position)},
          {"constraint_velocity", number_or_null(d.constraint_velocity)},
          {"steps", o.extremes.steps_recorded},
          {"definitions", "maxima over the steps; see include/rigidae/app/accuracy_check.hpp"}};
}

// The energy at the start (kinetic plus potential about the reference point).
double initial_energy(const Scene& scene) {
  const RigidBodyModel b = make_rigid_body_model(scene);
  return b.kinetic_energy(scene.omega0_B) + b.potential_energy(scene.R0_WB);
}

nlohmann::json summary(const Scene& scene, const SolveOutcome& o) {
  const Observation& f = o.extremes.last;
  nlohmann::json multipliers = nlohmann::json::object();
  for (std::size_t i = 0; i < o.multiplier_names.size(); ++i) {
    const bool seen = o.extremes.steps_recorded > 0;
    multipliers[o.multiplier_names[i]] = {{"min", seen ? o.extremes.multiplier_min(i) : 0.0},
                                          {"max", seen ? o.extremes.multiplier_max(i) : 0.0},
                                          {"final", f.multipliers(i)}};
  }
  nlohmann::json switches = nlohmann::json::array();
  for (const auto& s : o.run.switches) switches.push_back({{"t", s.t}, {"from", s.from}, {"to", s.to}, {"margin", s.margin}});

  // The keys both summaries share (summary_common.hpp), then a single body's own.
  nlohmann::json j = common_summary_json(scene, o);
  j.update({
      {"configuration", configuration_json(scene, o.scheme_parameters)},
      {"chart_switches", switches},  // the first kSwitchesKept; events.csv has them all
      {"maxima",
       {{"drift_position", o.extremes.max_drift_position},
        {"drift_velocity", o.extremes.max_drift_velocity},
        {"abs_energy_rel_error", o.extremes.max_abs_energy_error},
        {"abs_vertical_momentum_rel_error", o.extremes.max_abs_vertical_momentum_error}}},
      {"multipliers", multipliers},
      {"accuracy_check", accuracy_check_json(o)},
      {"final",
       {{"t", f.t},
        {"q_WB", vec_json(f.q_WB)},
        {"omega_B", vec_json(f.omega_B)},
        {"drift_position", f.drift.position},
        {"drift_velocity", f.drift.velocity},
        {"energy", f.energy},
        {"energy_rel_error", f.energy_error},
        {"initial_energy", initial_energy(scene)},
        {"vertical_momentum", f.vertical_momentum},
        {"vertical_momentum_rel_error", f.vertical_momentum_error}}},
      {"final_row", final_row_json(f, o.multiplier_names)},
      {"columns_units", columns::units_line().substr(2)},
  });
  add_provenance(j);  // "build" and "run"
  return j;
}

}  // namespace

std::string summary_json(const Scene& scene, const SolveOutcome& o) {
  // A path from the command line need not be UTF-8; JSON must be: invalid bytes become U+FFFD.
  return summary(scene, o).dump(2, ' ', false, nlohmann::json::error_handler_t::replace);
}

void write_summary(const std::filesystem::path& path, const Scene& scene, const SolveOutcome& o) {
  write_file_atomically(path, summary_json(scene, o) + '\n');
}

std::string default_run_name(const Scene& scene) {
  return fmt::format("{}-{}-{}-{}", scene.name.empty() ? "scene" : scene.name,
                     to_string(scene.formulation.coordinates), to_string(scene.formulation.equations),
                     scene.formulation.scheme);
}

SolveOutcome solve_scene(const Scene& scene, const std::filesystem::path& out_dir) {
  if (scene.multibody) return solve_multibody_scene(scene, out_dir);
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec) throw InputError(fmt::format("{}: cannot create output folder: {}", out_dir.string(), ec.message()));

  std::unique_ptr<RunRecorder> recorder;
  SolveOutcome o = solve_with(scene, [&](const OneBodyView& problem) {
    recorder = std::make_unique<RunRecorder>(problem, scene, out_dir);
    return RunSink{recorder.get(), [&] { recorder->close(); }};
  });
  o.out_dir = out_dir;
  try {
    write_summary(out_dir / "summary.json", scene, o);
  } catch (const OutputError& e) {
    // On a full disk the summary fails after the step file did: the file that
    // failed first (the CSV) is the cause and is named first.
    if (o.output_lost) throw OutputError(fmt::format("{}; summary.json could not be written either: {}",
                                                     o.run.message, e.what()));
    throw;
  }
  if (o.output_lost) throw OutputError(o.run.message);
  return o;
}

SolveOutcome solve_with(const Scene& scene, const std::function<RunSink(const OneBodyView&)>& attach) {
  // The scene as a system of one pivoted body (model/one_body_system.hpp),
  // the model every scene runs on; the view reads it as the one-body records do.
  const Scene system_scene = one_body_system(scene);
  check_multibody_integrator(system_scene);
  multibody::MultibodyProblem system(system_scene);
  const OneBodyView view(system, scene);
  // What the scheme says of itself on this representation (its note, the
  // parameters it used): the registry's scheme, which writes the rows.
  const std::unique_ptr<ConstraintScheme> scheme = make_scheme(scene.formulation.scheme, scheme_settings(scene));
  SolveOutcome o;
  o.representation = view.representation().name();
  o.scheme = scheme->name();
  o.note = scheme->note(view.representation());
  o.multiplier_names = view.multiplier_names();
  o.unknowns = system.size();
  o.scheme_parameters = scheme->parameters();
  o.multipliers_error =
      multiplier_error_control(scene.solver.integrator, system.suppress_algebraic_error_test(), o.scheme);

  const RunSink recording = attach(view);
  RecordingSink& recorder = *recording.sink;
  InvariantMonitor monitor(view, scene, recorder);
  const auto t0 = std::chrono::steady_clock::now();
  std::string lost;  // the first output file that could not be written completely
  try {
    o.run = run_multibody(system, system_scene, monitor);
  } catch (const SolverError& e) {
    o.run.status = RunStatus::Failed;
    o.run.message = e.what();
  } catch (const OutputError& e) {
    lost = e.what();
  }
  o.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  try {
    if (recording.close) recording.close();
  } catch (const OutputError& e) {
    if (lost.empty()) lost = e.what();
  }
  o.extremes = recorder.extremes();
  o.drifts = monitor.drifts();
  o.warnings = monitor.warnings();
  if (!lost.empty()) {
    // Results that did not reach the disk are no success, however the solver fared.
    o.output_lost = true;
    o.run.status = RunStatus::Failed;
    o.run.t_reached = o.extremes.last.t;
    o.run.message = fmt::format("output lost: {}; the run stopped there (last recorded t = {:.9g} s) and what "
                                "was written is kept",
                                lost, o.extremes.last.t);
  }
  return o;
}

}  // namespace rigidae
