// rigidae view | vtk | animate RUN_DIR: a run (or a compare's runs) drawn.
// The scene is loaded here (the same loader and checks as solve), its
// geometry written as JSON (app/scene_geometry.hpp) to a temporary file, and
// a tool script draws it from the run's trajectory.csv:
//   view    tools/view_run.py    one self-contained HTML page (three.js inlined)
//   vtk     tools/vtk_run.py     a ParaView .pvd collection of .vtp files
//   animate tools/animate_run.py a GIF or MP4 and a strobe picture (PNG)
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>

#include "commands.hpp"
#include "output_folder.hpp"
#include "plot_script.hpp"
#include "rigidae/app/command_line.hpp"
#include "rigidae/app/scene_geometry.hpp"
#include "rigidae/core/error.hpp"
#include "rigidae/io/checked_file.hpp"
#include "rigidae/io/scene_loader.hpp"

namespace rigidae::cli {

namespace fs = std::filesystem;

namespace {

struct DrawCommand {
  const char* name;
  const char* script;
  const char* usage;
  const char* what;
  // Options that take a value, with their help; the script checks their values.
  std::vector<std::pair<const char*, const char*>> options;
};

const std::vector<DrawCommand>& draw_commands() {
  static const std::vector<DrawCommand> all{
      {"view", "view_run.py", "rigidae view RUN_DIR [--out FILE.html] [options]",
       "Writes one self-contained HTML page that plays a run in a browser (three.js\n"
       "inlined: it opens offline from file://): the bodies (their `visual` shapes,\n"
       "else their inertia ellipsoids), joints, trails, reaction forces as arrows, a\n"
       "time slider, play/pause and speed. RUN_DIR is the folder of a solve, or of a\n"
       "compare (its runs side by side). The page honours #t=SECONDS in its address.\n",
       {{"--out", "the page [default RUN_DIR/view.html]"},
        {"--frames", "at most this many frames per run, thinned evenly from trajectory.csv [default 2000]"},
        {"--runs", "a compare's runs to include: comma-separated folder names [default all]"},
        {"--scene", "the scene file, when summary.json's path does not reach it from here"}}},
      {"vtk", "vtk_run.py", "rigidae vtk RUN_DIR [--out DIR] [options]",
       "Writes a ParaView collection DIR/run.pvd with one DIR/frame_NNNNN.vtp per\n"
       "output time: each body's shapes as triangles (body id as cell data) and the\n"
       "joint and reference points as vertices, in space coordinates.\n",
       {{"--out", "the folder [default RUN_DIR/vtk]"},
        {"--frames", "at most this many output times, thinned evenly [default: every one]"},
        {"--scene", "the scene file, when summary.json's path does not reach it from here"}}},
      {"animate", "animate_run.py", "rigidae animate RUN_DIR [--out FILE.gif|FILE.mp4] [options]",
       "Draws the run with matplotlib into an animation (GIF, or MP4 with Debian's\n"
       "ffmpeg) and a strobe picture (PNG: several poses overlaid) beside it.\n",
       {{"--out", "the animation: .gif or .mp4 [default RUN_DIR/animation.gif]"},
        {"--frames", "frames of the animation, evenly in time [default 100]"},
        {"--fps", "frames per second [default 20]"},
        {"--strobe", "poses in the strobe picture [default 8]"},
        {"--scene", "the scene file, when summary.json's path does not reach it from here"}}},
  };
  return all;
}

const DrawCommand& draw_command(std::string_view name) {
  for (const DrawCommand& c : draw_commands())
    if (name == c.name) return c;
  throw std::logic_error("no draw command");
}

std::string help_of(const DrawCommand& c) {
  std::string s = fmt::format("Usage: {}\n\n{}\nOptions:\n  -h, --help              this text\n", c.usage, c.what);
  for (const auto& [opt, help] : c.options) s += fmt::format("  {:<24}{}\n", std::string(opt) + " VALUE", help);
  return s;
}

// A temporary file that is removed when it goes out of scope.
struct TempFile {
  fs::path path;
  ~TempFile() {
    std::error_code ec;
    if (!path.empty()) fs::remove(path, ec);
  }
};

}  // namespace

std::string draw_command_help(const std::string& name) { return help_of(draw_command(name)); }

bool is_draw_command(const std::string& name) {
  for (const DrawCommand& c : draw_commands())
    if (name == c.name) return true;
  return false;
}

int draw_command_run(const std::string& name, const std::vector<std::string>& args) {
  const DrawCommand& c = draw_command(name);
  std::vector<std::string> positional;
  std::map<std::string, std::string> values;
  std::vector<std::string> names{"--help"};
  for (const auto& o : c.options) names.emplace_back(o.first);
  for (std::size_t i = 0; i < args.size(); ++i) {
    std::string a = args[i];
    if (a == "--help" || a == "-h") {
      fmt::print("{}", help_of(c));
      return 0;
    }
    if (a.rfind("--", 0) != 0) {
      positional.push_back(a);
      continue;
    }
    std::string value;
    const bool inline_value = a.find('=') != std::string::npos;
    if (inline_value) value = a.substr(a.find('=') + 1), a = a.substr(0, a.find('='));
    if (std::find(names.begin(), names.end(), a) == names.end() || a == "--help")
      throw InputError(fmt::format("rigidae {}: unknown option '{}'{} (see rigidae {} --help)", name, a,
                                   did_you_mean(a, names), name));
    if (!inline_value) {
      if (i + 1 >= args.size()) throw InputError(fmt::format("rigidae {}: {} needs a value", name, a));
      value = args[++i];
    }
    values[a] = value;
  }
  // The values the scripts take, checked here: bad input is exit code 2.
  for (const char* opt : {"--frames", "--strobe", "--fps"})
    if (values.count(opt)) {
      const std::string& v = values[opt];
      char* end = nullptr;
      const double x = std::strtod(v.c_str(), &end);
      const bool integer = std::string_view(opt) != "--fps";
      const double least = std::string_view(opt) == "--frames" ? 2 : 1;
      if (v.empty() || *end != '\0' || !(x >= least) || x > 1e7 || (integer && x != std::floor(x)))
        throw InputError(fmt::format("rigidae {}: {} '{}' must be {} of at least {:g}", name, opt, v,
                                     integer ? "an integer" : "a number", least));
    }
  if (name == "animate" && values.count("--out")) {
    const std::string ext = fs::path(values["--out"]).extension().string();
    if (ext != ".gif" && ext != ".mp4")
      throw InputError(fmt::format("rigidae animate: --out '{}': the animation is a .gif or an .mp4",
                                   values["--out"]));
  }
  if (positional.size() != 1)
    throw InputError(fmt::format("rigidae {} takes one run folder (usage: {}), {} given", name, c.usage,
                                 positional.size()));
  const fs::path dir = positional[0];
  if (!fs::is_directory(dir)) throw InputError(fmt::format("'{}' is not a folder (give a run's output folder)", dir.string()));
  const std::vector<fs::path> runs = run_folders(dir);
  if (name != "view" && runs.size() > 1)
    throw InputError(fmt::format("rigidae {} draws one run: '{}' holds {} (a compare's folder); give one of its "
                                 "run folders, e.g. '{}'",
                                 name, dir.string(), runs.size(), runs.front().string()));
  if (values.count("--runs")) {
    // A name that is no run folder is a command-line error (exit 2) named
    // here, before the script runs: the script's own exit would be a 1.
    std::vector<std::string> missing;
    std::string there;
    for (const fs::path& r : runs) there += (there.empty() ? "" : ", ") + r.filename().string();
    const std::string& list = values["--runs"];
    for (std::size_t at = 0; at <= list.size();) {
      const std::size_t comma = std::min(list.find(',', at), list.size());
      const std::string want = list.substr(at, comma - at);
      const bool found = std::any_of(runs.begin(), runs.end(), [&](const fs::path& r) { return r.filename() == want; });
      if (!found) missing.push_back("'" + want + "'");
      at = comma + 1;
    }
    if (!missing.empty())
      throw InputError(fmt::format("rigidae {}: --runs names no run folder {} in '{}' (valid: {})", name,
                                   fmt::join(missing, ", "), dir.string(), there));
  }
  const fs::path scene_file = run_scene_file(runs.front(), values.count("--scene") ? values["--scene"] : "");
  const Scene scene = io::load_scene(scene_file.string());

  {
    // Where the script writes: a folder that cannot be written is bad input
    // (exit 2, docs/robustness.md), said before the script starts, not a
    // Python traceback from it.
    fs::path out = values.count("--out") ? fs::path(values["--out"]) : fs::path();
    if (out.empty()) out = name == "vtk" ? dir / "vtk" : dir / (name == "view" ? "view.html" : "animation.gif");
    const fs::path folder = name == "vtk" ? out : out.parent_path();
    create_output_folder(folder.empty() ? fs::path(".") : folder, /*disposable=*/false);
  }
  TempFile geometry{fs::temp_directory_path() / fmt::format("rigidae-geometry-{}.json", getpid())};
  {
    std::ofstream out(geometry.path);
    out << scene_geometry_json(scene);
    if (!out) throw OutputError(fmt::format("cannot write {}", geometry.path.string()));
  }
  std::vector<std::string> script_args{"--geometry", geometry.path.string()};
  for (const fs::path& r : runs) script_args.push_back(r.string());
  for (const auto& [k, v] : values)
    if (k != "--scene") script_args.insert(script_args.end(), {k, v});
  if (name == "view" && !values.count("--out")) script_args.insert(script_args.end(), {"--out", (dir / "view.html").string()});
  if (name == "vtk" && !values.count("--out")) script_args.insert(script_args.end(), {"--out", (dir / "vtk").string()});
  if (name == "animate" && !values.count("--out"))
    script_args.insert(script_args.end(), {"--out", (dir / "animation.gif").string()});
  if (name == "view") {
    // three.js, installed beside the tools by the build (npm) and never
    // fetched when a page is written or viewed. RIGIDAE_THREE_JS overrides.
    fs::path three;
    if (const char* env = std::getenv("RIGIDAE_THREE_JS"); env && *env) three = env;
    else three = find_shared_file("three/three.module.min.js");
    if (three.empty() || !fs::exists(three))
      throw OutputError("three.js (share/rigidae/three/three.module.min.js) was not found beside rigidae: the build "
                        "installs it with npm (tools/build.sh); or set RIGIDAE_THREE_JS to three.module.min.js");
    script_args.insert(script_args.end(), {"--three", three.string()});
  }
  return run_tool_script(c.script, script_args) == 0 ? 0 : 1;
}


}  // namespace rigidae::cli
