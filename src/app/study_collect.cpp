// Merging a study's run folders into results.csv and the best-per-target table.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <nlohmann/json.hpp>

#include "rigidae/app/study.hpp"
#include "rigidae/core/error.hpp"
#include "rigidae/io/checked_file.hpp"

namespace rigidae {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;


double num(const json& j) { return j.is_number() ? j.get<double>() : kNaN; }

std::string cell(double x) { return std::isnan(x) ? "" : fmt::format("{:.6e}", x); }

std::string quoted(std::string s) {
  std::replace(s.begin(), s.end(), '"', '\'');
  std::replace(s.begin(), s.end(), '\n', ' ');
  return "\"" + s + "\"";
}

json read_run(const fs::path& file) {
  std::ifstream in(file);
  try {
    return json::parse(in);
  } catch (const json::exception& e) {
    throw InputError(fmt::format("{}: not a run record ({}); delete its folder to redo the run", file.string(),
                                 e.what()));
  }
}

// The columns of results.csv, in order, each read from run.json by its JSON pointer.
enum class Kind { Text, Quoted, Tolerance, Number, Integer, Size };
struct Column {
  const char* name;
  const char* pointer;
  Kind kind;
};

const Column kColumns[] = {
    {"study", "/study", Kind::Text},
    {"scene", "/scene", Kind::Text},
    {"combination", "/combination", Kind::Text},
    {"coordinates", "/coordinates", Kind::Text},
    {"equations", "/equations", Kind::Text},
    {"scheme", "/scheme", Kind::Text},
    {"integrator", "/integrator", Kind::Text},
    {"rtol", "/rtol", Kind::Tolerance},
    {"atol", "/atol", Kind::Tolerance},
    {"status", "/status", Kind::Text},
    {"wall_min_s", "/wall_min_s", Kind::Number},
    {"wall_median_s", "/wall_median_s", Kind::Number},
    {"wall_count", "/wall_s", Kind::Size},
    {"warmups", "/warmups", Kind::Integer},
    {"steps", "/counters/steps", Kind::Integer},
    {"residual_evals", "/counters/residual_evals", Kind::Integer},
    {"jacobian_residual_evals", "/counters/jacobian_residual_evals", Kind::Integer},
    {"jacobian_evals", "/counters/jacobian_evals", Kind::Integer},
    {"nonlinear_iters", "/counters/nonlinear_iters", Kind::Integer},
    {"error_test_fails", "/counters/error_test_fails", Kind::Integer},
    {"nonlinear_conv_fails", "/counters/nonlinear_conv_fails", Kind::Integer},
    {"restarts", "/counters/restarts", Kind::Integer},
    {"projections", "/counters/projections", Kind::Integer},
    {"chart_switches", "/counters/chart_switches", Kind::Integer},
    {"orientation_error_final_rad", "/errors/orientation_rad/final", Kind::Number},
    {"orientation_error_l2_rad", "/errors/orientation_rad/l2", Kind::Number},
    {"orientation_error_max_rad", "/errors/orientation_rad/max", Kind::Number},
    {"final_state_error_rad", "/timing/final_error_rad", Kind::Number},
    {"position_error_final_m", "/errors/position_m/final", Kind::Number},
    {"position_error_l2_m", "/errors/position_m/l2", Kind::Number},
    {"position_error_max_m", "/errors/position_m/max", Kind::Number},
    {"angular_velocity_error_final_rad_s", "/errors/angular_velocity_rad_s/final", Kind::Number},
    {"angular_velocity_error_l2_rad_s", "/errors/angular_velocity_rad_s/l2", Kind::Number},
    {"angular_velocity_error_max_rad_s", "/errors/angular_velocity_rad_s/max", Kind::Number},
    {"lambda_error_final", "/errors/lambda/final", Kind::Number},
    {"lambda_error_l2", "/errors/lambda/l2", Kind::Number},
    {"lambda_error_max", "/errors/lambda/max", Kind::Number},
    {"mu_error_final", "/errors/mu/final", Kind::Number},
    {"mu_error_l2", "/errors/mu/l2", Kind::Number},
    {"mu_error_max", "/errors/mu/max", Kind::Number},
    {"scd", "/errors/scd", Kind::Number},
    {"mescd", "/errors/mescd", Kind::Number},
    {"max_drift_position", "/drift/max_position", Kind::Number},
    {"max_drift_velocity", "/drift/max_velocity", Kind::Number},
    {"max_abs_energy_rel_error", "/drift/max_abs_energy_rel_error", Kind::Number},
    {"reference_accuracy_rad", "/reference_accuracy_rad", Kind::Number},
    {"reference", "/reference", Kind::Quoted},
    {"run_dir", "/id", Kind::Text},
    {"message", "/message", Kind::Quoted},
    {"warnings", "/warning_summary", Kind::Quoted},  // accuracy-check warnings (app/accuracy_check.hpp)
    {"recorded_wall_s", "/timing/recorded_wall_s", Kind::Number},
    {"host", "/machine/host", Kind::Quoted},
    {"cpu_model", "/machine/cpu_model", Kind::Quoted},
    {"load_average", "/machine/load_average", Kind::Quoted},
    {"commit", "/machine/commit", Kind::Text},
    {"compiler", "/machine/compiler", Kind::Quoted},
};

std::string cell(const json& run, const Column& c) {
  if (!run.contains(json::json_pointer(c.pointer))) return "";  // a record from before the column existed
  const json& v = run.at(json::json_pointer(c.pointer));
  switch (c.kind) {
    case Kind::Text: return v.get<std::string>();
    case Kind::Quoted: return quoted(v.get<std::string>());
    case Kind::Tolerance: return fmt::format("{}", v.get<double>());
    case Kind::Integer: return std::to_string(v.get<long>());
    case Kind::Size: return std::to_string(v.size());
    default: return cell(num(v));
  }
}

struct Best {
  const json* by_time = nullptr;   // least wall time (minimum of repeats)
  const json* by_evals = nullptr;  // fewest residual evaluations (a count: repeatable)
};

long evals(const json& r) {
  return r["counters"]["residual_evals"].get<long>() + r["counters"]["jacobian_residual_evals"].get<long>();
}

std::string best_tables(const StudySpec& spec, const std::vector<json>& runs, bool markdown) {
  std::string s;
  for (const Scene& scene : spec.scenes) {
    s += markdown ? fmt::format("\n### {}\n\n", scene.name) : fmt::format("\n{}\n", scene.name);
    if (markdown)
      s += "| error target, rad | fastest | rtol | wall min, s | error, rad | fewest residual evals | rtol | evals | "
           "error, rad |\n|---|---|---|---|---|---|---|---|---|\n";
    else
      s += fmt::format("  {:<10} {:<28} {:>7} {:>10} {:>9}   {:<28} {:>7} {:>9} {:>9}\n", "target", "fastest", "rtol",
                       "wall min s", "error", "fewest residual evals", "rtol", "evals", "error");
    for (double target : spec.targets) {
      Best b;
      for (const json& r : runs) {
        if (r["scene"] != scene.name || r["status"] != "success") continue;
        const double e = num(r["errors"]["orientation_rad"]["final"]);
        if (!(e <= target)) continue;
        if (!b.by_time || r["wall_min_s"].get<double>() < (*b.by_time)["wall_min_s"].get<double>()) b.by_time = &r;
        if (!b.by_evals || evals(r) < evals(*b.by_evals)) b.by_evals = &r;
      }
      auto err = [](const json* r) { return fmt::format("{:.1e}", num((*r)["errors"]["orientation_rad"]["final"])); };
      if (!b.by_time) {
        s += markdown ? fmt::format("| {:g} | none reached it | | | | | | | |\n", target)
                      : fmt::format("  {:<10g} none of the runs reached it\n", target);
        continue;
      }
      const json& t = *b.by_time;
      const json& v = *b.by_evals;
      const auto row = markdown ? fmt::runtime("| {:g} | {} | {:g} | {:.4f} | {} | {} | {:g} | {} | {} |\n")
                                : fmt::runtime("  {:<10g} {:<28} {:>7g} {:>10.4f} {:>9}   {:<28} {:>7g} {:>9} {:>9}\n");
      s += fmt::format(row, target, t["combination"].get<std::string>(), t["rtol"].get<double>(),
                       t["wall_min_s"].get<double>(), err(&t), v["combination"].get<std::string>(),
                       v["rtol"].get<double>(), evals(v), err(&v));
    }
  }
  return s;
}

}  // namespace

std::string collect_study(const StudySpec& spec, const fs::path& out, std::vector<std::string>* missing) {
  std::vector<json> runs;
  for (const StudyRun& run : plan_study(spec)) {
    if (!run_complete(out, spec, run)) {
      if (missing) missing->push_back(run.id(spec));
      continue;
    }
    runs.push_back(read_run(run_folder(out, spec, run) / "run.json"));
  }
  {
    std::ostringstream f;
    f << "# units: wall s (min and median of the timed repeats after the warm-ups, runs recording nothing; "
         "recorded_wall_s: the run that wrote the grid); orientation errors rad (angle to the reference; multibody: "
         "the worst body), final_state_error_rad from a timed run's final state; position errors m (multibody: the "
         "worst body's centre of mass); angular velocity errors rad/s (|delta omega_B|, body frame); lambda errors J and mu errors 1/s (max "
         "over the multipliers); _l2 is the root mean square over the output grid; scd/mescd as the IVP Test Set "
         "defines them on the final (q_WB, omega_B); drift |Phi| 1, |dPhi/dt| 1/s\n";
    for (std::size_t k = 0; k < std::size(kColumns); ++k) f << (k ? "," : "") << kColumns[k].name;
    f << "\n";
    for (const json& r : runs) {
      for (std::size_t k = 0; k < std::size(kColumns); ++k) f << (k ? "," : "") << cell(r, kColumns[k]);
      f << "\n";
    }
    write_file_atomically(out / "results.csv", f.str());
  }
  const std::string header =
      fmt::format("study {}: best combination per final orientation error target ({} of {} runs complete)\n",
                  spec.name, runs.size(), runs.size() + (missing ? missing->size() : 0));
  const std::string text = header + best_tables(spec, runs, false);
  write_file_atomically(out / "best.txt", text);
  write_file_atomically(out / "best.md", "## " + header + best_tables(spec, runs, true));
  return text;
}

}  // namespace rigidae
