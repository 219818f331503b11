// rigidae solve SCENE: one run, its report on stdout, outputs in a folder.
#include <fmt/format.h>

#include "commands.hpp"
#include "rigidae/app/error_estimate.hpp"
#include "rigidae/app/solve.hpp"
#include "rigidae/core/error.hpp"
#include "rigidae/app/command_line.hpp"
#include "output_folder.hpp"
#include "plot_script.hpp"
#include "reference_csv.hpp"
#include "rigidae/app/reference.hpp"

namespace rigidae::cli {

namespace {

// The files the run wrote, as scene.output chose them (record/recorder.hpp).
std::string recorded_files(const OutputSettings& out) {
  std::string files;
  if (out.record == RecordMode::Steps) files += out.step_format == StepFormat::Npy ? "steps.npy, " : "steps.csv, ";
  if (out.record != RecordMode::None) files += "trajectory.csv, ";
  return files + "events.csv, summary.json";
}

void print_report(const Scene& scene, const SolveOutcome& o) {
  const RunResult& r = o.run;
  const IdaCounters& c = r.counters;
  fmt::print("rigidae {}: {} ({})\n", RIGIDAE_VERSION, scene.name, scene.source);
  fmt::print("  formulation   {} with scheme {}\n", o.representation, o.scheme);
  if (!o.note.empty()) fmt::print("  note          {}\n", o.note);
  const SolverSettings& solver = scene.solver;
  const std::string integrator =
      solver.integrator == "arkode-erk" ? solver.integrator + ":" + solver.erk_method : solver.integrator;
  if (solver.integrator_named || solver.integrator_choice.empty())
    fmt::print("  integrator    {}\n", integrator);
  else
    fmt::print("  integrator    {} ({}; name [solver] integrator or --integrator to choose)\n", integrator,
               solver.integrator_choice);
  fmt::print("  tolerances    rtol {:g}, atol {:g}\n", scene.solver.rtol, scene.solver.atol);
  fmt::print("  status        {}{}\n", to_string(r.status),
             r.status == RunStatus::Success ? fmt::format(": t = {:g} s reached", r.t_reached) : ": " + r.message);
  fmt::print("  work          {} steps, {} residual evaluations ({} for Jacobians), {} Jacobians, {:.3f} s wall\n",
             c.steps, c.residual_evals + c.jacobian_residual_evals, c.jacobian_residual_evals, c.jacobian_evals,
             o.wall_seconds);
  fmt::print("  failures      {} error-test, {} Newton convergence\n", c.error_test_fails, c.nonlinear_conv_fails);
  fmt::print("{}", o.final_report);
  if (!r.switches.empty())
    fmt::print("  charts        {} switches; first at t = {:.6g} s ({} -> {})\n", r.switch_count, r.switches.front().t,
               r.switches.front().from, r.switches.front().to);
  // IDA and CVODE's Adams restart after a projection; CVODE's BDF and ARKODE project inside their steps.
  const bool restarts_after_projection = solver.integrator == "ida" || solver.integrator == "cvode-adams";
  const char* integrator_name = solver.integrator == "ida" ? "IDA" : "CVODE";
  if (c.projections > 0)
    fmt::print("  projections   {} ({})\n", c.projections,
               restarts_after_projection ? fmt::format("each restarts {} at order 1", integrator_name)
                                         : std::string("inside the integrator's steps"));
  if (c.restarts > 0) fmt::print("  restarts      {} ({} calls)\n", c.restarts,
                                 solver.integrator == "ida"           ? "IDAReInit"
                                 : solver.integrator == "arkode-erk"  ? "ERKStepReInit"
                                                                      : "CVodeReInit");
  fmt::print("  outputs       {}/ ({})\n", o.out_dir.string(), recorded_files(scene.output));
}

}  // namespace

int solve_command(const std::vector<std::string>& args) {
  const CommandInfo& info = command_info("solve");
  const CommandLine cl = parse_arguments(args, info);
  if (cl.help) {
    fmt::print("{}", command_help(info));
    return 0;
  }
  const Scene scene = scene_from(cl, info);
  const bool error_estimate = cl.has("--error-estimate");
  if (error_estimate && scene.output.record == RecordMode::None)
    throw InputError("--error-estimate compares the output grids of two runs: it needs --record steps or grid, "
                     "not none");
  if ((cl.has("--view") || cl.has("--vtk")) && scene.output.record == RecordMode::None)
    throw InputError("--view and --vtk draw the output grid (trajectory.csv): they need --record steps or grid, "
                     "not none");
  const std::string out_arg = cl.text("--out");
  const bool quiet = cl.has("--quiet");

  const std::filesystem::path out =
      out_arg.empty() ? std::filesystem::path("out") / default_run_name(scene) : std::filesystem::path(out_arg);
  create_output_folder(out, /*disposable=*/true);
  const SolveOutcome o = solve_scene(scene, out);
  if (!quiet || o.run.status != RunStatus::Success) print_report(scene, o);
  for (const std::string& w : o.start_warnings) fmt::print(stderr, "rigidae: warning: {}\n", w);
  // A scene with a closed form (a free body, a symmetric Lagrange top): the
  // error against it on the output grid, printed and in summary.json, and the
  // closed form kept beside the run (reference.csv) to draw error against time.
  // Only for a run that reached the end: the closed form is evaluated on the
  // whole output grid, which an interrupted run of a long span never wrote.
  if (scene.output.record != RecordMode::None && o.run.status == RunStatus::Success)
    if (const auto ref = exact_reference(scene, nullptr)) {
      write_reference_csv(*ref, out / "reference.csv");
      // A mechanism's closed form (the bodies' positions) is reported by the verdict below.
      if (ref->grid.layout == GridLayout::OneBody) {
        const OrientationError e = error_against(o, *ref);
        add_closed_form_error_to_summary(out / "summary.json", e);
        if (!quiet)
          fmt::print("  closed form   orientation error {:.3g} rad at t = {:g} s, max {:.3g} rad over the output "
                     "grid (reference.csv)\n",
                     e.final, e.t_final, e.max);
      }
    }
  // The verdict (app/error_estimate.hpp): the closed form's error where the
  // scene has one; else, with --error-estimate, a companion run at rtol/100;
  // else "accuracy not estimated" (a companion adds a median 180 % to the
  // wall time of the shipped scenes, tools/error_estimate_cost.py, past the 30 % a default may add:
  // docs/accuracy_check.md).
  ErrorEstimate verdict;
  if (o.run.status == RunStatus::Success) {
    verdict = accuracy_verdict(scene, o, error_estimate, "--error-estimate");
    add_error_estimate_to_summary(out / "summary.json", verdict);
    if (!quiet && verdict.estimated()) {
      fmt::print("  accuracy      {}\n", describe(verdict));
      if (verdict.companion_orientation)
        fmt::print("                companion at rtol {:g}: orientation {:.2e} rad max over the grid ({:.3f} s "
                   "wall)\n",
                   verdict.rtol, verdict.companion_orientation->max, verdict.companion_wall_s);
    }
    if (!verdict.estimated() && !quiet) fmt::print(stderr, "rigidae: note: {}\n", describe(verdict));
  }
  // Accuracy warnings (app/accuracy_check.hpp) reach stderr even with --quiet.
  for (const AccuracyWarning& w : o.warnings) fmt::print(stderr, "rigidae: warning: {}\n", w.message);
  for (const AccuracyWarning& w : verdict.warnings) fmt::print(stderr, "rigidae: warning: {}\n", w.message);
  if (cl.has("--plot")) {
    // reference.csv (above) lets the figures draw the error against time.
    std::vector<std::string> plot_args{out.string()};
    if (quiet) plot_args.push_back("--quiet");
    run_plot_script("plot_solve.py", plot_args);
  }
  // The page and the ParaView files of what was computed, also of a run that
  // stopped early (they show how far it got).
  bool drawn = true;
  if (cl.has("--view")) drawn = draw_command_run("view", {out.string(), "--scene", scene.source}) == 0 && drawn;
  if (cl.has("--vtk")) drawn = draw_command_run("vtk", {out.string(), "--scene", scene.source}) == 0 && drawn;
  if (o.run.status != RunStatus::Success) {
    fmt::print(stderr, "rigidae: error: {}\n", o.run.message);
    return 1;
  }
  return drawn ? 0 : 1;
}

}  // namespace rigidae::cli
