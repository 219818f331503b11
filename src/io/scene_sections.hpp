#pragma once
// The readers of the scene tables that schema 1 (one body) and schema 2
// (bodies and joints) share: defined once in scene_loader.cpp and used by
// multibody_loader.cpp, so both schemas accept exactly the same [gravity],
// [time], [formulation], [solver], name and orientation forms. Internal to
// the library.
#include <array>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <toml++/toml.h>

#include "rigidae/model/scene.hpp"
#include "toml_reader.hpp"

namespace rigidae::io::detail {

// The keys of the shared tables ([gravity], [time], [formulation...], [solver]).
std::span<const SectionKeys> shared_sections();

// The scene's `name` (checked: it names the output folder) and `description`.
void read_scene_name(const TomlReader& r, const toml::table& root, Scene& scene);

// [gravity], [time] (required), [formulation], [solver]: schema 1's tables.
void read_gravity(const TomlReader& r, const toml::table& root, Scene& scene);
void read_time(const TomlReader& r, const toml::table& root, Scene& scene);
// [output] (optional): record mode, step file format, output times. After read_time.
// `more_keys`: keys of [output] the caller reads itself (schema 2: bodies, joints).
void read_output(const TomlReader& r, const toml::table& root, Scene& scene,
                 std::span<const std::string_view> more_keys = {});
void read_formulation(const TomlReader& r, const toml::table& root, Scene& scene);
void read_solver(const TomlReader& r, const toml::table& root, Scene& scene);
// The settings at the top level (`reference`), and the checks between
// settings (after all of them are read).
void read_top_level_settings(const TomlReader& r, const toml::table& root, Scene& scene);
void check_settings_together(const TomlReader& r, const toml::table& root, const Scene& scene);

// Mass and inertia about the centre of mass of a body table. `table` is the
// table's name in the schema (for key checks), `prefix` names the values in
// messages ("body.mass", "bodies[2].mass").
struct MassInertia {
  double mass = 1.0;
  Mat3 inertia_com = Mat3::Identity();
  const toml::node* node = nullptr;  // where the inertia was given
  std::string name;                  // its key, as named in messages
};
MassInertia read_mass_inertia(const TomlReader& r, const toml::table& body, std::string_view table,
                              std::string_view prefix);

// Principal moments obey J_i <= J_j + J_k for any mass distribution: an
// error at `node` otherwise.
void check_possible_moments(const TomlReader& r, const toml::node& node, std::string_view name,
                            const Mat3& inertia);

// One of the orientation forms (quaternion, euler, matrix, axis_angle) of
// `tbl` as R_WB; none is an error when `required`, else unset. `schema` gives
// the tables that misplaced keys are pointed to.
std::optional<Mat3> read_orientation(const TomlReader& r, const toml::table& tbl, std::string_view table,
                                     std::string_view prefix, std::span<const SectionKeys> schema,
                                     bool required);

// A body's optional `visual` shapes (visual_loader.cpp): a table or an array
// of tables under the body's table `table` ("body", "bodies"); `prefix`
// names them in messages ("body", "bodies[2]").
inline constexpr std::array<std::string_view, 7> kVisualKeys{"shape",    "size",       "radius", "length",
                                                             "position", "quaternion", "axis"};
std::vector<VisualShape> read_visuals(const TomlReader& r, const toml::table& body, std::string_view table,
                                      std::string_view prefix, std::span<const SectionKeys> schema);

// Schema 2 (multibody_loader.cpp): everything after schema_version.
Scene read_multibody_scene(const TomlReader& r, const toml::table& root);
// Schema 2 with [urdf] (urdf_scene.cpp): the bodies and joints from a URDF file.
Scene read_urdf_scene(const TomlReader& r, const toml::table& root);

}  // namespace rigidae::io::detail
