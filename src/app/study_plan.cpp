// The deterministic list of a study's runs, its slices, and their folders.
#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cstdlib>

#include "rigidae/app/reference.hpp"
#include "rigidae/app/study.hpp"
#include "rigidae/core/error.hpp"

namespace rigidae {

std::string StudyRun::id(const StudySpec& spec) const {
  // Shortest round-trip text: distinct tolerances never share a folder.
  return fmt::format("{}/{}/rtol_{}_atol_{}", spec.scenes[scene].name, combination.folder(), rtol, atol);
}

Scene StudyRun::scene_for(const StudySpec& spec) const {
  Scene s = combination.applied_to(spec.scenes[scene]);
  s.solver.rtol = rtol;
  s.solver.atol = atol;
  return s;
}

std::string study_reference_kind(const StudySpec& spec, const Scene& scene) {
  return spec.reference.empty() ? to_string(scene.reference) : spec.reference;
}

double study_reference_rtol(const StudySpec& spec) {
  return spec.reference_rtol.value_or(default_reference_rtol(*std::min_element(spec.rtols.begin(), spec.rtols.end())));
}

std::vector<Combination> study_combinations(const StudySpec& spec, const Scene& scene) {
  std::vector<Combination> combos;
  for (const Combination& c : combinations_for(scene, spec.integrators, spec.source)) {
    const bool in = spec.only.empty() || std::any_of(spec.only.begin(), spec.only.end(),
                                                     [&](const std::string& p) { return matches(c, p, "*"); });
    const bool out =
        std::any_of(spec.skip.begin(), spec.skip.end(), [&](const std::string& p) { return matches(c, p, "*"); });
    if (in && !out) combos.push_back(c);
  }
  return combos;
}

std::vector<StudyRun> plan_study(const StudySpec& spec) {
  std::vector<double> rtols = spec.rtols;
  std::sort(rtols.begin(), rtols.end(), std::greater<>());  // loose to tight
  std::vector<StudyRun> runs;
  for (std::size_t s = 0; s < spec.scenes.size(); ++s)
    for (const Combination& c : study_combinations(spec, spec.scenes[s]))
      for (double rtol : rtols) {
        StudyRun r;
        r.index = static_cast<int>(runs.size());
        r.scene = s;
        r.combination = c;
        r.rtol = rtol;
        r.atol = spec.atol_tied ? spec.atol_ratio * rtol : spec.atol;
        runs.push_back(r);
      }
  return runs;
}

std::vector<StudyRun> select_shard(const std::vector<StudyRun>& runs, Shard shard) {
  std::vector<StudyRun> slice;
  for (const StudyRun& r : runs)
    if (r.index % shard.count == shard.index) slice.push_back(r);
  return slice;
}

namespace {

bool parse_int(std::string_view s, int& v) {
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  return ec == std::errc() && end == s.data() + s.size();
}

}  // namespace

Shard parse_shard(const std::string& text) {
  const std::size_t slash = text.find('/');
  Shard s;
  if (slash == std::string::npos || !parse_int(std::string_view(text).substr(0, slash), s.index) ||
      !parse_int(std::string_view(text).substr(slash + 1), s.count) || s.count < 1 || s.index < 0 ||
      s.index >= s.count)
    throw InputError(fmt::format("--shard '{}': expected i/N with 0 <= i < N (e.g. 0/4 ... 3/4)", text));
  return s;
}

std::optional<Shard> shard_from_slurm() {
  const char* id = std::getenv("SLURM_ARRAY_TASK_ID");
  if (!id) return std::nullopt;
  const char* count = std::getenv("SLURM_ARRAY_TASK_COUNT");
  const char* min = std::getenv("SLURM_ARRAY_TASK_MIN");
  Shard s;
  int task = 0, first = 0;
  if (!count || !parse_int(id, task) || !parse_int(count, s.count) || (min && !parse_int(min, first)))
    throw InputError(fmt::format(
        "SLURM_ARRAY_TASK_ID={} but SLURM_ARRAY_TASK_COUNT/MIN are missing or not integers; give --shard i/N instead",
        id));
  s.index = task - first;
  if (s.count < 1 || s.index < 0 || s.index >= s.count)
    throw InputError(fmt::format("Slurm array task {} (first {}, count {}) is not a slice 0..{}: use a contiguous "
                                 "array such as --array=0-{}",
                                 task, first, s.count, s.count - 1, s.count - 1));
  return s;
}

std::filesystem::path run_folder(const std::filesystem::path& out, const StudySpec& spec, const StudyRun& run) {
  return out / "runs" / run.id(spec);
}

bool run_complete(const std::filesystem::path& out, const StudySpec& spec, const StudyRun& run) {
  std::error_code ec;
  return std::filesystem::is_regular_file(run_folder(out, spec, run) / "run.json", ec);
}

}  // namespace rigidae
