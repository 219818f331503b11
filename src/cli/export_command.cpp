// `rigidae export --mjcf SCENE -o model.xml`: a scene (one body, a mechanism
// or a URDF) as an MJCF model for MuJoCo (src/io/mjcf_writer.cpp has the
// rules), written as the system it runs as (as_system).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "commands.hpp"
#include "rigidae/app/command_line.hpp"
#include "rigidae/core/text.hpp"
#include "rigidae/core/error.hpp"
#include "output_folder.hpp"
#include "rigidae/io/checked_file.hpp"
#include "rigidae/io/mjcf_export.hpp"
#include "rigidae/io/scene_loader.hpp"
#include "rigidae/model/one_body_system.hpp"

namespace rigidae::cli {
namespace {

constexpr const char* kHelp = R"(Usage: rigidae export --mjcf SCENE -o MODEL.xml [options]

Writes a scene (schema_version = 1 or 2, a [urdf] scene or a .urdf file) as an
MJCF model for MuJoCo: nested bodies (frame at the centre of mass, the scene's
body axes, full inertia), hinge / slide / ball / free joints (a universal
joint as two hinges, a cylindrical one as slide + hinge, a fixed one as a body
without joints, a pivot as a ball joint; a one-body scene is its body on a
ball joint at the fixed point, or at its centre of mass when free), gravity, contacts off, torsional springs and
dampers, limits as data (limited="false"), and the scene's initial state as
keyframe 0 ("initial"; qpos = 0 is rigidae's joint zero). Closed loops, springs
and loads are refused. Trees deeper than --bodies-per-file continue in
MODEL.partK.xml files beside MODEL.xml (MuJoCo's XML reader stops at 100
nested elements).

Options:
  --mjcf                 the format (the only one; required)
  -o, --output FILE      the model file to write (.xml); parts go beside it
  --timestep S           <option timestep> in s (default 1e-4)
  --integrator NAME      <option integrator>: RK4 (default), Euler or implicit
  --bodies-per-file N    bodies nested in one file at most (default 40)
  -h, --help             this text

Exit codes: 0 written; 2 bad input (nothing written); 1 a file could not be written.
)";

double positive_number(const std::string& option, const std::string& value) {
  char* end = nullptr;
  const double x = std::strtod(value.c_str(), &end);
  if (value.empty() || *end != '\0' || !(x > 0.0) || !std::isfinite(x))
    throw InputError(fmt::format("{} '{}': give a positive number of seconds, e.g. {} 1e-4", option, value, option));
  return x;
}

}  // namespace

int export_command(const std::vector<std::string>& args) {
  bool mjcf = false;
  std::string scene_path, output;
  io::MjcfOptions options;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    const auto value = [&]() -> const std::string& {
      if (i + 1 >= args.size()) throw InputError(fmt::format("option {} needs a value (see rigidae export --help)", a));
      return args[++i];
    };
    if (a == "-h" || a == "--help") {
      fmt::print("{}", kHelp);
      return 0;
    } else if (a == "--mjcf") {
      mjcf = true;
    } else if (a == "-o" || a == "--output") {
      output = value();
    } else if (a == "--timestep") {
      options.timestep = positive_number(a, value());
    } else if (a == "--integrator") {
      options.integrator = value();
      if (options.integrator != "RK4" && options.integrator != "Euler" && options.integrator != "implicit")
        throw InputError(fmt::format("--integrator '{}': give RK4, Euler or implicit (MuJoCo 2.2's integrators)",
                                     options.integrator));
    } else if (a == "--bodies-per-file") {
      const std::string v = value();
      char* end = nullptr;
      const long n = std::strtol(v.c_str(), &end, 10);
      if (v.empty() || *end != '\0' || n < 1 || n > 90)
        throw InputError(fmt::format("--bodies-per-file '{}': give a whole number from 1 to 90", v));
      options.bodies_per_file = static_cast<int>(n);
    } else if (!a.empty() && a[0] == '-') {
      throw InputError(fmt::format("unknown option '{}' for export{} (options: --mjcf, -o, --timestep, "
                                   "--integrator, --bodies-per-file, --help)",
                                   a, did_you_mean(a, {"--mjcf", "--output", "--timestep", "--integrator",
                                                       "--bodies-per-file", "--help"})));
    } else if (scene_path.empty()) {
      scene_path = a;
    } else {
      throw InputError(fmt::format("export takes one scene, got '{}' and '{}'", scene_path, a));
    }
  }
  if (!mjcf) throw InputError("export needs the format: --mjcf (MuJoCo's MJCF, the one format written)");
  if (scene_path.empty()) throw InputError("export needs a scene: rigidae export --mjcf SCENE -o MODEL.xml");
  if (output.empty()) throw InputError("export needs -o MODEL.xml (the model file to write)");
  const Scene system = as_system(io::load_scene(scene_path));
  const std::filesystem::path out(output);
  const auto files = io::mjcf_files(system, options, out.filename().string());
  const std::filesystem::path dir = out.parent_path();
  // A folder that cannot be written is bad input (exit 2), as for every command.
  create_output_folder(dir.empty() ? std::filesystem::path(".") : dir, /*disposable=*/false);
  for (const auto& [name, text] : files) write_file_atomically(dir / name, text);
  const MultibodySpec& spec = *system.multibody;
  const auto pivots = std::count_if(spec.bodies.begin(), spec.bodies.end(), [](const BodySpec& b) { return b.pivot_W.has_value(); });
  fmt::print(stderr, "rigidae export: wrote {}{} ({}, {}{})\n", output,
             files.size() > 1 ? fmt::format(" and {} part files beside it", files.size() - 1) : "",
             text::count(spec.bodies.size(), "body", "bodies"), text::count(spec.joints.size(), "joint", "joints"),
             pivots > 0 ? fmt::format(", {} on a pivot", pivots) : "");
  return 0;
}

}  // namespace rigidae::cli
