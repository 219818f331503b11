#include "rigidae/app/solve.hpp"

#include "solve_multibody.hpp"

#include <fmt/format.h>
#include <sundials/sundials_config.h>

#include <chrono>
#include <fstream>
#include <nlohmann/json.hpp>

#include "rigidae/core/error.hpp"
#include "rigidae/dae/dae_system.hpp"
#include "rigidae/dae/single_body_problem.hpp"
#include "rigidae/so3/rotation.hpp"

namespace rigidae {

namespace {

nlohmann::json vec_json(const Eigen::Ref<const Eigen::VectorXd>& v) {
  return std::vector<double>(v.data(), v.data() + v.size());
}

nlohmann::json mat_json(const Mat3& M) {
  return {vec_json(M.row(0).transpose()), vec_json(M.row(1).transpose()), vec_json(M.row(2).transpose())};
}

nlohmann::json configuration_json(const Scene& s) {
  nlohmann::json euler = {{"sequence", s.formulation.euler.sequence ? s.formulation.euler.sequence->name() : "auto"},
                          {"switching", s.formulation.euler.switching},
                          {"switch_threshold", s.formulation.euler.switch_threshold}};
  return {
      {"scene", s.source},
      {"name", s.name},
      {"body",
       {{"mass_kg", s.body.mass},
        {"inertia_com_kg_m2", mat_json(s.body.inertia_com)},
        {"center_of_mass_m", vec_json(s.body.com_B)}}},
      {"support", s.support == Support::FixedPoint ? "fixed_point" : "free"},
      {"gravity_m_s2", vec_json(s.gravity_W)},
      {"initial", {{"R_WB", mat_json(s.R0_WB)}, {"omega_B_rad_s", vec_json(s.omega0_B)}}},
      {"time_s", {{"start", s.time.start}, {"end", s.time.end}, {"output_step", s.time.output_step}}},
      {"formulation",
       {{"coordinates", to_string(s.formulation.coordinates)},
        {"equations", to_string(s.formulation.equations)},
        {"scheme", s.formulation.scheme},
        {"euler_angles", euler},
        {"baumgarte", {{"a", baumgarte_gains(s).first}, {"b", baumgarte_gains(s).second}}},
        {"projection",
         {{"when", s.formulation.projection.every_step ? "every_step" : "threshold"},
          {"threshold", projection_threshold(s)}}}}},
      {"solver",
       {{"rtol", s.solver.rtol},
        {"atol", s.solver.atol},
        {"max_steps", s.solver.max_steps},
        {"max_order", s.solver.max_order},
        {"initial_step", s.solver.initial_step},
        {"linear_solver", s.solver.linear_solver},
        {"jacobian", s.solver.jacobian}}},
  };
}

void write_summary(const std::filesystem::path& path, const Scene& scene, const SolveOutcome& o) {
  const IdaCounters& c = o.run.counters;
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

  nlohmann::json j = {
      {"units", "SI: s, rad, rad/s, J, kg m^2/s; quaternions scalar first, R_WB body to space"},
      {"configuration", configuration_json(scene)},
      {"representation", o.representation},
      {"scheme", o.scheme},
      {"note", o.note},
      {"versions", {{"rigidae", RIGIDAE_VERSION}, {"sundials", SUNDIALS_VERSION},
                    {"eigen", fmt::format("{}.{}.{}", EIGEN_WORLD_VERSION, EIGEN_MAJOR_VERSION, EIGEN_MINOR_VERSION)}}},
      {"status", to_string(o.run.status)},
      {"message", o.run.message},
      {"t_reached", o.run.t_reached},
      {"wall_time_s", o.wall_seconds},
      {"initial_residual_max_abs", o.run.initial_residual},
      {"counters",
       {{"steps", c.steps},
        {"residual_evals", c.residual_evals},
        {"jacobian_evals", c.jacobian_evals},
        {"jacobian_residual_evals", c.jacobian_residual_evals},
        {"nonlinear_iters", c.nonlinear_iters},
        {"nonlinear_conv_fails", c.nonlinear_conv_fails},
        {"error_test_fails", c.error_test_fails},
        {"linear_setups", c.linear_setups},
        {"root_evals", c.root_evals},
        {"restarts", c.restarts},
        {"projections", c.projections},
        {"last_step", c.last_step},
        {"last_order", c.last_order}}},
      {"chart_switch_count", o.run.switch_count},
      {"chart_switches", switches},  // the first kSwitchesKept; events.csv has them all
      {"maxima",
       {{"drift_position", o.extremes.max_drift_position},
        {"drift_velocity", o.extremes.max_drift_velocity},
        {"abs_energy_rel_error", o.extremes.max_abs_energy_error},
        {"abs_vertical_momentum_rel_error", o.extremes.max_abs_vertical_momentum_error}}},
      {"multipliers", multipliers},
      {"final",
       {{"t", f.t},
        {"q_WB", vec_json(f.q_WB)},
        {"omega_B", vec_json(f.omega_B)},
        {"drift_position", f.drift.position},
        {"drift_velocity", f.drift.velocity},
        {"energy", f.energy},
        {"energy_rel_error", f.energy_error},
        {"vertical_momentum", f.vertical_momentum},
        {"vertical_momentum_rel_error", f.vertical_momentum_error}}},
  };
  std::ofstream out(path);
  if (!out) throw InputError(fmt::format("{}: cannot open for writing", path.string()));
  // A path from the command line need not be UTF-8; JSON must be: invalid bytes become U+FFFD.
  out << j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) << '\n';
}

}  // namespace

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

  std::unique_ptr<DaeSystem> dae = assemble_dae(scene);
  SolveOutcome o;
  o.out_dir = out_dir;
  o.representation = dae->representation().name();
  o.scheme = dae->scheme().name();
  o.note = dae->scheme().note(dae->representation());
  o.multiplier_names = dae->multiplier_names();

  RunRecorder recorder(*dae, scene, out_dir);
  const auto t0 = std::chrono::steady_clock::now();
  try {
    SingleBodyProblem problem(*dae, scene.formulation.euler, scene.R0_WB, scene.omega0_B, scene.source);
    o.run = integrate(problem, scene.solver, scene.time, recorder);
  } catch (const SolverError& e) {
    o.run.status = RunStatus::Failed;
    o.run.message = e.what();
  }
  o.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  recorder.flush();
  o.extremes = recorder.extremes();
  write_summary(out_dir / "summary.json", scene, o);
  return o;
}

}  // namespace rigidae
