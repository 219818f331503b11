// Scene files: TOML, schema_version 1 (one body). The format is documented
// key by key in docs/scene_format.md; this file is its only implementation.
// A file with schema_version = 2 (bodies and joints) is handed to
// multibody_loader.cpp, which shares this file's readers of the common tables
// (scene_sections.hpp).
//
// Every problem is reported as an InputError whose message starts with
// "FILE:LINE:COL: error: " (the position of the offending key or value, or of
// the enclosing table when a key is missing) and says what would be valid.
#include "rigidae/io/scene_loader.hpp"
#include "rigidae/io/urdf.hpp"
#include "parse_hints.hpp"
#include "rigidae/schemes/scheme.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iostream>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <toml++/toml.h>

#include "rigidae/core/error.hpp"
#include "rigidae/exact/exact_solution.hpp"
#include "rigidae/settings/default_integrator.hpp"
#include "rigidae/settings/settings.hpp"
#include "rigidae/so3/euler_sequence.hpp"
#include "rigidae/so3/rotation.hpp"
#include "scene_sections.hpp"
#include "toml_reader.hpp"

namespace rigidae::io {
namespace {

// ---------------------------------------------------------------------------
// The schema: allowed keys of every table, and the value lists.
// ---------------------------------------------------------------------------


constexpr int kSchemaVersion = 1;
constexpr int kMultibodySchemaVersion = 2;  // bodies and joints: multibody_loader.cpp

constexpr std::array<std::string_view, 12> kRootKeys{
    "schema_version", "name", "description", "body", "support",
    "gravity", "initial", "time", "output", "formulation", "solver", "reference"};
constexpr std::array<std::string_view, 5> kBodyKeys{"mass", "inertia_principal", "inertia",
                                                    "center_of_mass", "visual"};
constexpr std::array<std::string_view, 1> kSupportKeys{"type"};
constexpr std::array<std::string_view, 1> kGravityKeys{"acceleration"};
constexpr std::array<std::string_view, 6> kInitialKeys{
    "quaternion", "euler", "matrix", "axis_angle", "angular_velocity", "angular_velocity_frame"};
constexpr std::array<std::string_view, 3> kInitialEulerKeys{"sequence", "convention", "angles"};
constexpr std::array<std::string_view, 2> kAxisAngleKeys{"axis", "angle"};
// The keys of a table that holds settings: those the table of settings
// (src/settings/table.cpp) places in it, then the table's structural keys.
// A setting added there is accepted here without another list to edit.
std::vector<std::string_view> setting_keys(std::string_view table, std::initializer_list<std::string_view> structural) {
  std::vector<std::string_view> keys;
  for (const settings::Setting& s : settings::all()) {
    const std::size_t dot = s.scene_key.rfind('.');
    if (!s.scene_key.empty() && dot != std::string_view::npos && s.scene_key.substr(0, dot) == table)
      keys.push_back(s.scene_key.substr(dot + 1));
  }
  keys.insert(keys.end(), structural.begin(), structural.end());
  return keys;
}

// Built on first use (the table of settings lives in another translation unit).
struct SettingTables {
  std::vector<std::string_view> time = setting_keys("time", {});
  std::vector<std::string_view> output = setting_keys("output", {"times"});
  std::vector<std::string_view> formulation = setting_keys("formulation", {"euler_angles", "baumgarte", "projection"});
  std::vector<std::string_view> euler_angles = setting_keys("formulation.euler_angles", {"convention"});
  std::vector<std::string_view> baumgarte = setting_keys("formulation.baumgarte", {});
  std::vector<std::string_view> projection = setting_keys("formulation.projection", {});
  std::vector<std::string_view> solver = setting_keys("solver", {});
};

constexpr std::array<std::string_view, 4> kOrientationForms{"quaternion", "euler", "matrix",
                                                            "axis_angle"};

// Every table's keys, used to point a key written in the wrong table to the right one.
struct Schema {
  SettingTables settings;
  std::array<SectionKeys, 15> sections{{
      {"", kRootKeys},
      {"body", kBodyKeys},
      {"body.visual", detail::kVisualKeys},
      {"support", kSupportKeys},
      {"gravity", kGravityKeys},
      {"initial", kInitialKeys},
      {"initial.euler", kInitialEulerKeys},
      {"initial.axis_angle", kAxisAngleKeys},
      {"time", settings.time},
      {"output", settings.output},
      {"formulation", settings.formulation},
      {"formulation.euler_angles", settings.euler_angles},
      {"formulation.baumgarte", settings.baumgarte},
      {"formulation.projection", settings.projection},
      {"solver", settings.solver},
  }};
};

const Schema& schema() {
  static const Schema s;
  return s;
}

// The tables both schemas share ([gravity], [time], [formulation...],
// [solver]), for pointing misplaced keys of a schema-2 file to the right table.
std::span<const SectionKeys> shared_sections_impl() {
  static const std::vector<SectionKeys> shared = [] {
    std::vector<SectionKeys> v;
    for (const SectionKeys& s : schema().sections)
      if (s.name == "gravity" || s.name == "time" || s.name == "output" || s.name == "solver" || s.name.rfind("formulation", 0) == 0)
        v.push_back(s);
    return v;
  }();
  return shared;
}

// Magnitudes beyond these are taken as input mistakes (wrong units, typos).
constexpr double kMaxMass = 1e9;                 // kg
constexpr double kMaxAngularVelocity = 1e6;      // rad/s
constexpr double kMaxGravity = 1e4;              // m/s^2
constexpr double kMaxCenterOfMass = 1e6;         // m
constexpr std::size_t kMaxNameBytes = 100;       // the name becomes part of the default output folder
// A one-body scene is a few hundred bytes and a 10,000-link chain about 5 MB
// (tools/make_chain.py); a bigger file is a mistake (or a device).
constexpr std::size_t kMaxSceneBytes = std::size_t{64} << 20;

constexpr double kInertiaSymmetryTol = 1e-12;    // relative
constexpr double kTriangleTol = 1e-12;           // relative to the trace
constexpr double kUnitTolError = 1e-6;           // | |q| - 1 |, ||R^T R - I||_F
constexpr double kUnitTolSilent = 1e-12;         // below: fixed without a warning


// Computed values (not the user's digits): round-off shown as such would only distract.
std::string fmt_vec6(const Vec3& v) { return fmt::format("({:.6g}, {:.6g}, {:.6g})", v[0], v[1], v[2]); }

// ---------------------------------------------------------------------------
// Sections
// ---------------------------------------------------------------------------

// Where the inertia came from, for messages about it once the support is known.
struct InertiaSource {
  const toml::node* node = nullptr;
  std::string name;
};

// The mass and the inertia about the centre of mass of one body table
// (schema 1: [body]; schema 2: each [[bodies]] entry). `prefix` names the
// values in messages ("body", "bodies[2]").
detail::MassInertia read_mass_inertia_impl(const TomlReader& r, const toml::table& body, std::string_view table,
                                   std::string_view prefix) {
  detail::MassInertia out;
  const std::string label = prefix == table ? table_label(table) : std::string(prefix);
  const std::string mass_name = join_key(prefix, "mass");
  const toml::node& mass_node = r.required(body, table, "mass", "kg, > 0");
  const double mass = r.number(mass_node, mass_name);
  if (!(mass > 0.0) || mass >= kMaxMass)
    r.fail(mass_node, fmt::format("'{}' must be > 0 and < {:g} kg, got {}", mass_name, kMaxMass, mass));
  out.mass = mass;

  const toml::node* principal = body.get("inertia_principal");
  const toml::node* full = body.get("inertia");
  const std::string principal_name = join_key(prefix, "inertia_principal");
  const std::string full_name = join_key(prefix, "inertia");
  if (principal && full) {
    const toml::node& later = before(principal->source().begin, full->source().begin) ? *full : *principal;
    r.fail(later, fmt::format("give either '{}' or '{}', not both", principal_name, full_name));
  }
  if (!principal && !full)
    r.fail(body.source(),
           fmt::format("missing the inertia in {}: give 'inertia_principal = [J1, J2, J3]' (kg m^2, "
                       "principal moments about the centre of mass along the body axes) or "
                       "'inertia = [[Ixx, Ixy, Ixz], [Ixy, Iyy, Iyz], [Ixz, Iyz, Izz]]'",
                       label));

  out.node = principal ? principal : full;
  out.name = principal ? principal_name : full_name;
  if (principal) {
    const Vec3 moments = r.vec3(*principal, out.name);
    const toml::array& a = *principal->as_array();
    for (int i = 0; i < 3; ++i)
      if (!(moments[i] > 0.0))
        r.fail(*a.get(i), fmt::format("'{}[{}]' must be > 0 (a principal moment of inertia), got {}",
                                      out.name, i, moments[i]));
    out.inertia_com = moments.asDiagonal();
  } else {
    std::array<std::array<const toml::node*, 3>, 3> el{};
    Mat3 I = r.mat3(*full, out.name, &el);
    const double scale = I.cwiseAbs().maxCoeff();
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < i; ++j) {
        const double asym = std::abs(I(i, j) - I(j, i));
        if (asym > kInertiaSymmetryTol * scale)
          r.fail(*el[i][j],
                 fmt::format("'{}' must be symmetric: element [{}][{}] = {} differs from "
                             "[{}][{}] = {} (relative difference {:.3g} > {:g})",
                             out.name, i, j, I(i, j), j, i, I(j, i), scale > 0 ? asym / scale : 0.0,
                             kInertiaSymmetryTol));
      }
    }
    I = 0.5 * (I + I.transpose()).eval();
    Eigen::SelfAdjointEigenSolver<Mat3> eig(I);
    const Vec3 moments = eig.eigenvalues();
    if (!(moments.minCoeff() > 0.0))
      r.fail(*full, fmt::format("'{}' must be positive definite; its principal moments "
                                "(eigenvalues) are {}",
                                out.name, fmt_vec6(moments)));
    out.inertia_com = I;
  }
  return out;
}

InertiaSource read_body(const TomlReader& r, const toml::table& root, Scene& scene) {
  const toml::table& body = r.required_table(root, "", "body");
  r.check_keys(body, "body", kBodyKeys, schema().sections);
  const detail::MassInertia mi = read_mass_inertia_impl(r, body, "body", "body");
  scene.body.mass = mi.mass;
  scene.body.inertia_com = mi.inertia_com;
  if (const toml::node* c = body.get("center_of_mass")) {
    const Vec3 com = r.vec3(*c, "body.center_of_mass");
    if (com.norm() > kMaxCenterOfMass)
      r.fail(*c, fmt::format("'body.center_of_mass' is {} m from the body origin; it must be at "
                             "most {:g} m (check the units: metres)",
                             com.norm(), kMaxCenterOfMass));
    scene.body.com_B = com;
  }
  scene.body.visuals = detail::read_visuals(r, body, "body", "body", schema().sections);
  return {mi.node, mi.name};
}

std::string fmt_moments(const Vec3& J) { return fmt::format("J1 = {}, J2 = {}, J3 = {}", J[0], J[1], J[2]); }

// The triangle inequality of the principal moments. J_i <= J_j + J_k holds for
// every mass distribution; a scene that breaks it describes no body and is
// refused. Equality is a lamina (all the mass in one plane through the centre
// of mass, or, for a top, through the fixed point, which the parallel-axis
// shift keeps valid): accepted. Its Euler tensor tr(J)/2 I - J is singular
// along the plane's normal, so the mass matrix of the linear-coordinate and
// quaternion Lagrange forms is singular in that direction, but not on the
// constraint manifold's tangent space (a change R' = a n^T is never tangent
// to SO(3)), so [M G^T; G 0] stays regular; the Euler forms and Euler angles
// use J itself, positive definite. Measured: all 26 combinations on the
// lamina (1, 2, 3) as accurate as on (1, 2, 2.9) (tests/unit/test_flat_body.cpp).
// A moment of zero (a rod, a point) is refused earlier: J is then singular.
// Shared with the schema-2 loader (one body of many, its moments about its
// centre of mass).
void check_possible_moments_impl(const TomlReader& r, const toml::node& node, std::string_view name,
                                 const Mat3& Ic) {
  const Vec3 Jc = Eigen::SelfAdjointEigenSolver<Mat3>(Ic).eigenvalues();
  const double trace_c = Jc.sum();
  for (int i = 0; i < 3; ++i) {
    const double others = trace_c - Jc[i];
    if (Jc[i] > others + kTriangleTol * trace_c)
      r.fail(node,
             fmt::format("'{}': the principal moments about the centre of mass ({}) violate the "
                         "triangle inequality: J{} = {} exceeds the sum of the other two ({}); no "
                         "mass distribution has these moments (valid: J1 <= J2 + J3, J2 <= J1 + J3, "
                         "J3 <= J1 + J2; equality is a lamina)",
                         name, fmt_moments(Jc), i + 1, Jc[i], others));
  }
}

void check_triangle_inequality(const TomlReader& r, const InertiaSource& src, const Scene& scene) {
  check_possible_moments_impl(r, *src.node, src.name, scene.body.inertia_com);
}

void read_support(const TomlReader& r, const toml::table& root, Scene& scene) {
  const toml::table* sup = r.optional_table(root, "", "support");
  if (!sup) return;
  r.check_keys(*sup, "support", kSupportKeys, schema().sections);
  if (const toml::node* t = sup->get("type")) {
    constexpr std::array<std::string_view, 2> opts{"fixed_point", "free"};
    scene.support = r.choice(*t, "support.type", opts) == 0 ? Support::FixedPoint : Support::Free;
  }
}

void read_gravity(const TomlReader& r, const toml::table& root, Scene& scene) {
  const toml::table* g = r.optional_table(root, "", "gravity");
  if (!g) return;
  r.check_keys(*g, "gravity", kGravityKeys, schema().sections);
  if (const toml::node* a = g->get("acceleration")) {
    const Vec3 acc = r.vec3(*a, "gravity.acceleration");
    if (acc.stableNorm() > kMaxGravity)
      r.fail(*a, fmt::format("|gravity.acceleration| = {} m/s^2 is too large; it must be at most "
                             "{:g} m/s^2",
                             acc.stableNorm(), kMaxGravity));
    scene.gravity_W = acc;
  }
}

bool read_convention(const TomlReader& r, const toml::table& tbl, std::string_view table) {
  const toml::node* c = tbl.get("convention");
  if (!c) return false;
  constexpr std::array<std::string_view, 2> opts{"intrinsic", "extrinsic"};
  return r.choice(*c, join_key(table, "convention"), opts) == 1;
}

so3::EulerSequence read_sequence(const TomlReader& r, const toml::node& n, std::string_view name,
                                 bool extrinsic, Vec3* angles) {
  const std::string letters = r.string(n, name);
  if (letters.size() != 3)
    r.fail(n, fmt::format("'{}' = \"{}\" is not an Euler sequence: give three axis letters from x, y, z with "
                          "consecutive letters distinct, e.g. \"zxz\" or \"zyx\"",
                          name, printable(letters)));
  try {
    return so3::parse_euler_sequence(letters, extrinsic, angles);
  } catch (const std::invalid_argument& e) {
    r.fail(n, fmt::format("'{}' = \"{}\": {}", name, printable(letters), printable(e.what(), 1000)));
  }
}

// One orientation form of `tbl` (schema 1: [initial]; schema 2: each
// [[bodies]] entry), as R_WB. `prefix` names the values in messages; unset
// (not given and not `required`) when the table has none.
std::optional<Mat3> read_orientation_impl(const TomlReader& r, const toml::table& init, std::string_view table,
                                          std::string_view prefix, std::span<const SectionKeys> sections,
                                          bool required) {
  const std::string label = prefix == table ? table_label(table) : std::string(prefix);
  const auto name_of = [&](std::string_view key) { return join_key(prefix, key); };
  const toml::node* form = nullptr;
  std::string_view form_name;
  for (auto name : kOrientationForms) {
    const toml::node* n = init.get(name);
    if (!n) continue;
    if (form) {
      const bool n_later = before(form->source().begin, n->source().begin);
      const toml::node& later = n_later ? *n : *form;
      r.fail(later, fmt::format("{} has several orientations ('{}' and '{}'); give exactly "
                                "one of {}",
                                label, n_later ? form_name : name, n_later ? name : form_name,
                                quoted_list(kOrientationForms)));
    }
    form = n;
    form_name = name;
  }
  if (!form && !required) return std::nullopt;
  if (!form)
    r.fail(init.source(), fmt::format("{} needs an orientation: give exactly one of {} "
                                      "(e.g. quaternion = [1.0, 0.0, 0.0, 0.0] for the identity)",
                                      label, quoted_list(kOrientationForms)));

  if (form_name == "quaternion") {
    const std::string qname = name_of("quaternion");
    const Vec4 q = r.vector<4>(*form, qname);
    const double n = q.stableNorm();  // a norm of 1e-300 is not zero (squaring would make it so)
    if (n == 0.0)
      r.fail(*form, fmt::format("'{}' has zero norm; give a unit quaternion (w, x, y, z), "
                                "scalar first, e.g. [1.0, 0.0, 0.0, 0.0] for the identity",
                                qname));
    const double dev = std::abs(n - 1.0);
    if (dev > kUnitTolError)
      r.fail(*form, fmt::format("'{}' has norm {} (| |q| - 1 | = {:.3g} > {:g}); "
                                "normalise it (a unit quaternion is expected, scalar first)",
                                qname, n, dev, kUnitTolError));
    if (dev > kUnitTolSilent)
      r.warn(*form, fmt::format("'{}' has norm {} (| |q| - 1 | = {:.3g}); "
                                "normalised",
                                qname, n, dev));
    return so3::quaternion_to_matrix(q / n);
  }

  if (form_name == "matrix") {
    const std::string mname = name_of("matrix");
    const Mat3 M = r.mat3(*form, mname);
    const double dev = (M.transpose() * M - Mat3::Identity()).norm();
    if (dev > kUnitTolError)
      r.fail(*form, fmt::format("'{}' is not orthogonal: ||R^T R - I||_F = {:.3g} > "
                                "{:g}; give the rotation matrix R_WB (rows, body to world) "
                                "to at least 7 significant digits",
                                mname, dev, kUnitTolError));
    if (M.determinant() < 0.0)
      r.fail(*form, fmt::format("'{}' has determinant -1: it is a reflection, not a rotation "
                                "(flip the sign of one row or column)",
                                mname));
    if (dev > kUnitTolSilent)
      r.warn(*form, fmt::format("'{}' deviates from a rotation by ||R^T R - I||_F = "
                                "{:.3g}; replaced by the nearest rotation",
                                mname, dev));
    return so3::nearest_rotation(M);
  }

  if (form_name == "euler") {
    if (!form->is_table())
      r.fail(*form, fmt::format("'{}' must be a table such as {{ sequence = \"zxz\", "
                                "convention = \"intrinsic\", angles = [0.1, 0.2, 0.3] }}, not {}",
                                name_of("euler"), type_name(*form)));
    const toml::table& e = *form->as_table();
    const std::string etable = join_key(table, "euler"), ename = name_of("euler");
    r.check_keys(e, etable, kInitialEulerKeys, sections);
    const toml::node& seq_node =
        r.required(e, etable, "sequence", "three axis letters such as \"zxz\" or \"zyx\"");
    const toml::node& angles_node =
        r.required(e, etable, "angles", "[a, b, c] in rad, in the order of the sequence");
    const bool extrinsic = read_convention(r, e, ename);
    Vec3 angles = r.vec3(angles_node, join_key(ename, "angles"));
    const so3::EulerSequence seq = read_sequence(r, seq_node, join_key(ename, "sequence"), extrinsic, &angles);
    return so3::euler_to_matrix(seq, angles);
  }

  // axis_angle
  if (!form->is_table())
    r.fail(*form, fmt::format("'{}' must be a table such as {{ axis = [0.0, 0.0, "
                              "1.0], angle = 0.5 }}, not {}",
                              name_of("axis_angle"), type_name(*form)));
  const toml::table& aa = *form->as_table();
  const std::string atable = join_key(table, "axis_angle"), aname = name_of("axis_angle");
  r.check_keys(aa, atable, kAxisAngleKeys, sections);
  const toml::node& axis_node =
      r.required(aa, atable, "axis", "[x, y, z], any non-zero length");
  const toml::node& angle_node = r.required(aa, atable, "angle", "rad");
  const Vec3 axis = r.vec3(axis_node, join_key(aname, "axis"));
  const double angle = r.number(angle_node, join_key(aname, "angle"));
  const double len = axis.norm();
  if (!(len > 0.0) || !std::isfinite(len))
    r.fail(axis_node, fmt::format("'{}' must be a non-zero vector (it is normalised by "
                                  "the loader)",
                                  join_key(aname, "axis")));
  return so3::axis_angle_to_matrix(axis / len, angle);
}

void read_initial(const TomlReader& r, const toml::table& root, Scene& scene) {
  const toml::table& init = r.required_table(root, "", "initial");
  r.check_keys(init, "initial", kInitialKeys, schema().sections);
  scene.R0_WB = *read_orientation_impl(r, init, "initial", "initial", schema().sections, true);

  const toml::node& w_node =
      r.required(init, "initial", "angular_velocity", "[wx, wy, wz] in rad/s");
  const Vec3 w = r.vec3(w_node, "initial.angular_velocity");
  // stableNorm: |(1e300, 0, 0)| is 1e300, not the inf that squaring gives.
  if (w.stableNorm() > kMaxAngularVelocity)
    r.fail(w_node, fmt::format("|initial.angular_velocity| = {} rad/s is too large; it must be at "
                               "most {:g} rad/s (check the units: rad/s, not rpm or deg/s)",
                               w.stableNorm(), kMaxAngularVelocity));
  bool space = false;
  if (const toml::node* f = init.get("angular_velocity_frame")) {
    constexpr std::array<std::string_view, 2> opts{"body", "space"};
    space = r.choice(*f, "initial.angular_velocity_frame", opts) == 1;
  }
  scene.omega0_B = space ? Vec3(scene.R0_WB.transpose() * w) : w;
}

// The table's settings (rigidae/settings) that live in `table` of the scene:
// read with the type the table states, checked by settings::problem, stored
// through the table's accessor. One check and one wording for the scene file,
// the command line and study files.
void read_settings(const TomlReader& r, const toml::table& t, std::string_view table, Scene& scene) {
  for (const settings::Setting& s : settings::all()) {
    if (s.scene_key.empty() || !s.set) continue;
    const std::size_t dot = s.scene_key.rfind('.');
    const std::string_view parent = dot == std::string_view::npos ? std::string_view() : s.scene_key.substr(0, dot);
    if (parent != table) continue;
    const toml::node* n = t.get(dot == std::string_view::npos ? s.scene_key : s.scene_key.substr(dot + 1));
    if (!n) continue;
    settings::Value v;
    switch (s.kind) {
      case settings::Kind::Real: v = r.number(*n, s.scene_key); break;
      case settings::Kind::Integer: v = r.integer(*n, s.scene_key); break;
      case settings::Kind::Boolean: v = r.boolean(*n, s.scene_key); break;
      case settings::Kind::Choice:
      case settings::Kind::Text: v = r.string(*n, s.scene_key); break;
    }
    const std::string why = settings::problem(s, v);
    if (!why.empty()) r.fail(*n, fmt::format("'{}' = {}", s.scene_key, why));
    s.set(scene, v);
  }
}

void read_time(const TomlReader& r, const toml::table& root, Scene& scene) {
  const toml::table& t = r.required_table(root, "", "time");
  r.check_keys(t, "time", schema().settings.time, schema().sections);
  r.required(t, "time", "end", "s, > start");
  read_settings(r, t, "time", scene);
  // Unset, the grid has 100 intervals (settings::cross_problem checks the grid).
  if (!t.get("output_step") && scene.time.end > scene.time.start)
    scene.time.output_step = (scene.time.end - scene.time.start) / 100.0;
}

// [output]: record and step_format from the table of settings; `times`, an
// array, here: each time a number, strictly increasing, inside the time span.
void read_output(const TomlReader& r, const toml::table& root, Scene& scene,
                 std::span<const std::string_view> more_keys = {}) {
  const toml::table* t = r.optional_table(root, "", "output");
  if (!t) return;
  std::vector<std::string_view> keys = schema().settings.output;
  keys.insert(keys.end(), more_keys.begin(), more_keys.end());
  r.check_keys(*t, "output", keys, schema().sections);
  read_settings(r, *t, "output", scene);
  const toml::node* n = t->get("times");
  if (!n) return;
  const toml::array* a = n->as_array();
  const TimeGrid& g = scene.time;
  const std::string span = fmt::format("[time.start, time.end] = [{}, {}] s", g.start, g.end);
  if (!a)
    r.fail(*n, fmt::format("'output.times' must be an array of times in s, strictly increasing inside {} (e.g. "
                           "[1.0, 2.5, 7.0]), not {}",
                           span, type_name(*n)));
  if (a->empty())
    r.fail(*n, fmt::format("'output.times' is empty: give at least one time in s inside {}, or leave the key out "
                           "for the even grid of time.output_step",
                           span));
  if (const toml::table* time = root.get_as<toml::table>("time"); time && time->contains("output_step"))
    r.fail(*n, "'output.times' and 'time.output_step' both choose the output times: keep one (output.times for "
               "given times, time.output_step for an even grid)");
  std::vector<double> times;
  for (std::size_t i = 0; i < a->size(); ++i) {
    const toml::node& e = *a->get(i);
    const std::string name = fmt::format("output.times[{}]", i);
    const double x = r.number(e, name);
    if (x < g.start || x > g.end)
      r.fail(e, fmt::format("'{}' = {} s is outside the time span {}; every output time must lie inside it", name,
                            x, span));
    if (!times.empty() && !(x > times.back()))
      r.fail(e, fmt::format("'{}' = {} s must be greater than 'output.times[{}]' = {} s: the times must be strictly "
                            "increasing",
                            name, x, i - 1, times.back()));
    times.push_back(x);
  }
  scene.time.output_times = std::move(times);
  scene.output_times_at = r.location(n->source());
}

void read_euler_charts(const TomlReader& r, const toml::table& f, EulerChartSpec& euler, Scene& scene) {
  const toml::table* ea = r.optional_table(f, "formulation", "euler_angles");
  if (!ea) return;
  r.check_keys(*ea, "formulation.euler_angles", schema().settings.euler_angles, schema().sections);
  const bool extrinsic = read_convention(r, *ea, "formulation.euler_angles");
  read_settings(r, *ea, "formulation.euler_angles", scene);
  // The table reads the letters as intrinsic; extrinsic letters name the reversed sequence.
  if (extrinsic && euler.sequence) euler.sequence = so3::parse_euler_sequence(euler.sequence->name(), true);
}

void read_formulation(const TomlReader& r, const toml::table& root, Scene& scene) {
  const toml::table* f = r.optional_table(root, "", "formulation");
  if (!f) return;
  r.check_keys(*f, "formulation", schema().settings.formulation, schema().sections);
  read_settings(r, *f, "formulation", scene);
  read_euler_charts(r, *f, scene.formulation.euler, scene);
  for (const char* sub : {"baumgarte", "projection"}) {
    const std::string table = fmt::format("formulation.{}", sub);
    const toml::table* t = r.optional_table(*f, "formulation", sub);
    if (!t) continue;
    r.check_keys(*t, table, sub[0] == 'b' ? schema().settings.baumgarte : schema().settings.projection,
                 schema().sections);
    read_settings(r, *t, table, scene);
  }
}

void read_solver(const TomlReader& r, const toml::table& root, Scene& scene) {
  const toml::table* s = r.optional_table(root, "", "solver");
  if (!s) return;
  r.check_keys(*s, "solver", schema().settings.solver, schema().sections);
  read_settings(r, *s, "solver", scene);
  // An ODE integrator without a scheme in the file runs the ODE form with projection.
  const toml::table* f = root.get_as<toml::table>("formulation");
  const std::string scheme = settings::default_scheme(scene.solver.integrator);
  if (s->contains("integrator") && !scheme.empty() && !(f && f->contains("scheme"))) scene.formulation.scheme = scheme;
}

// Checks between settings, reported at the key they name (or its table when
// the file leaves the key out).
void check_settings_together(const TomlReader& r, const toml::table& root, const Scene& scene) {
  const std::optional<settings::CrossProblem> p = settings::cross_problem(scene);
  if (!p) return;
  toml::node_view<const toml::node> at = root.at_path(p->scene_key);
  std::string_view key = p->scene_key;
  while (!at && key.find('.') != std::string_view::npos) {
    key = key.substr(0, key.rfind('.'));
    at = root.at_path(key);
  }
  r.fail(at ? at.node()->source() : root.source(), fmt::format("'{}' = {}", p->scene_key, p->message));
}

// After everything else: whether an exact solution exists depends on the
// whole scene.
void read_reference_kind(const TomlReader& r, const toml::table& root, Scene& scene) {
  const toml::node* n = root.get("reference");
  if (!n) return;
  read_settings(r, root, "", scene);
  if (scene.reference != ReferenceKind::Exact) return;
  std::string why;
  if (exact::find_exact_solution(scene, &why)) return;
  r.fail(*n, fmt::format("'reference' = \"exact\" but this scene has no closed-form solution: {} (use \"auto\" "
                         "or \"tight\" for a tight run of quaternion/euler/ggl)",
                         why));
}

void read_scene_name_impl(const TomlReader& r, const toml::table& root, Scene& scene) {
  scene.name = std::filesystem::path(r.file()).stem().string();
  if (const toml::node* n = root.get("name")) {
    scene.name = r.string(*n, "name");
    if (scene.name.empty()) r.fail(*n, "'name' must not be empty (leave it out to use the file name)");
    // The name names the default output folder out/NAME-...: no paths, no hidden folders.
    const bool control = std::any_of(scene.name.begin(), scene.name.end(),
                                     [](char c) { return static_cast<unsigned char>(c) < 0x20 || c == 0x7f; });
    if (scene.name.size() > kMaxNameBytes || control || scene.name.front() == '.' ||
        scene.name.find_first_of("/\\") != std::string::npos)
      r.fail(*n, fmt::format("'name' = \"{}\" cannot name an output folder: give at most {} bytes of printable "
                             "characters, without '/' or '\\' and not starting with '.' (e.g. \"heavy_top\")",
                             printable(scene.name), kMaxNameBytes));
  }
  if (const toml::node* n = root.get("description")) scene.description = r.string(*n, "description");
}

Scene read_scene(const TomlReader& r, const toml::table& root) {
  Scene scene;
  scene.source = r.file();
  if (root.empty())
    r.fail(root.source(), "the scene is empty (nothing but whitespace or comments); a scene needs "
                          "schema_version = 1 and the tables [body], [initial] and [time] (see "
                          "docs/scene_format.md and problems/*.toml)");

  // The version first: a file of another version should fail on that, not on
  // the keys it renamed.
  // (Unless it is missing: then a misspelt key is the likelier cause -- but
  // not in a file of bodies and joints, whose keys are schema 2's.)
  // A robot from a URDF file (urdf_scene.cpp): schema 2 without [[bodies]].
  if (root.get("urdf")) return detail::read_urdf_scene(r, root);
  const bool has_bodies = root.get("bodies") || root.get("joints");
  if (!root.get("schema_version") && !has_bodies) r.check_keys(root, "", kRootKeys, schema().sections);
  const toml::node& ver =
      r.required(root, "", "schema_version",
                 has_bodies ? "schema_version = 2 for a scene of [[bodies]] and [[joints]]" : "schema_version = 1");
  const long long version = r.integer(ver, "schema_version");
  if (version == kMultibodySchemaVersion) return detail::read_multibody_scene(r, root);
  if (version != kSchemaVersion)
    r.fail(ver, fmt::format("unsupported schema_version {}; this version of rigidae reads "
                            "schema_version = {} (one body) or {} (bodies and joints)",
                            version, kSchemaVersion, kMultibodySchemaVersion));
  if (has_bodies)
    r.fail(ver, fmt::format("schema_version = 1 is a scene of one body ([body], [initial]), but this file has "
                            "schema 2's [[{}]]: write schema_version = 2 for bodies and joints (see "
                            "docs/scene_format.md)",
                            root.get("bodies") ? "bodies" : "joints"));
  r.check_keys(root, "", kRootKeys, schema().sections);
  scene.schema_version = kSchemaVersion;
  read_scene_name_impl(r, root, scene);

  const InertiaSource inertia = read_body(r, root, scene);
  read_support(r, root, scene);
  check_triangle_inequality(r, inertia, scene);
  read_gravity(r, root, scene);
  read_initial(r, root, scene);
  read_time(r, root, scene);
  read_output(r, root, scene);
  read_formulation(r, root, scene);
  read_solver(r, root, scene);
  check_settings_together(r, root, scene);
  read_reference_kind(r, root, scene);
  return scene;
}


}  // namespace

// The shared readers (scene_sections.hpp), for the schema-2 loader.
namespace detail {
std::span<const SectionKeys> shared_sections() { return shared_sections_impl(); }
void read_scene_name(const TomlReader& r, const toml::table& root, Scene& scene) {
  read_scene_name_impl(r, root, scene);
}
void read_gravity(const TomlReader& r, const toml::table& root, Scene& scene) { io::read_gravity(r, root, scene); }
void read_time(const TomlReader& r, const toml::table& root, Scene& scene) { io::read_time(r, root, scene); }
void read_output(const TomlReader& r, const toml::table& root, Scene& scene,
                 std::span<const std::string_view> more_keys) {
  io::read_output(r, root, scene, more_keys);
}
void read_formulation(const TomlReader& r, const toml::table& root, Scene& scene) {
  io::read_formulation(r, root, scene);
}
void read_solver(const TomlReader& r, const toml::table& root, Scene& scene) { io::read_solver(r, root, scene); }
void read_top_level_settings(const TomlReader& r, const toml::table& root, Scene& scene) {
  read_settings(r, root, "", scene);
}
void check_settings_together(const TomlReader& r, const toml::table& root, const Scene& scene) {
  io::check_settings_together(r, root, scene);
}
MassInertia read_mass_inertia(const TomlReader& r, const toml::table& body, std::string_view table,
                              std::string_view prefix) {
  return read_mass_inertia_impl(r, body, table, prefix);
}
void check_possible_moments(const TomlReader& r, const toml::node& node, std::string_view name,
                            const Mat3& inertia) {
  check_possible_moments_impl(r, node, name, inertia);
}
std::optional<Mat3> read_orientation(const TomlReader& r, const toml::table& tbl, std::string_view table,
                                     std::string_view prefix, std::span<const SectionKeys> schema,
                                     bool required) {
  return read_orientation_impl(r, tbl, table, prefix, schema, required);
}
}  // namespace detail

Scene parse_scene(const std::string& text, const std::string& source_name) {
  const TomlReader reader(source_name);
  toml::table root;
  try {
    root = toml::parse(std::string_view(text), std::string_view(source_name));
  } catch (const toml::parse_error& e) {
    reader.fail(e.source(), explain_parse_error(text, e));
  }
  Scene scene = read_scene(reader, root);
  // The integrator, unless the file names one: the measured rule (settings/default_integrator.hpp).
  settings::resolve_integrator(scene);
  return scene;
}

Scene load_scene(const std::string& path) {
  // A URDF file on its own: default run settings (urdf_scene.cpp).
  if (const std::string ext = std::filesystem::path(path).extension().string();
      ext.size() == 5 && text::lower(ext[1]) == 'u' && text::lower(ext[2]) == 'r' && text::lower(ext[3]) == 'd' &&
      text::lower(ext[4]) == 'f')
  {
    Scene scene = load_urdf_scene(path);
    settings::resolve_integrator(scene);
    return scene;
  }
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw InputError(fmt::format("{}: error: cannot read scene file '{}': it is a directory", path, path));
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    const int err = errno;
    throw InputError(fmt::format("{}: error: cannot open scene file '{}': {}", path, path,
                                 err ? std::strerror(err) : "unreadable"));
  }
  // Read in chunks, at most one byte more than a scene may have: a huge file
  // or a device such as /dev/zero is refused without reading it all, and a
  // short scene costs no more than its size (a buffer of the whole limit,
  // zeroed, cost ~20 ms per run).
  std::string text;
  char chunk[1 << 16];
  while (text.size() <= kMaxSceneBytes && in) {
    in.read(chunk, static_cast<std::streamsize>(sizeof chunk));
    text.append(chunk, static_cast<std::size_t>(in.gcount()));
  }
  if (in.bad()) throw InputError(fmt::format("{}: error: cannot read scene file '{}'", path, path));
  if (text.size() > kMaxSceneBytes)
    throw InputError(fmt::format("{}: error: scene file '{}' is larger than {} bytes; a scene is a short TOML "
                                 "file (see problems/*.toml)",
                                 path, path, kMaxSceneBytes));
  return parse_scene(text, path);
}

}  // namespace rigidae::io
