#include "rigidae/app/command_line.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <array>
#include <stdexcept>

#include "rigidae/core/error.hpp"
#include "rigidae/core/text.hpp"
#include "rigidae/io/scene_loader.hpp"
#include "rigidae/settings/default_integrator.hpp"

namespace rigidae::cli {

namespace {

constexpr const char* kExitCodes =
    "Exit codes: 0 success, 1 a run failed, stalled, timed out or was interrupted\n"
    "(SIGINT/SIGTERM), or output could not be written (outputs so far kept),\n"
    "2 bad input (scene file, command line, an output folder not writable).\n";

const std::array<CommandInfo, 3> kCommands{{
    {settings::kSolve, "solve", "rigidae solve SCENE.toml [options]",
     "Integrates a scene and writes steps.csv (every IDA step; steps.npy with\n"
     "--step-format npy), trajectory.csv (the output grid), events.csv (chart\n"
     "switches, projections) and summary.json into a folder; --record grid|none\n"
     "writes less. Options override the scene file (docs/scene_format.md).\n"
     "SCENE may be a URDF file (.urdf: default run settings) or a scene with\n"
     "[urdf] (docs/scene_format.md, \"URDF robots\").\n",
     "", kExitCodes},
    {settings::kCompare, "compare", "rigidae compare SCENE.toml [options]",
     "Runs every applicable coordinates x equations x scheme combination against one\n"
     "reference and writes compare.csv, compare.txt, compare.md and each run's folder\n"
     "(a mechanism of particles alone, which has no rotation coordinates, runs each\n"
     "scheme and integrator once, in the scene's coordinates and form).\n"
     "Options override the scene file (docs/scene_format.md).\n",
     "compare runs every combination and integrator; select with --only/--skip (e.g. --only 'quaternion/*/ggl', "
     "--only '*@cvode-adams')",
     "Exit code 0 when every run finished, failed combinations included (they are\n"
     "rows of the table); 1 when the reference could not be computed; 2 bad input.\n"},
    {settings::kStudy, "study", "rigidae study [list|run|collect] STUDY.toml [options]",
     "Accuracy studies (study file format: docs/studies.md):\n"
     "  rigidae study STUDY.toml            run every run not yet complete, then collect\n"
     "  rigidae study list STUDY.toml       print one command per run (for GNU parallel)\n"
     "  rigidae study run STUDY.toml        run a slice: --shard i/N (0 <= i < N), or the\n"
     "                                      Slurm array task's slice, or one --run ID\n"
     "  rigidae study collect STUDY.toml    merge run folders into results.csv and\n"
     "                                      best.txt, draw the figures\n",
     "the scene settings of a study come from its scene files and its [grid]",
     "A complete run (its folder holds run.json) is never redone: rerun the same\n"
     "command to resume an interrupted study. Exit codes: 0 done, 1 interrupted,\n"
     "(collect) runs missing or output not written, 2 bad input (study or scene\n"
     "file, command line, an output folder not writable).\n"},
}};

std::vector<std::string> options_of(const CommandInfo& command) {
  std::vector<std::string> v{"--help"};
  for (const settings::Setting& s : settings::all())
    if (!s.option.empty() && (s.commands & command.bit)) v.emplace_back(s.option);
  return v;
}

}  // namespace

const CommandInfo& command_info(std::string_view name) {
  for (const CommandInfo& c : kCommands)
    if (c.name == name) return c;
  throw std::logic_error(fmt::format("no command '{}'", name));
}

std::string did_you_mean(std::string_view word, const std::vector<std::string>& options) {
  const std::vector<std::string_view> views(options.begin(), options.end());
  if (auto best = text::closest(word, views)) return fmt::format("; did you mean '{}'?", *best);
  return "";
}

const settings::Value* CommandLine::last(std::string_view option) const {
  for (auto it = options.rbegin(); it != options.rend(); ++it)
    if (it->first->option == option) return &it->second;
  return nullptr;
}

std::string CommandLine::text(std::string_view option) const {
  const settings::Value* v = last(option);
  return v ? settings::to_text(*v) : std::string();
}

CommandLine parse_arguments(const std::vector<std::string>& args, const CommandInfo& command) {
  CommandLine cl;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "-h" || a == "--help") {
      cl.help = true;
      return cl;
    }
    if (a.size() < 2 || a[0] != '-') {
      cl.positional.push_back(a);
      continue;
    }
    const std::size_t eq = a.find('=');
    const std::string name = a.substr(0, eq);
    const settings::Setting* s = settings::by_option(name);
    if (!s || !(s->commands & command.bit)) {
      if (s)
        throw InputError(fmt::format("option {} does not apply to {}{} (see rigidae {} --help)", name, command.name,
                                     command.foreign_hint.empty() ? "" : fmt::format("; {}", command.foreign_hint),
                                     command.name));
      throw InputError(fmt::format("unknown option '{}' for {}{} (see rigidae {} --help)", text::printable(name),
                                   command.name, did_you_mean(name, options_of(command)), command.name));
    }
    std::string value;
    if (s->flag_value) {
      if (eq != std::string::npos) throw InputError(fmt::format("option {} takes no value", name));
      value = std::string(*s->flag_value);
    } else if (eq != std::string::npos) {
      value = a.substr(eq + 1);
    } else {
      if (i + 1 >= args.size())
        throw InputError(fmt::format("option {} needs a value (see rigidae {} --help)", name, command.name));
      value = args[++i];
    }
    settings::Value v = settings::parse_text(*s, value);
    const std::string why = settings::problem(*s, v);
    if (!why.empty()) throw InputError(fmt::format("option {}: {}", name, why));
    cl.options.emplace_back(s, std::move(v));
  }
  return cl;
}

namespace {

// --t-end shorter than the scene's output.times: the times beyond the new
// end are dropped with a note (the run ends where the user asked); when none
// is left the command is refused at output.times' position.
void clip_output_times(Scene& scene) {
  std::vector<double>& times = scene.time.output_times;
  if (times.empty() || times.back() <= scene.time.end || !(scene.time.end > scene.time.start)) return;
  const auto beyond = std::upper_bound(times.begin(), times.end(), scene.time.end);
  const std::size_t dropped = static_cast<std::size_t>(times.end() - beyond);
  const std::string where = scene.output_times_at.empty() ? scene.source : scene.output_times_at;
  if (beyond == times.begin())
    throw InputError(fmt::format("{}: error: 'output.times' = [{}] s has no time left inside [time.start, --t-end] "
                                 "= [{}, {}] s: give a --t-end of at least {} s (the first output time), or edit "
                                 "output.times",
                                 where, fmt::join(times, ", "), scene.time.start, scene.time.end, times.front()));
  fmt::print(stderr,
             "{}: note: --t-end {} s leaves out {} of the {} output times (from {} s on); trajectory.csv has the {} "
             "up to {} s\n",
             where, scene.time.end, dropped, times.size(), *beyond, times.size() - dropped, *(beyond - 1));
  times.erase(beyond, times.end());
}

}  // namespace

Scene scene_from(const CommandLine& cl, const CommandInfo& command) {
  if (cl.positional.empty())
    throw InputError(fmt::format("{0} needs a scene file: rigidae {0} SCENE.toml (see rigidae {0} --help)", command.name));
  if (cl.positional.size() > 1)
    throw InputError(fmt::format("unexpected argument '{}': {} takes one scene file", text::printable(cl.positional[1]),
                                 command.name));
  Scene scene = io::load_scene(cl.positional.front());
  for (const auto& [s, v] : cl.options)
    if (s->set && !s->scene_key.empty()) s->set(scene, v);
  // --output-step asks for the even grid: it replaces the scene's
  // output.times (the scene file may hold only one of the two), said once.
  for (const auto& [s, v] : cl.options)
    if (s->scene_key == "time.output_step" && !scene.time.output_times.empty()) {
      fmt::print(stderr, "{}: note: --output-step {} s replaces the scene's {} output times with an even grid\n",
                 scene.output_times_at.empty() ? scene.source : scene.output_times_at, scene.time.output_step,
                 scene.time.output_times.size());
      scene.time.output_times.clear();
      scene.output_times_at.clear();
    }
  clip_output_times(scene);
  // The options may have changed what the default rule reads (scheme, springs' output step) or named the integrator.
  settings::resolve_integrator(scene);
  if (const auto p = settings::cross_problem(scene))
    throw InputError(fmt::format("{} = {}", settings::scene_setting(p->scene_key).label(), p->message));
  return scene;
}

std::string command_help(const CommandInfo& command) {
  return fmt::format("Usage: {}\n\n{}\nOptions (--name value or --name=value; ranges, units and defaults in brackets):\n"
                     "  -h, --help              this text\n{}\n{}",
                     command.usage, command.description, settings::options_help(command.bit), command.trailer);
}

}  // namespace rigidae::cli
