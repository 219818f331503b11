// URDF files as scenes (rigidae/io/urdf.hpp; docs/scene_format.md, "URDF"):
//
//   rigidae solve arm.urdf         the URDF alone: default run settings (0 to
//                                  1 s, output every 0.01 s, the default
//                                  formulation and solver), every joint at
//                                  position 0 and at rest, the root link fixed
//                                  unless a `world` link says otherwise;
//   rigidae solve arm.toml         a schema-2 scene whose [urdf] table names the
//                                  file (relative to the TOML file) and gives
//                                  base, initial positions and velocities by
//                                  joint name; [gravity], [time], [output],
//                                  [formulation], [solver] and `reference` as
//                                  in any schema-2 scene.
#include <fmt/format.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include <toml++/toml.h>

#include "rigidae/core/error.hpp"
#include "rigidae/io/urdf.hpp"
#include "scene_sections.hpp"
#include "toml_reader.hpp"

namespace rigidae::io {
namespace {

constexpr std::size_t kMaxUrdfBytes = 64u << 20;  // robot descriptions with inline meshes stay far below

constexpr std::array<std::string_view, 10> kRootKeysWithReference{
    "schema_version", "name", "description", "urdf", "gravity", "time", "output", "formulation", "solver",
    "reference"};
constexpr std::array<std::string_view, 4> kUrdfKeys{"file", "base", "positions", "velocities"};
constexpr std::array<std::string_view, 2> kBases{"fixed", "floating"};

std::string read_text(const std::string& path, const std::string& where) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw InputError(fmt::format("{}: error: cannot read URDF file '{}': it is a directory", where, path));
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    const int err = errno;
    throw InputError(fmt::format("{}: error: cannot open URDF file '{}': {}", where, path,
                                 err ? std::strerror(err) : "unreadable"));
  }
  std::string text(kMaxUrdfBytes + 1, '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  if (in.bad()) throw InputError(fmt::format("{}: error: cannot read URDF file '{}'", where, path));
  text.resize(static_cast<std::size_t>(in.gcount()));
  if (text.size() > kMaxUrdfBytes)
    throw InputError(fmt::format("{}: error: URDF file '{}' is larger than {} bytes", where, path, kMaxUrdfBytes));
  return text;
}

std::vector<UrdfJointState> joint_values(const TomlReader& r, const toml::node& n, const std::string& key,
                                         std::string_view unit) {
  const toml::table* t = n.as_table();
  if (!t)
    r.fail(n, fmt::format("'{}' must be a table of joint names and values in {}, e.g. {{ shoulder = 0.3, "
                          "elbow = -0.5 }}, not {}",
                          key, unit, type_name(n)));
  std::vector<UrdfJointState> out;
  for (auto&& [k, v] : *t) {
    const double x = r.number(v, fmt::format("{}.{}", key, k.str()));
    out.push_back({std::string(k.str()), x, r.location(v.source())});
  }
  return out;
}

}  // namespace

namespace detail {

// A schema-2 scene with [urdf] instead of [[bodies]] and [[joints]].
Scene read_urdf_scene(const TomlReader& r, const toml::table& root) {
  Scene scene;
  scene.source = r.file();
  for (std::string_view k : {"bodies", "joints", "springs", "loads"})
    if (const toml::node* n = root.get(k))
      r.fail(*n, fmt::format("'{}' cannot stand beside [urdf]: the URDF file gives the bodies and joints (write "
                             "a scene of [[bodies]] and [[joints]] without [urdf] to build them by hand)",
                             k));
  r.check_keys(root, "", kRootKeysWithReference, shared_sections());
  const toml::node& ver = r.required(root, "", "schema_version", "schema_version = 2");
  if (r.integer(ver, "schema_version") != 2)
    r.fail(ver, "a scene with [urdf] is a scene of bodies and joints: write schema_version = 2");
  scene.schema_version = 2;
  read_scene_name(r, root, scene);

  const toml::table& u = r.required_table(root, "", "urdf");
  r.check_keys(u, "urdf", kUrdfKeys, shared_sections());
  const toml::node& file = r.required(u, "urdf", "file", "the URDF file, relative to this scene file");
  std::filesystem::path path = r.string(file, "urdf.file");
  if (path.is_relative()) path = std::filesystem::path(r.file()).parent_path() / path;
  const std::string urdf_path = path.lexically_normal().string();
  const UrdfModel model = parse_urdf(read_text(urdf_path, r.location(file.source())), urdf_path);

  UrdfOptions options;
  if (const toml::node* n = u.get("base")) {
    options.base = r.choice(*n, "urdf.base", kBases) == 0 ? UrdfBase::Fixed : UrdfBase::Floating;
    options.base_where = r.location(n->source());
  }
  if (const toml::node* n = u.get("positions")) options.positions = joint_values(r, *n, "urdf.positions", "rad or m");
  if (const toml::node* n = u.get("velocities"))
    options.velocities = joint_values(r, *n, "urdf.velocities", "rad/s or m/s");
  MultibodySpec spec = urdf_to_multibody(model, options);

  read_gravity(r, root, scene);
  spec.gravity_W = scene.gravity_W;
  read_time(r, root, scene);
  read_output(r, root, scene);
  read_formulation(r, root, scene);
  read_solver(r, root, scene);
  check_settings_together(r, root, scene);
  if (const toml::node* n = root.get("reference")) {
    read_top_level_settings(r, root, scene);
    if (scene.reference == ReferenceKind::Exact)
      r.fail(*n, "'reference' = \"exact\" but a robot has no closed-form solution (use \"auto\" or \"tight\")");
  }
  scene.multibody = std::move(spec);
  return scene;
}

}  // namespace detail

Scene load_urdf_scene(const std::string& path) {
  const UrdfModel model = parse_urdf(read_text(path, path), path);
  Scene scene;
  scene.source = path;
  // No version of its own: read as a scene of bodies and joints (schema 2),
  // which is what its summaries say.
  scene.schema_version = 2;
  scene.name = std::filesystem::path(path).stem().string();
  if (scene.name.empty() || scene.name.front() == '.') scene.name = "urdf";
  scene.description = model.name.empty() ? std::string("URDF robot") : fmt::format("URDF robot \"{}\"", model.name);
  scene.multibody = urdf_to_multibody(model, UrdfOptions{});
  return scene;
}

}  // namespace rigidae::io
