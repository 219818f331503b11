// Executing a study's runs: each measured once with its grid recorded (errors
// over the grid, counters, drifts, accuracy warnings), then timed over
// repeats of the same run recording nothing (app/unrecorded_run.hpp: the
// wall time users see with save_everystep = false, and the error of its
// final state), written under a temporary name and renamed when complete.
#include <fmt/format.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>

#include "rigidae/app/accuracy.hpp"
#include "rigidae/app/error_estimate.hpp"
#include "rigidae/app/reference.hpp"
#include "rigidae/app/solve.hpp"
#include "rigidae/app/study.hpp"
#include "rigidae/app/unrecorded_run.hpp"
#include "machine_record.hpp"
#include "rigidae/core/error.hpp"
#include "rigidae/io/checked_file.hpp"
#include "rigidae/record/trajectory_csv.hpp"
#include "rigidae/solver/ida_driver.hpp"

namespace rigidae {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// JSON has no NaN: unmeasured values become null.
json number(double x) { return std::isfinite(x) ? json(x) : json(nullptr); }

json stats(const ErrorStats& e) { return {{"final", number(e.final)}, {"l2", number(e.l2)}, {"max", number(e.max)}}; }

// A name no other process writing into the same OUT will pick.
fs::path temporary_name(const fs::path& final_path) {
  char host[256] = "host";
  gethostname(host, sizeof host - 1);
  return final_path.parent_path() / fmt::format(".{}.tmp-{}-{}", final_path.filename().string(), host, getpid());
}

// Temporary folders that killed workers left behind (SIGKILL, a node lost,
// a second signal after the grace period: nothing ran their cleanup). Only
// those of this host whose process is gone are removed: another worker on
// this host may be writing its own right now, and of another host's nothing
// can be known from here (it is left; its folder never counts as a run).
// Returns the folders removed.
std::vector<fs::path> remove_dead_temporaries(const fs::path& out) {
  char host[256] = "host";
  gethostname(host, sizeof host - 1);
  const std::string mark = fmt::format(".tmp-{}-", host);
  std::vector<fs::path> dead;
  std::error_code ec;
  for (const fs::path& top : {out / "runs", out / "reference"}) {
    if (!fs::is_directory(top, ec)) continue;
    for (auto it = fs::recursive_directory_iterator(top, ec); !ec && it != fs::recursive_directory_iterator();
         it.increment(ec)) {
      const std::string name = it->path().filename().string();
      const std::size_t at = name.rfind(mark);
      if (name.empty() || name[0] != '.' || at == std::string::npos) continue;
      const std::string digits = name.substr(at + mark.size());
      if (digits.empty() || digits.find_first_not_of("0123456789") != std::string::npos) continue;
      const long pid = std::strtol(digits.c_str(), nullptr, 10);
      if (pid == getpid() || (::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH)) {
        dead.push_back(it->path());
        it.disable_recursion_pending();
      }
    }
  }
  for (const fs::path& d : dead) fs::remove_all(d, ec);
  return dead;
}

// Moves a finished folder into place. Another worker may have finished the
// same run (or reference) meanwhile: then its folder stands and ours goes.
void publish(const fs::path& tmp, const fs::path& final_path) {
  std::error_code ec;
  fs::rename(tmp, final_path, ec);
  if (ec) {
    if (!fs::exists(final_path)) throw OutputError(fmt::format("cannot move {} to {}: {}", tmp.string(), final_path.string(), ec.message()));
    fs::remove_all(tmp, ec);
  }
}

// A folder at a final name without its completion marker is not ours (no
// worker renames an incomplete folder into place): a leftover, replaced.
void replace_incomplete(const fs::path& final_path, const char* marker) {
  std::error_code ec;
  if (fs::exists(final_path, ec) && !fs::exists(final_path / marker, ec)) fs::remove_all(final_path, ec);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

// The references of a study's scenes, made once per process and shared
// between processes through OUT/reference/SCENE.
class StudyReferences {
 public:
  StudyReferences(const StudySpec& spec, fs::path out) : spec_(spec), out_(std::move(out)) {}

  // nullptr when interrupted while making it; SolverError when it failed.
  const ReferenceTrajectory* of(std::size_t scene) {
    auto it = cache_.find(scene);
    if (it != cache_.end()) return &it->second;
    const Scene& s = spec_.scenes[scene];
    const std::string kind = study_reference_kind(spec_, s);
    std::string why;
    std::optional<ReferenceTrajectory> ref = kind == "tight" ? std::nullopt : exact_reference(s, &why);
    if (!ref && kind == "exact")  // load_study checks this; a scene file edited since is caught here
      throw InputError(fmt::format("{}: no exact solution for this scene: {}", s.source, why));
    if (!ref) ref = tight(s);
    if (!ref) return nullptr;
    return &cache_.emplace(scene, std::move(*ref)).first->second;
  }

 private:
  std::optional<ReferenceTrajectory> tight(const Scene& s) {
    const double rtol = study_reference_rtol(spec_);
    const fs::path dir = out_ / "reference" / s.name;
    if (std::optional<ReferenceTrajectory> ref = read_reference(dir)) {
      if (ref->rtol != rtol)
        throw InputError(fmt::format("{} holds a reference at rtol {}, but this study asks for rtol {}: give "
                                     "another --out, or delete that folder to make it again",
                                     dir.string(), ref->rtol, rtol));
      return ref;
    }
    fs::create_directories(dir.parent_path());
    const fs::path tmp = temporary_name(dir);
    ReferenceTrajectory ref = make_reference(s, "tight", rtol, tmp, nullptr);
    if (!ref.ok) {
      std::error_code ec;
      fs::remove_all(tmp, ec);
      if (g_interrupt_requested.load()) return std::nullopt;
      throw SolverError(fmt::format("the tight reference of scene '{}' ({} at rtol {}) failed: {}; no run of this "
                                    "scene can be measured (try a looser reference_rtol in the study file)",
                                    s.name, ref.combination, rtol, ref.message));
    }
    replace_incomplete(dir, "reference.json");
    publish(tmp, dir);
    return ref;
  }

  const StudySpec& spec_;
  fs::path out_;
  std::map<std::size_t, ReferenceTrajectory> cache_;
};

// What the timed repeats measured.
struct Timing {
  std::vector<double> wall;           // unrecorded runs after the warm-ups
  double final_error = std::numeric_limits<double>::quiet_NaN();  // of the last timed run's final state
  bool same_steps = true;             // every timed run took the recorded run's steps
};

json run_record(const StudySpec& spec, const StudyRun& run, const SolveOutcome& o, const Timing& timing,
                const RunAccuracy& acc, const ReferenceTrajectory& ref, const ErrorEstimate& verdict) {
  const IdaCounters& c = o.run.counters;
  const std::vector<double>& wall = timing.wall;
  return {
      {"id", run.id(spec)},
      {"study", spec.name},
      {"scene", spec.scenes[run.scene].name},
      {"scene_source", spec.scenes[run.scene].source},
      {"combination", run.combination.name()},
      {"coordinates", to_string(run.combination.coordinates)},
      {"equations", to_string(run.combination.equations)},
      {"scheme", run.combination.scheme},
      {"integrator", run.combination.integrator_label()},
      {"rtol", run.rtol},
      {"atol", run.atol},
      {"status", to_string(o.run.status)},
      {"message", o.run.message},
      {"warmups", spec.warmups},
      {"wall_s", wall},
      {"wall_min_s", *std::min_element(wall.begin(), wall.end())},
      {"wall_median_s", median(wall)},
      {"timing",
       {{"what", "runs recording nothing (no step or grid file, no per-step observation): the integration alone; "
                 "the recorded run's wall time is recorded_wall_s"},
        {"recorded_wall_s", o.wall_seconds},
        {"final_error_rad", number(timing.final_error)},
        {"same_steps_as_recorded", timing.same_steps}}},
      {"machine", machine_record()},
      {"counters",
       {{"steps", c.steps},
        {"residual_evals", c.residual_evals},
        {"jacobian_residual_evals", c.jacobian_residual_evals},
        {"jacobian_evals", c.jacobian_evals},
        {"nonlinear_iters", c.nonlinear_iters},
        {"error_test_fails", c.error_test_fails},
        {"nonlinear_conv_fails", c.nonlinear_conv_fails},
        {"restarts", c.restarts},
        {"projections", c.projections},
        {"chart_switches", o.run.switch_count}}},
      {"drift",
       {{"max_position", number(o.extremes.max_drift_position)},
        {"max_velocity", number(o.extremes.max_drift_velocity)},
        {"max_abs_energy_rel_error", number(o.extremes.max_abs_energy_error)}}},
      {"errors",
       {{"orientation_rad", stats(acc.orientation_rad)},
        {"angular_velocity_rad_s", stats(acc.angular_velocity)},
        {"position_m", stats(acc.position_m)},
        {"lambda", stats(acc.lambda)},
        {"mu", stats(acc.mu)},
        {"scd", number(acc.scd)},
        {"mescd", number(acc.mescd)},
        {"points_compared", acc.points_compared}}},
      {"warning_summary", warnings_cell(o.warnings)},
      {"warnings", [&] {
         json a = json::array();
         for (const AccuracyWarning& w : o.warnings)
           a.push_back({{"quantity", w.quantity}, {"drift", w.drift}, {"limit", w.limit}, {"message", w.message}});
         return a;
       }()},
      {"error_estimate", error_estimate_json(verdict)},
      {"reference", ref.describe()},
      {"reference_accuracy_rad", number(ref.accuracy_rad)},
  };
}

}  // namespace

bool run_study(const StudySpec& spec, const std::vector<StudyRun>& runs, const StudyRunOptions& opt) {
  for (const fs::path& d : remove_dead_temporaries(opt.out))
    if (opt.note) opt.note(fmt::format("removed {}: the temporary folder of a run killed before it finished", d.string()));
  StudyReferences references(spec, opt.out);
  StudyProgress p;
  p.total = static_cast<int>(runs.size());
  for (const StudyRun& run : runs) {
    if (g_interrupt_requested.load()) return false;
    const fs::path final_path = run_folder(opt.out, spec, run);
    p.last = run.id(spec);
    if (run_complete(opt.out, spec, run)) {
      ++p.done, ++p.skipped;
      if (opt.progress) opt.progress(p);
      continue;
    }
    const ReferenceTrajectory* ref = references.of(run.scene);
    if (!ref) return false;  // interrupted while making it
    const Scene scene = run.scene_for(spec);
    fs::create_directories(final_path.parent_path());
    const fs::path tmp = temporary_name(final_path);
    std::error_code ec;
    fs::remove_all(tmp, ec);

    // The recorded run: errors over the grid, counters, drifts and warnings.
    const SolveOutcome outcome = solve_scene(scene, tmp);
    if (outcome.run.status == RunStatus::Interrupted) {
      fs::remove_all(tmp, ec);
      return false;
    }
    Timing timing;
    // Warm-ups and repeats time the same run recording nothing; a run that fails is not repeated.
    if (outcome.run.status != RunStatus::Success) timing.wall.push_back(outcome.wall_seconds);
    for (int k = 0; k < spec.warmups + spec.repeats && outcome.run.status == RunStatus::Success; ++k) {
      const UnrecordedRun timed = run_unrecorded(scene);
      if (timed.run.status == RunStatus::Interrupted || g_interrupt_requested.load()) {
        fs::remove_all(tmp, ec);
        return false;
      }
      timing.same_steps = timing.same_steps && timed.run.counters.steps == outcome.run.counters.steps;
      if (k >= spec.warmups) timing.wall.push_back(timed.wall_seconds);
      timing.final_error = final_orientation_error(timed, *ref);
    }
    const RunAccuracy acc = measure_run_accuracy(scene, tmp, *ref, outcome.run.status == RunStatus::Success);
    // The verdict: the closed form, or a companion at rtol/100 into tmp/error_estimate (not timed).
    SolveOutcome judged = outcome;
    judged.out_dir = tmp;
    const ErrorEstimate verdict = accuracy_verdict(scene, judged, opt.error_estimate, "study without --no-error-estimate");
    if (g_interrupt_requested.load()) {
      fs::remove_all(tmp, ec);
      return false;
    }
    if (outcome.run.status == RunStatus::Success) add_error_estimate_to_summary(tmp / "summary.json", verdict);
    apply_verdict(judged, verdict);
    if (!opt.keep_steps) fs::remove(tmp / "steps.csv", ec);  // summaries and grids always stay
    // run.json marks the run complete: written last, whole or not at all.
    write_file_atomically(tmp / "run.json", run_record(spec, run, judged, timing, acc, *ref, verdict).dump(2) + "\n");
    replace_incomplete(final_path, "run.json");
    publish(tmp, final_path);
    ++p.done;
    if (outcome.run.status != RunStatus::Success) ++p.failed;
    if (opt.progress) opt.progress(p);
  }
  return true;
}

}  // namespace rigidae
