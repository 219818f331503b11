// Scene files of schema_version 2: rigid bodies joined by joints, with
// springs and loads (docs/scene_format.md, "Schema 2"). Fills
// Scene::multibody (model/multibody_spec.hpp); the tables both schemas share
// ([gravity], [time], [formulation], [solver], the name and the orientation
// forms) are read by scene_loader.cpp's readers (scene_sections.hpp).
//
// What the user writes and what the spec holds differ in one way: joint and
// spring points and axes are written in SPACE at the initial pose (read off a
// drawing), unless `frame = "body"`; the spec holds them in each body's frame,
// from its centre of mass:
//     s_B = R0_WB^T (p_W - x0_W),   d_B = R0_WB^T d_W.
// The ground is the space frame itself (R = I, x = 0).
//
// Checks beyond single values, all at the initial pose: a joint's bodies
// exist (with a suggestion), axes are non-zero and normals perpendicular, the
// joints between one pair of bodies do not repeat or fight each other (their
// conditions on the relative motion are independent), and no body is welded
// to the ground. Whether the joints hold at the initial pose, and closed
// loops, are the assembler's to check (it has the constraint functions).
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <numeric>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <toml++/toml.h>

#include "rigidae/core/error.hpp"
#include "rigidae/model/scene.hpp"
#include "rigidae/settings/settings.hpp"
#include "scene_sections.hpp"
#include "time_function_reader.hpp"
#include "toml_reader.hpp"

namespace rigidae::io::detail {
namespace {

// ---------------------------------------------------------------------------
// The schema
// ---------------------------------------------------------------------------

constexpr std::array<std::string_view, 18> kRootKeys{
    "schema_version", "name",    "description", "start_tolerance", "reference",   "bodies",  "joints",
    "springs",        "loads",   "gravity",     "time",            "output",      "formulation", "solver",
    "expected_dof",   "mechanism", "drivers", "markers"};
constexpr std::array<std::string_view, 4> kMarkerKeys{"name", "body", "point", "frame"};
constexpr std::array<std::string_view, 4> kMechanismKeys{"expected_dof", "assemble", "hold", "singular_poses"};
constexpr std::array<std::string_view, 2> kSingularPoseModes{"bridge", "integrate"};
constexpr std::array<std::string_view, 17> kBodyKeys{
    "name",     "mass",  "inertia_principal", "inertia",    "inertia_axes", "position",         "quaternion",
    "euler",    "matrix", "axis_angle",       "velocity",   "angular_velocity", "angular_velocity_frame",
    "coordinates", "visual", "kind", "pivot"};
// kind = "rigid" (the default) or "particle": a point mass has mass,
// position and velocity only (multibody/point_mass.hpp).
constexpr std::array<std::string_view, 2> kBodyKinds{"rigid", "particle"};
constexpr std::array<std::string_view, 6> kParticleKeys{"name", "kind", "mass", "position", "velocity", "visual"};
constexpr std::array<std::string_view, 3> kEulerKeys{"sequence", "convention", "angles"};
constexpr std::array<std::string_view, 2> kAxisAngleKeys{"axis", "angle"};
constexpr std::array<std::string_view, 13> kJointGeometryKeys{
    "name",    "type",    "bodies",   "frame",    "point",   "axis",
    "axis_a",  "axis_b",  "point_a",  "point_b",  "normal_a", "normal_b", "length"};
// [[joints]]'s keys: the geometry, and the keys of the force elements the
// registered joint types carry (model/joint_type.hpp), each once.
const std::vector<std::string_view>& joint_keys() {
  static const std::vector<std::string_view> keys = [] {
    std::vector<std::string_view> k(kJointGeometryKeys.begin(), kJointGeometryKeys.end());
    for (const JointType* t : joint_types())
      for (std::string_view f : t->force_keys)
        if (std::find(k.begin(), k.end(), f) == k.end()) k.push_back(f);
    return k;
  }();
  return keys;
}
constexpr std::array<std::string_view, 8> kSpringKeys{"name",    "bodies",    "frame",   "point_a",
                                                      "point_b", "stiffness", "damping", "rest_length"};
constexpr std::array<std::string_view, 5> kLoadKeys{"body", "force", "torque", "frame", "profile"};
constexpr std::array<std::string_view, 3> kDriverKeys{"joint", "coordinate", "motion"};
// [output]'s keys of schema 2 only: which bodies and joints have columns.
constexpr std::array<std::string_view, 2> kOutputPartKeys{"bodies", "joints"};

// Schema 2's own tables; the shared ones are added from scene_loader.cpp.
std::array<SectionKeys, 11> own_sections() {
  return {{
    {"", kRootKeys},
    {"mechanism", kMechanismKeys},
    {"bodies", kBodyKeys},
    {"bodies.visual", kVisualKeys},
    {"bodies.euler", kEulerKeys},
    {"bodies.axis_angle", kAxisAngleKeys},
    {"joints", joint_keys()},
    {"springs", kSpringKeys},
    {"loads", kLoadKeys},
    {"drivers", kDriverKeys},
    {"markers", kMarkerKeys},
  }};
}

const std::vector<SectionKeys>& sections() {
  static const std::vector<SectionKeys> all = [] {
    const std::array<SectionKeys, 11> own = own_sections();
    std::vector<SectionKeys> v(own.begin(), own.end());
    const auto shared = shared_sections();
    v.insert(v.end(), shared.begin(), shared.end());
    return v;
  }();
  return all;
}

constexpr std::array<std::string_view, 2> kFrames{"space", "body"};
constexpr std::string_view kGroundName = "ground";

// Magnitudes beyond these are taken as input mistakes (wrong units, typos).
constexpr double kMaxLength = 1e6;           // m: positions and points
constexpr double kMaxSpeed = 1e6;            // m/s
constexpr double kMaxAngularSpeed = 1e6;     // rad/s
constexpr double kMaxForce = 1e12;           // N, N m
constexpr double kMaxCoefficient = 1e12;     // N/m, N s/m, N m/rad, N m s/rad
constexpr double kMaxRestAngle = 1e3;        // rad
constexpr std::size_t kMaxPartNameBytes = 64;

// Directions that should be at right angles: off by more than this (the
// cosine of their angle) is an error; between kSilent and this, fixed with a
// warning; below, fixed silently. The same bounds as unit quaternions.
constexpr double kPerpendicularError = 1e-6;
constexpr double kPerpendicularSilent = 1e-12;
// Attachment points closer than this leave a spring without a direction.
constexpr double kMinSpringLength = 1e-9;  // m
// Relative singular-value threshold when counting independent joint conditions.
constexpr double kRankTol = 1e-9;

// Keys of the force elements joint types carry, and the types that carry one.
bool is_force_key(std::string_view k) {
  for (const JointType* t : joint_types())
    if (std::find(t->force_keys.begin(), t->force_keys.end(), k) != t->force_keys.end()) return true;
  return false;
}
std::vector<std::string_view> types_carrying(std::string_view k) {
  std::vector<std::string_view> out;
  for (const JointType* t : joint_types())
    if (std::find(t->force_keys.begin(), t->force_keys.end(), k) != t->force_keys.end()) out.push_back(t->name);
  return out;
}

std::string fmt_vec6(const Vec3& v) { return fmt::format("({:.6g}, {:.6g}, {:.6g})", v[0], v[1], v[2]); }
std::string item(std::string_view array, std::size_t i) { return fmt::format("{}[{}]", array, i); }

std::string lowercase(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = text::lower(c);
  return out;
}

// ---------------------------------------------------------------------------
// Values
// ---------------------------------------------------------------------------

Vec3 bounded_vec3(const TomlReader& r, const toml::node& n, const std::string& name, double max,
                  std::string_view unit) {
  const Vec3 v = r.vec3(n, name);
  // stableNorm: |(0, 1e300, 0)| is 1e300 as given, not the overflow of its square
  if (v.stableNorm() > max)
    r.fail(n, fmt::format("|{}| = {:g} {} is too large; it must be at most {:g} {} (check the units)", name,
                          v.stableNorm(), unit, max, unit));
  return v;
}

double bounded_number(const TomlReader& r, const toml::node& n, const std::string& name, double lo, double hi,
                      std::string_view unit) {
  const double v = r.number(n, name);
  if (!(v >= lo && v <= hi))
    r.fail(n, fmt::format("'{}' = {} must lie in [{:g}, {:g}] {}", name, v, lo, hi, unit));
  return v;
}

// A direction: any non-zero length, returned as a unit vector.
Vec3 direction(const TomlReader& r, const toml::node& n, const std::string& name) {
  const Vec3 v = r.vec3(n, name);
  const double len = v.norm();
  if (!(len > 0.0) || !std::isfinite(len))
    r.fail(n, fmt::format("'{}' must be a non-zero vector (a direction: its length does not matter, the "
                          "loader normalises it), got {}",
                          name, fmt_vec6(v)));
  return v / len;
}

// `v` (unit) made exactly perpendicular to `axis` (unit).
Vec3 perpendicular(const TomlReader& r, const toml::node& n, const std::string& name, const Vec3& v,
                   const Vec3& axis, const std::string& axis_name, std::string_view hint) {
  const double c = v.dot(axis);
  if (std::abs(c) > kPerpendicularError)
    r.fail(n, fmt::format("'{}' must be perpendicular to {}: the angle between them is {:.6g} degrees "
                          "(cosine {:.3g}, at most {:g} is accepted){}",
                          name, axis_name, std::acos(std::clamp(c, -1.0, 1.0)) * 180.0 / std::numbers::pi, c,
                          kPerpendicularError, hint));
  if (std::abs(c) > kPerpendicularSilent)
    r.warn(n, fmt::format("'{}' is {:.3g} rad from perpendicular to {}; made perpendicular", name,
                          std::abs(std::asin(std::clamp(c, -1.0, 1.0))), axis_name));
  return (v - c * axis).normalized();
}

// A unit vector perpendicular to `axis`: the coordinate axis e_x, e_y or e_z
// least parallel to it (the first on a tie), with its component along `axis`
// removed. The choice never changes the motion: both bodies get the same
// normal at the initial pose.
Vec3 default_normal(const Vec3& axis) {
  int k = 0;
  for (int i = 1; i < 3; ++i)
    if (std::abs(axis[i]) < std::abs(axis[k])) k = i;
  const Vec3 e = Vec3::Unit(k);
  return (e - e.dot(axis) * axis).normalized();
}

// Names of bodies, joints and springs become output columns (BODY.qw,
// JOINT.force_x) and may become folder names.
void check_part_name(const TomlReader& r, const toml::node& n, const std::string& key, const std::string& name) {
  const bool safe = !name.empty() && name.size() <= kMaxPartNameBytes && name.front() != '-' &&
                    std::all_of(name.begin(), name.end(), [](char c) {
                      return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                             c == '_' || c == '-';
                    });
  if (!safe)
    r.fail(n, fmt::format("'{}' = \"{}\" cannot name output columns and folders: give 1 to {} letters, digits, "
                          "'_' or '-' (not starting with '-'), e.g. \"upper_arm\"",
                          key, printable(name), kMaxPartNameBytes));
  if (lowercase(name) == kGroundName)
    r.fail(n, fmt::format("'{}' = \"{}\" is reserved: \"ground\" names the fixed space frame in joints, springs "
                          "and loads; give the part another name",
                          key, printable(name)));
}

// ---------------------------------------------------------------------------
// The reader
// ---------------------------------------------------------------------------

struct Part {
  std::string kind;  // "body", "joint", "spring"
  std::string name;
  int line = 0;
};

// The initial pose of a body, or of the ground.
struct Pose {
  Mat3 R = Mat3::Identity();
  Vec3 x = Vec3::Zero();
};

class MultibodyReader {
 public:
  MultibodyReader(const TomlReader& r, const toml::table& root) : r_(r), root_(root) {}

  Scene read() {
    Scene scene;
    scene.source = r_.file();
    // A one-body file with the wrong version: say so, not "unknown key 'body'".
    for (std::string_view old : {"body", "initial", "support"})
      if (root_.get(old) && !root_.get("bodies"))
        r_.fail(*root_.get("schema_version"),
                fmt::format("schema_version = 2 is a scene of [[bodies]] and [[joints]], but this file has schema "
                            "1's [{}]: write schema_version = 1 for one body (see docs/scene_format.md)",
                            old));
    r_.check_keys(root_, "", kRootKeys, sections());
    scene.schema_version = 2;
    read_scene_name(r_, root_, scene);
    MultibodySpec spec;
    if (const toml::node* n = root_.get("start_tolerance"))
      spec.start_tolerance = open_unit_interval(*n, "start_tolerance",
                                                "(m and rad: the largest miss of a joint at the start that is "
                                                "projected with a warning, e.g. 1e-6)");

    read_bodies(spec);
    read_expected_dof(spec);
    read_gravity(r_, root_, scene);
    spec.gravity_W = scene.gravity_W;
    read_joints(spec);
    check_joint_pairs(spec);
    check_welds(spec);
    read_springs(spec);
    read_loads(spec);
    read_drivers(spec);
    read_markers(spec);

    read_time(r_, root_, scene);
    read_output(r_, root_, scene, kOutputPartKeys);
    read_recorded_parts(spec);
    read_formulation(r_, root_, scene);
    read_solver(r_, root_, scene);
    check_settings_together(r_, root_, scene);
    read_reference(scene);
    scene.multibody = std::move(spec);
    return scene;
  }

 private:
  const TomlReader& r_;
  const toml::table& root_;
  std::map<std::string, Part> names_;  // lower-case name -> the part that has it
  std::vector<Pose> poses_;            // of the bodies, in order
  std::vector<std::string> body_names_;
  std::map<std::string, int, std::less<>> body_index_;
  std::vector<const toml::table*> joint_tables_;
  std::vector<bool> particle_;  // per body: a point mass

  // [output] bodies / joints: "all", "none" or an array of names of the
  // scene's bodies / joints (model/recorded_parts.hpp: unset is the default).
  void read_recorded_parts(MultibodySpec& spec) const {
    const toml::table* out = root_.get_as<toml::table>("output");
    if (!out) return;
    std::vector<std::string_view> bodies, joints;
    for (const BodySpec& b : spec.bodies) bodies.push_back(b.name);
    for (const JointSpec& j : spec.joints) joints.push_back(j.name);
    if (const toml::node* n = out->get("bodies")) spec.output_bodies = part_list(*n, "output.bodies", "body", bodies);
    if (const toml::node* n = out->get("joints")) spec.output_joints = part_list(*n, "output.joints", "joint", joints);
  }

  std::vector<int> part_list(const toml::node& n, const std::string& key, std::string_view kind,
                             const std::vector<std::string_view>& names) const {
    std::vector<int> chosen;
    const auto all = [&] {
      for (std::size_t i = 0; i < names.size(); ++i) chosen.push_back(static_cast<int>(i));
    };
    if (n.is_string()) {
      const std::string s = r_.string(n, key);
      if (s == "all") all();
      else if (s != "none")
        r_.fail(n, fmt::format("'{}' = \"{}\": give \"all\", \"none\" or an array of {} names, e.g. [\"{}\"]", key,
                               printable(s), kind, names.empty() ? std::string_view("A") : names.front()));
      return chosen;
    }
    const toml::array* a = n.as_array();
    if (!a)
      r_.fail(n, fmt::format("'{}' must be \"all\", \"none\" or an array of {} names, not {}", key, kind,
                             type_name(n)));
    for (const toml::node& e : *a) {
      const std::string name = r_.string(e, key + "[]");
      const auto it = std::find(names.begin(), names.end(), name);
      if (it != names.end()) {
        chosen.push_back(static_cast<int>(it - names.begin()));
        continue;
      }
      std::string msg = fmt::format("'{}' names \"{}\", which is not a {} of this scene", key, printable(name), kind);
      if (auto best = closest(name, names)) msg += fmt::format("; did you mean \"{}\"?", *best);
      constexpr std::size_t kShown = 8;
      const std::vector<std::string_view> shown(names.begin(), names.begin() + std::min(kShown, names.size()));
      msg += fmt::format(" ({}s: {}{})", kind, quoted_list(shown),
                         names.size() > kShown ? fmt::format(" and {} more", names.size() - kShown) : "");
      r_.fail(e, msg);
    }
    // Recorded in the scene's order, each once.
    std::sort(chosen.begin(), chosen.end());
    chosen.erase(std::unique(chosen.begin(), chosen.end()), chosen.end());
    return chosen;
  }

  double open_unit_interval(const toml::node& n, const std::string& name, std::string_view what) const {
    const double v = r_.number(n, name);
    if (!(v > 0.0 && v < 1.0)) r_.fail(n, fmt::format("'{}' = {} must lie in (0, 1) {}", name, v, what));
    return v;
  }

  SourcePosition where(const toml::node& n) const {
    const auto b = n.source().begin;
    return {r_.file(), static_cast<int>(b.line), static_cast<int>(b.column)};
  }

  // The entries of an array of tables `key` ([[key]]); none if absent.
  std::vector<const toml::table*> tables(std::string_view key, bool required, std::string_view what) const {
    const toml::node* n = root_.get(key);
    std::vector<const toml::table*> out;
    if (!n) {
      if (required)
        r_.fail(root_.source(), fmt::format("missing [[{}]]: a schema-2 scene needs at least one {} (see "
                                            "docs/scene_format.md, \"Schema 2\")",
                                            key, what));
      return out;
    }
    const toml::array* a = n->as_array();
    if (a && a->empty()) {
      if (required) r_.fail(*n, fmt::format("'{}' is empty; a schema-2 scene needs at least one {}", key, what));
      return out;
    }
    if (!a || !a->is_array_of_tables())
      r_.fail(*n, fmt::format("'{}' must be an array of tables, one [[{}]] header per {}, not {}", key, key,
                              what, a ? std::string("an array of other values") : type_name(*n)));
    for (const toml::node& e : *a) out.push_back(e.as_table());
    return out;
  }

  // Registers a name, refusing one already used by any part (letter case
  // ignored: output folders may live on case-insensitive file systems).
  void claim_name(const toml::node* n, const toml::table& tbl, const std::string& kind, const std::string& name) {
    const auto [it, fresh] = names_.try_emplace(lowercase(name), Part{kind, name, static_cast<int>(tbl.source().begin.line)});
    if (fresh) return;
    const Part& p = it->second;
    const std::string msg = fmt::format(
        "duplicate name \"{}\": the {} \"{}\" (line {}) has it already; bodies, joints and springs need "
        "distinct names, ignoring letter case (they name output columns)",
        printable(name), p.kind, printable(p.name), p.line);
    if (n) r_.fail(*n, msg);
    r_.fail(tbl.source(), msg);
  }

  // A body by name, or the ground (kGround).
  int body_index(const toml::node& n, const std::string& key, bool allow_ground) const {
    const std::string name = r_.string(n, key);
    if (name == kGroundName) {
      if (!allow_ground)
        r_.fail(n, fmt::format("'{}' = \"ground\": a {} is on a body (the ground does not move)", key,
                               key.rfind("markers", 0) == 0 ? "marker" : "load"));
      return kGround;
    }
    if (const auto it = body_index_.find(name); it != body_index_.end()) return it->second;
    std::vector<std::string_view> options(body_names_.begin(), body_names_.end());
    if (allow_ground) options.push_back(kGroundName);
    std::string msg = fmt::format("'{}' = \"{}\" is not a body of this scene", key, printable(name));
    if (auto best = closest(name, options)) msg += fmt::format("; did you mean \"{}\"?", *best);
    constexpr std::size_t kShown = 8;
    std::vector<std::string_view> shown(options.begin(), options.begin() + std::min(kShown, options.size()));
    msg += fmt::format(" (bodies: {}{}{})", quoted_list(shown),
                       options.size() > kShown ? fmt::format(" and {} more", options.size() - kShown) : "",
                       allow_ground && options.size() > kShown ? ", or 'ground'" : "");
    r_.fail(n, msg);
  }

  Pose pose(int body) const { return body == kGround ? Pose{} : poses_[static_cast<std::size_t>(body)]; }
  std::string body_label(int body) const {
    return body == kGround ? std::string("the ground") : fmt::format("\"{}\"", body_names_[static_cast<std::size_t>(body)]);
  }

  // `bodies = ["a", "b"]`: two different bodies, either may be the ground.
  std::pair<int, int> body_pair(const toml::table& tbl, const std::string& prefix, std::string_view table) const {
    const toml::node& n = r_.required(tbl, table, "bodies", "[\"a\", \"b\"]: two body names, or \"ground\"");
    const std::string key = join_key(prefix, "bodies");
    const toml::array& a = r_.array(n, key, 2, "body names (or \"ground\")");
    const int ia = body_index(*a.get(0), item(key, 0), true);
    const int ib = body_index(*a.get(1), item(key, 1), true);
    if (ia == ib)
      r_.fail(*a.get(1), fmt::format("'{}' names {} twice; a {} joins two different bodies (or a body and "
                                     "\"ground\")",
                                     key, body_label(ia), table == "springs" ? "spring" : "joint"));
    return {ia, ib};
  }

  // --- bodies ----------------------------------------------------------------

  void read_bodies(MultibodySpec& spec) {
    const auto list = tables("bodies", true, "body");
    for (std::size_t i = 0; i < list.size(); ++i) {
      const toml::table& t = *list[i];
      const std::string prefix = item("bodies", i);
      r_.check_keys(t, "bodies", kBodyKeys, sections());
      BodySpec b;
      b.where = where(t);
      const toml::node& name_node = r_.required(t, "bodies", "name", "a name such as \"upper_arm\"");
      b.name = r_.string(name_node, join_key(prefix, "name"));
      check_part_name(r_, name_node, join_key(prefix, "name"), b.name);
      claim_name(&name_node, t, "body", b.name);
      if (const toml::node* k = t.get("kind")) b.particle = r_.choice(*k, join_key(prefix, "kind"), kBodyKinds) == 1;
      if (b.particle) {
        read_particle(t, prefix, b);
        poses_.push_back({b.R0_WB, b.x0_W});
        body_index_.emplace(b.name, static_cast<int>(body_names_.size()));
        body_names_.push_back(b.name);
        particle_.push_back(true);
        spec.bodies.push_back(std::move(b));
        continue;
      }

      const MassInertia mi = read_mass_inertia(r_, t, "bodies", prefix);
      b.mass = mi.mass;
      b.inertia_com = mi.inertia_com;
      if (const toml::node* ax = t.get("inertia_axes")) {
        const std::string name = join_key(prefix, "inertia_axes");
        if (!t.get("inertia_principal"))
          r_.fail(*ax, fmt::format("'{}' goes with '{}' (the principal moments along these axes); a full "
                                   "'inertia' tensor carries its axes already",
                                   name, join_key(prefix, "inertia_principal")));
        const Mat3 A = r_.mat3(*ax, name);
        const double dev = (A * A.transpose() - Mat3::Identity()).norm();
        if (dev > kPerpendicularError)
          r_.fail(*ax, fmt::format("the rows of '{}' must be three orthonormal directions (the principal axes "
                                   "in body components): ||A A^T - I||_F = {:.3g} > {:g}",
                                   name, dev, kPerpendicularError));
        // Rows are the axes a_k: J = sum_k J_k a_k a_k^T = A^T diag(J) A.
        b.inertia_com = A.transpose() * mi.inertia_com * A;
        b.inertia_com = 0.5 * (b.inertia_com + b.inertia_com.transpose()).eval();
      }
      // A flat part (J_i = J_j + J_k, a disk) is accepted: held by joints it
      // is as determined as any other (the heavy top is one).
      check_possible_moments(r_, *mi.node, mi.name, b.inertia_com);

      const toml::node& pos = r_.required(t, "bodies", "position", "[x, y, z] in m: the centre of mass in space");
      b.x0_W = bounded_vec3(r_, pos, join_key(prefix, "position"), kMaxLength, "m");
      b.R0_WB = read_orientation(r_, t, "bodies", prefix, sections(), false).value_or(Mat3::Identity());
      if (const toml::node* v = t.get("velocity"))
        b.v0_W = bounded_vec3(r_, *v, join_key(prefix, "velocity"), kMaxSpeed, "m/s");
      Vec3 w = Vec3::Zero();
      if (const toml::node* n = t.get("angular_velocity"))
        w = bounded_vec3(r_, *n, join_key(prefix, "angular_velocity"), kMaxAngularSpeed, "rad/s");
      bool space = true;
      if (const toml::node* f = t.get("angular_velocity_frame"))
        space = r_.choice(*f, join_key(prefix, "angular_velocity_frame"), kFrames) == 0;
      b.omega0_B = space ? Vec3(b.R0_WB.transpose() * w) : w;
      // pivot = [x, y, z] (m, space): the body turns about this fixed point
      // only (the one-body model of a top); its centre of mass keeps its
      // distance, and its velocity follows from the angular velocity.
      if (const toml::node* p = t.get("pivot")) {
        b.pivot_W = bounded_vec3(r_, *p, join_key(prefix, "pivot"), kMaxLength, "m");
        if (const toml::node* v = t.get("velocity"))
          r_.fail(*v, fmt::format("'{}' is given, but body '{}' has a pivot: its centre of mass moves with its "
                                  "rotation about the pivot (omega x (position - pivot)); leave 'velocity' out",
                                  join_key(prefix, "velocity"), b.name));
        b.v0_W = (b.R0_WB * b.omega0_B).cross(b.x0_W - *b.pivot_W);
      }
      if (const toml::node* c = t.get("coordinates")) {
        // The values formulation.coordinates takes: the representation registry's.
        const std::vector<std::string> names = settings::scene_setting("formulation.coordinates").choices();
        const std::vector<std::string_view> opts(names.begin(), names.end());
        b.coordinates = Coordinates(names[r_.choice(*c, join_key(prefix, "coordinates"), opts)]);
      }
      b.visuals = read_visuals(r_, t, "bodies", prefix, sections());
      poses_.push_back({b.R0_WB, b.x0_W});
      body_index_.emplace(b.name, static_cast<int>(body_names_.size()));
      body_names_.push_back(b.name);
      particle_.push_back(false);
      spec.bodies.push_back(std::move(b));
    }
  }

  // A point mass: mass, position, velocity (and how to draw it); no
  // inertia, orientation or angular velocity, which are refused by name.
  void read_particle(const toml::table& t, const std::string& prefix, BodySpec& b) const {
    for (const auto& [k, n] : t) {
      if (std::find(kParticleKeys.begin(), kParticleKeys.end(), k.str()) != kParticleKeys.end()) continue;
      r_.fail(n, fmt::format("'{}' does not apply to a particle (kind = \"particle\": a point mass has no "
                             "inertia, orientation or angular velocity; its keys: {}); leave it out, or make the body "
                             "kind = \"rigid\"",
                             join_key(prefix, k.str()), quoted_list(kParticleKeys)));
    }
    const toml::node& mass_node = r_.required(t, "bodies", "mass", "kg, > 0");
    b.mass = bounded_number(r_, mass_node, join_key(prefix, "mass"), 0.0, 1e12, "kg");
    if (!(b.mass > 0.0)) r_.fail(mass_node, fmt::format("'{}' must be > 0 kg, got {}", join_key(prefix, "mass"), b.mass));
    b.inertia_com = Mat3::Zero();
    const toml::node& pos = r_.required(t, "bodies", "position", "[x, y, z] in m: the particle in space");
    b.x0_W = bounded_vec3(r_, pos, join_key(prefix, "position"), kMaxLength, "m");
    if (const toml::node* v = t.get("velocity"))
      b.v0_W = bounded_vec3(r_, *v, join_key(prefix, "velocity"), kMaxSpeed, "m/s");
    b.visuals = read_visuals(r_, t, "bodies", prefix, sections());
  }

  bool is_particle(int body) const { return body != kGround && particle_[static_cast<std::size_t>(body)]; }

  // --- mechanism -------------------------------------------------------------

  // expected_dof: at the top level or in [mechanism] (not both). The
  // mobility the author expects; the start warns when the rank's differs.
  void read_expected_dof(MultibodySpec& spec) {
    const toml::node* top = root_.get("expected_dof");
    const toml::node* in_table = nullptr;
    if (const toml::node* m = root_.get("mechanism")) {
      const toml::table* t = m->as_table();
      if (!t)
        r_.fail(*m, fmt::format("'mechanism' must be a table ([mechanism] with expected_dof = N), not {}",
                                type_name(*m)));
      r_.check_keys(*t, "mechanism", kMechanismKeys, sections());
      in_table = t->get("expected_dof");
      read_assembly(*t, spec);
      // singular_poses = "bridge" (default) or "integrate": how a run passes
      // a pose where the rows lose rank (multibody/pose_bridge.cpp).
      if (const toml::node* sp = t->get("singular_poses"))
        spec.bridge_singular_poses = r_.choice(*sp, "mechanism.singular_poses", kSingularPoseModes) == 0;
      if (top && in_table)
        r_.fail(*in_table, fmt::format("expected_dof is given twice: at the top level (line {}) and in [mechanism]; "
                                       "keep one",
                                       top->source().begin.line));
    }
    const toml::node* n = top ? top : in_table;
    if (!n) return;
    const std::string name = top ? "expected_dof" : "mechanism.expected_dof";
    const long long v = r_.integer(*n, name);
    long long most = 0;
    for (const BodySpec& b : spec.bodies) most += b.particle ? 3 : 6;
    if (v < 0 || v > most)
      r_.fail(*n, fmt::format("'{}' = {} must lie in [0, {}] (degrees of freedom: at most 6 per body and 3 per "
                              "particle, {} bodies)",
                              name, v, most, spec.bodies.size()));
    spec.expected_dof = static_cast<int>(v);
    spec.expected_dof_where = where(*n);
  }

  // [mechanism] assemble = true and/or hold = ["body", ...]: the start
  // assembles the mechanism from the given poses (guesses), keeping the held
  // bodies' poses and velocities (multibody/assembly.hpp).
  void read_assembly(const toml::table& t, MultibodySpec& spec) {
    const toml::node* assemble = t.get("assemble");
    const toml::node* hold = t.get("hold");
    if (assemble) {
      spec.assembly.requested = r_.boolean(*assemble, "mechanism.assemble");
      spec.assembly.where = where(*assemble);
    }
    if (!hold) return;
    if (assemble && !spec.assembly.requested)
      r_.fail(*hold, "'mechanism.hold' names bodies whose poses an assembled start keeps, but 'mechanism.assemble' "
                     "= false: set assemble = true or leave it out");
    const toml::array* a = hold->as_array();
    if (!a || a->empty())
      r_.fail(*hold, fmt::format("'mechanism.hold' must be a non-empty array of body names (e.g. [\"crank\"]), "
                                 "not {}",
                                 a ? "an empty array" : type_name(*hold)));
    std::vector<char> seen(spec.bodies.size(), 0);
    for (std::size_t k = 0; k < a->size(); ++k) {
      const std::string key = fmt::format("mechanism.hold[{}]", k);
      if (r_.string(*a->get(k), key) == kGroundName)
        r_.fail(*a->get(k), fmt::format("'{}' = \"ground\": the ground never moves; hold names bodies", key));
      const int b = body_index(*a->get(k), key, false);
      if (seen[static_cast<std::size_t>(b)])
        r_.fail(*a->get(k), fmt::format("'{}' = \"{}\" is held twice", key, body_names_[static_cast<std::size_t>(b)]));
      seen[static_cast<std::size_t>(b)] = 1;
      spec.assembly.held.push_back(b);
    }
    if (spec.assembly.held.size() == spec.bodies.size())
      r_.fail(*hold, "'mechanism.hold' holds every body: nothing is left to assemble (hold the driving bodies, "
                     "e.g. the crank, and let the others follow)");
    std::sort(spec.assembly.held.begin(), spec.assembly.held.end());
    spec.assembly.requested = true;
    if (!assemble) spec.assembly.where = where(*hold);
  }

  // --- joints ----------------------------------------------------------------

  void read_joints(MultibodySpec& spec) {
    joint_tables_ = tables("joints", false, "joint");
    for (std::size_t i = 0; i < joint_tables_.size(); ++i) spec.joints.push_back(read_joint(*joint_tables_[i], i));
  }

  JointSpec read_joint(const toml::table& t, std::size_t i) {
    const std::string prefix = item("joints", i);
    const auto key = [&](std::string_view k) { return join_key(prefix, k); };
    r_.check_keys(t, "joints", joint_keys(), sections());
    JointSpec j;
    j.where = where(t);
    const toml::node* name_node = t.get("name");
    j.name = name_node ? r_.string(*name_node, key("name")) : fmt::format("joint{}", i + 1);
    if (name_node) check_part_name(r_, *name_node, key("name"), j.name);
    claim_name(name_node, t, "joint", j.name);

    // The types and their keys: the registry's (model/joint_type.hpp).
    const std::vector<std::string_view> type_names = joint_type_names();
    const toml::node& type_node = r_.required(t, "joints", "type", quoted_list(type_names));
    j.type = joint_types()[r_.choice(type_node, key("type"), type_names)];
    const std::string_view type_name = j.type->name;
    std::tie(j.body_a, j.body_b) = body_pair(t, prefix, "joints");
    bool body_frame = false;
    if (const toml::node* f = t.get("frame")) body_frame = r_.choice(*f, key("frame"), kFrames) == 1;
    check_particle_joint_type(t, j);
    if (j.type->axes == JointAxes::TwoPoints) {
      read_two_points(t, prefix, body_frame, j);
      check_particle_points(t, j);
      return j;
    }

    const bool has_axis = j.type->axes == JointAxes::Axis;
    const bool universal = j.type->axes == JointAxes::CrossPins;
    const std::span<const std::string_view> force_keys = j.type->force_keys;
    const auto carried = [&](std::string_view k) {
      return std::find(force_keys.begin(), force_keys.end(), k) != force_keys.end();
    };

    // The keys this type and frame use; any other is a mistake.
    std::vector<std::string_view> valid{"name", "type", "bodies", "frame"};
    if (body_frame) {
      valid.insert(valid.end(), {"point_a", "point_b"});
      if (has_axis || universal) valid.insert(valid.end(), {"axis_a", "axis_b"});
      if (has_axis) valid.insert(valid.end(), {"normal_a", "normal_b"});
    } else {
      valid.push_back("point");
      if (has_axis) valid.push_back("axis");
      if (universal) valid.insert(valid.end(), {"axis_a", "axis_b"});
    }
    valid.insert(valid.end(), force_keys.begin(), force_keys.end());
    for (std::string_view k : joint_keys()) {
      const toml::node* n = t.get(k);
      if (!n || std::find(valid.begin(), valid.end(), k) != valid.end()) continue;
      const bool per_body = k == "point_a" || k == "point_b" || k == "normal_a" || k == "normal_b";
      std::string why;
      if (!carried(k) && is_force_key(k))
        why = fmt::format("it is a key of a force element that only {} joints carry", quoted_list(types_carrying(k)));
      else if (!body_frame && per_body)
        why = "in space (the default frame) a joint has one 'point'; per-body points and normals need "
              "frame = \"body\"";
      else if (body_frame && (k == "point" || k == "axis"))
        why = "with frame = \"body\" give 'point_a' and 'point_b' (and 'axis_a', 'axis_b') in each body's frame";
      else if (k == "axis" && universal)
        why = "a universal joint has two pins: 'axis_a' (fixed in the first body) and 'axis_b'";
      else if (has_axis && (k == "axis_a" || k == "axis_b"))
        why = "in space one 'axis' serves both bodies; 'axis_a' and 'axis_b' need frame = \"body\"";
      else if (universal && (k == "normal_a" || k == "normal_b"))
        why = "its pins 'axis_a' and 'axis_b' are normal to each other already";
      else if (k == "length")
        why = fmt::format("'length' is a distance joint's (a rod between 'point_a' and 'point_b')");
      else
        why = fmt::format("a {} joint has no axis", type_name);
      r_.fail(*n, fmt::format("'{}' does not apply to a {} joint{}: {} (its keys: {})", key(k), type_name,
                              body_frame ? " with frame = \"body\"" : "", why, quoted_list(valid)));
    }

    const Pose pa = pose(j.body_a), pb = pose(j.body_b);
    const auto required = [&](std::string_view k, std::string_view what) -> const toml::node& {
      return r_.required(t, "joints", k, fmt::format("{} of this {} joint", what, type_name));
    };
    if (!body_frame) {
      const Vec3 p = bounded_vec3(r_, required("point", "[x, y, z] in m, in space at the initial pose: the joint point"),
                                  key("point"), kMaxLength, "m");
      // One axis (u) and a normal (n) in space, equal for both bodies now.
      Vec3 u_a = Vec3::UnitZ(), u_b = Vec3::UnitZ(), n_a = Vec3::UnitX(), n_b = Vec3::UnitX();
      if (has_axis) {
        u_a = u_b = direction(r_, required("axis", "[x, y, z] in space: the axis"), key("axis"));
        n_a = n_b = default_normal(u_a);
      } else if (universal) {
        u_a = direction(r_, required("axis_a", "[x, y, z] in space: the cross-pin axis fixed in the first body"),
                        key("axis_a"));
        const toml::node& nb = required("axis_b", "[x, y, z] in space: the cross-pin axis fixed in the second body");
        u_b = perpendicular(r_, nb, key("axis_b"), direction(r_, nb, key("axis_b")), u_a, fmt::format("'{}'", key("axis_a")),
                            " (the two pins of a universal joint are at right angles)");
        n_a = u_b;  // the partner pin: perpendicular to each axis (unused by the joint)
        n_b = u_a;
      }
      j.point_a = pa.R.transpose() * (p - pa.x);
      j.point_b = pb.R.transpose() * (p - pb.x);
      j.axis_a = pa.R.transpose() * u_a;
      j.axis_b = pb.R.transpose() * u_b;
      j.normal_a = pa.R.transpose() * n_a;
      j.normal_b = pb.R.transpose() * n_b;
    } else {
      j.point_a = bounded_vec3(r_, required("point_a", "[x, y, z] in m, in the first body's frame from its centre of mass"),
                               key("point_a"), kMaxLength, "m");
      j.point_b = bounded_vec3(r_, required("point_b", "[x, y, z] in m, in the second body's frame from its centre of mass"),
                               key("point_b"), kMaxLength, "m");
      // Fixed and spherical joints: the initial relative orientation is welded
      // (fixed) or free (spherical); the axes below only keep the spec's
      // invariants.
      j.axis_a = pa.R.transpose().col(2);
      j.axis_b = pb.R.transpose().col(2);
      j.normal_a = pa.R.transpose().col(0);
      j.normal_b = pb.R.transpose().col(0);
      if (has_axis || universal) {
        const toml::node& na = required("axis_a", "[x, y, z] in the first body's frame: the axis");
        const toml::node& nb = required("axis_b", "[x, y, z] in the second body's frame: the axis");
        j.axis_a = direction(r_, na, key("axis_a"));
        j.axis_b = direction(r_, nb, key("axis_b"));
        const Vec3 ua = pa.R * j.axis_a, ub = pb.R * j.axis_b;
        if (universal) {
          const double c = ua.dot(ub);
          if (std::abs(c) > kPerpendicularError)
            r_.fail(nb, fmt::format("the pins of a universal joint must be at right angles at the initial pose; "
                                    "'{}' and '{}' make {:.6g} degrees there (in space: {} and {})",
                                    key("axis_a"), key("axis_b"), std::acos(std::clamp(c, -1.0, 1.0)) * 180.0 / std::numbers::pi,
                                    fmt_vec6(ua), fmt_vec6(ub)));
          j.normal_a = pa.R.transpose() * (ub - ub.dot(ua) * ua).normalized();
          j.normal_b = pb.R.transpose() * (ua - ua.dot(ub) * ub).normalized();
        } else {
          const std::string hint = " (or leave it out: the loader then computes one)";
          if (const toml::node* n = t.get("normal_a"))
            j.normal_a = perpendicular(r_, *n, key("normal_a"), direction(r_, *n, key("normal_a")), j.axis_a,
                                       fmt::format("'{}'", key("axis_a")), hint);
          else
            j.normal_a = default_normal(j.axis_a);
          if (const toml::node* n = t.get("normal_b")) {
            j.normal_b = perpendicular(r_, *n, key("normal_b"), direction(r_, *n, key("normal_b")), j.axis_b,
                                       fmt::format("'{}'", key("axis_b")), hint);
          } else {
            // Carried from a at the initial pose, so that a revolute joint's
            // angle is zero there (as with frame = "space").
            const Vec3 carried = pb.R.transpose() * (pa.R * j.normal_a);
            const Vec3 off = carried - carried.dot(j.axis_b) * j.axis_b;
            j.normal_b = off.norm() > 1e-3 ? off.normalized() : default_normal(j.axis_b);
          }
        }
      }
    }

    // A torsional spring-damper's keys (src/multibody/force_elements/torsion_spring.cpp).
    if (carried("stiffness")) {
      if (const toml::node* n = t.get("stiffness"))
        j.torsion_stiffness = bounded_number(r_, *n, key("stiffness"), 0.0, kMaxCoefficient, "N m/rad");
      if (const toml::node* n = t.get("damping"))
        j.torsion_damping = bounded_number(r_, *n, key("damping"), 0.0, kMaxCoefficient, "N m s/rad");
      if (const toml::node* n = t.get("rest_angle"))
        j.torsion_rest_angle = bounded_number(r_, *n, key("rest_angle"), -kMaxRestAngle, kMaxRestAngle, "rad");
    }
    // A motor's keys: a torque about the axis (motor_torque: the torsional
    // element) or a force along it (motor_force: joint_force.cpp), scaled by
    // motor_profile.
    if (carried("motor_torque") || carried("motor_force")) {
      const bool torque = carried("motor_torque");
      const std::string amount = torque ? "motor_torque" : "motor_force";
      const char* unit = torque ? "N m" : "N";
      const toml::node* n = t.get(amount);
      if (n) (torque ? j.motor_torque : j.motor_force) = bounded_number(r_, *n, key(amount), -kMaxForce, kMaxForce, unit);
      if (const toml::node* pr = t.get("motor_profile")) {
        if (!n)
          r_.fail(*pr, fmt::format("'{}' scales '{}', which {} does not give ({}, on b {} the axis)", key("motor_profile"),
                                   amount, prefix, unit, torque ? "about" : "along"));
        j.motor_profile = read_time_function(
            r_, *pr, key("motor_profile"), fmt::format("the factor (dimensionless) that scales '{}' at time t", amount),
            false);
      }
    }
    check_particle_points(t, j);
    return j;
  }

  // --- joints on particles -----------------------------------------------------

  // Whether a type's rows read body `side` (0: a, 1: b) through points only:
  // a particle has a position but no orientation, so a row with a direction
  // fixed in it (an axis, a pin, a weld's frame) cannot hold it.
  static bool points_only(const JointType& type, int side) {
    JointSpec probe;
    probe.type = &type;
    probe.body_a = side == 0 ? 0 : kGround;
    probe.body_b = side == 0 ? kGround : 0;
    probe.point_b = Vec3::UnitX();
    probe.length = 1.0;
    std::vector<ConstraintRow> rows;
    type.rows(probe, rows);
    for (const ConstraintRow& r : rows)
      for (int t = 0; t < r.n_terms; ++t)
        for (const BodyVector* v : {&r.terms[t].a, &r.terms[t].b})
          if (v->body == 0 && !v->point) return false;
    return true;
  }

  void check_particle_joint_type(const toml::table& t, const JointSpec& j) const {
    for (int side = 0; side < 2; ++side) {
      const int body = side == 0 ? j.body_a : j.body_b;
      if (!is_particle(body) || points_only(*j.type, side)) continue;
      std::vector<std::string_view> valid;
      for (const JointType* type : joint_types())
        if (points_only(*type, 0) && points_only(*type, 1)) valid.push_back(type->name);
      const toml::node* n = t.get("type");
      r_.fail(n ? *n : static_cast<const toml::node&>(t),
              fmt::format("joint \"{}\" ({}) needs an orientation of {}, which is a particle (kind = \"particle\": a "
                          "point mass has a position only); joints that can hold a particle: {}",
                          j.name, j.type->name, body_label(body), quoted_list(valid)));
    }
  }

  // A particle has no extent: a joint holds it at its position.
  void check_particle_points(const toml::table& t, const JointSpec& j) const {
    for (int side = 0; side < 2; ++side) {
      const int body = side == 0 ? j.body_a : j.body_b;
      if (!is_particle(body)) continue;
      const Vec3& s = side == 0 ? j.point_a : j.point_b;
      const Vec3 x = pose(body).x;
      if (s.norm() <= 1e-9 * std::max(1.0, x.norm())) continue;
      const char* k = j.type->axes == JointAxes::TwoPoints ? (side == 0 ? "point_a" : "point_b") : "point";
      const toml::node* n = t.get(k);
      if (!n) n = t.get(side == 0 ? "point_a" : "point_b");
      r_.fail(n ? *n : static_cast<const toml::node&>(t),
              fmt::format("joint \"{}\" holds {}, a particle, {} m away from it: a point mass has no extent, its "
                          "joints act at its position {} (give that point{})",
                          j.name, body_label(body), s.norm(), fmt_vec6(x),
                          j.type->axes == JointAxes::TwoPoints ? fmt::format(", or leave '{}' out", k) : ""));
    }
  }

  // A distance joint's keys: point_a, point_b (each optional on a particle:
  // its position) and length (default: the initial distance).
  void read_two_points(const toml::table& t, const std::string& prefix, bool body_frame, JointSpec& j) const {
    const auto key = [&](std::string_view k) { return join_key(prefix, k); };
    const std::vector<std::string_view> valid{"name", "type", "bodies", "frame", "point_a", "point_b", "length"};
    for (std::string_view k : joint_keys()) {
      const toml::node* n = t.get(k);
      if (!n || std::find(valid.begin(), valid.end(), k) != valid.end()) continue;
      r_.fail(*n, fmt::format("'{}' does not apply to a {} joint: it joins 'point_a' on the first body and 'point_b' on "
                              "the second (in space at the initial pose, or frame = \"body\"), at 'length' (its keys: {})",
                              key(k), j.type->name, quoted_list(valid)));
    }
    const Pose pose_of[2] = {pose(j.body_a), pose(j.body_b)};
    const int body_of[2] = {j.body_a, j.body_b};
    Vec3* out[2] = {&j.point_a, &j.point_b};
    const char* names[2] = {"point_a", "point_b"};
    for (int side = 0; side < 2; ++side) {
      const toml::node* n = t.get(names[side]);
      if (!n && is_particle(body_of[side])) {
        out[side]->setZero();  // the particle's position
        continue;
      }
      if (!n)
        n = &r_.required(t, "joints", names[side],
                         fmt::format("[x, y, z] in m, {}: the rod's end on {} (optional on a particle: its position)",
                                     body_frame ? "in that body's frame from its centre of mass" : "in space at the initial pose",
                                     body_label(body_of[side])));
      const Vec3 p = bounded_vec3(r_, *n, key(names[side]), kMaxLength, "m");
      *out[side] = body_frame ? p : Vec3(pose_of[side].R.transpose() * (p - pose_of[side].x));
    }
    const Vec3 pa = pose_of[0].R * j.point_a + pose_of[0].x, pb = pose_of[1].R * j.point_b + pose_of[1].x;
    const double initial = (pb - pa).norm();
    if (const toml::node* n = t.get("length")) {
      j.length = bounded_number(r_, *n, key("length"), 0.0, kMaxLength, "m");
      if (!(j.length >= kMinSpringLength))
        r_.fail(*n, fmt::format("'{}' = {} m: a rod needs a length of at least {:g} m (for coincident points use a "
                                "spherical joint)",
                                key("length"), j.length, kMinSpringLength));
    } else {
      j.length = initial;
      if (initial < kMinSpringLength)
        r_.fail(t.source(), fmt::format("the ends of distance joint \"{}\" coincide at the initial pose ({:.3g} m apart): "
                                        "give 'length', or use a spherical joint for coincident points",
                                        j.name, initial));
    }
    // Unused by the row; kept unit, perpendicular and equal in space at the
    // initial pose (the spec's invariants, as for a spherical joint).
    j.axis_a = pose_of[0].R.transpose().col(2);
    j.axis_b = pose_of[1].R.transpose().col(2);
    j.normal_a = pose_of[0].R.transpose().col(0);
    j.normal_b = pose_of[1].R.transpose().col(0);
  }

  // --- the joints between one pair of bodies ----------------------------------

  // The conditions a joint puts on the relative motion of b with respect to
  // a at the initial pose, as rows acting on the twist (v, L w): v the
  // velocity of b's point at `ref`, w its angular velocity (both relative to
  // a, in space), L a length that makes the columns comparable. A point of b
  // at p then moves at v + w x (p - ref). Read off the joint type's rows at
  // the initial pose (model/constraint_row.hpp): a point row along e
  // (coincident points, point on a line with normal e) is e . (v + w x p),
  // p the joint point; a perpendicular pair d_a . d_b is (d_a x d_b) . w.
  Eigen::Matrix<double, Eigen::Dynamic, 6> conditions(const JointSpec& j, const Vec3& ref, double L) const {
    const Pose pa = pose(j.body_a);
    const Vec3 p = pa.R * j.point_a + pa.x - ref;
    const auto in_space = [&](const BodyVector& b) { return Vec3(pose(b.body).R * b.s); };
    std::vector<ConstraintRow> joint_rows;
    j.type->rows(j, joint_rows);
    using Row = Eigen::Matrix<double, 1, 6>;
    Eigen::Matrix<double, Eigen::Dynamic, 6> M(static_cast<Eigen::Index>(joint_rows.size()), 6);
    for (std::size_t k = 0; k < joint_rows.size(); ++k) {
      const DotTerm& t = joint_rows[k].terms[0];
      Row row = Row::Zero();
      if (joint_rows[k].reaction == RowReaction::Distance) {
        // (p_b - p_a) . (relative velocity of b's end p_b) = 0
        const Vec3 pb = pose(j.body_b).R * j.point_b + pose(j.body_b).x;
        const Vec3 u = (pb - (p + ref)).normalized();
        row << u.transpose(), (pb - ref).cross(u).transpose() / L;
      } else if (joint_rows[k].reaction == RowReaction::Turn) {
        row.tail<3>() = in_space(t.a).cross(in_space(t.b)).transpose() / L;
      } else {
        const Vec3 n = in_space(t.b);
        row << n.transpose(), p.cross(n).transpose() / L;
      }
      M.row(static_cast<Eigen::Index>(k)) = row.normalized();
    }
    return M;
  }

  static int rank(const Eigen::Matrix<double, Eigen::Dynamic, 6>& M) {
    if (M.rows() == 0) return 0;
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(M);
    const auto& s = svd.singularValues();
    int r = 0;
    for (Eigen::Index k = 0; k < s.size(); ++k)
      if (s[k] > kRankTol * s[0]) ++r;
    return r;
  }

  // Joints between the same two bodies must impose independent conditions:
  // a repeated joint, or two that fight (two hinges with different axes),
  // make the constraint Jacobian lose rank, and their reactions are not
  // determined. Checked pair by pair, in file order, at the initial pose.
  void check_joint_pairs(const MultibodySpec& spec) const {
    std::map<std::pair<int, int>, std::vector<std::size_t>> pairs;
    for (std::size_t i = 0; i < spec.joints.size(); ++i) {
      const JointSpec& j = spec.joints[i];
      std::vector<std::size_t>& earlier = pairs[std::minmax(j.body_a, j.body_b)];
      if (!earlier.empty()) {
        // Reference point and length scale: the pair's joint points.
        const auto space_point = [&](const JointSpec& k) { return Vec3(pose(k.body_a).R * k.point_a + pose(k.body_a).x); };
        const Vec3 ref = space_point(j);
        double L = 1e-6;
        for (std::size_t k : earlier) L = std::max(L, (space_point(spec.joints[k]) - ref).norm());
        Eigen::Matrix<double, Eigen::Dynamic, 6> prior(0, 6);
        for (std::size_t k : earlier) {
          const auto rows = conditions(spec.joints[k], ref, L);
          prior.conservativeResize(prior.rows() + rows.rows(), 6);
          prior.bottomRows(rows.rows()) = rows;
        }
        const auto mine = conditions(j, ref, L);
        Eigen::Matrix<double, Eigen::Dynamic, 6> all(prior.rows() + mine.rows(), 6);
        all << prior, mine;
        const int r_before = rank(prior), r_mine = rank(mine), r_all = rank(all);
        if (r_all < r_before + r_mine) {
          std::vector<std::string> names;
          for (std::size_t k : earlier) names.push_back(fmt::format("\"{}\" (line {})", spec.joints[k].name, spec.joints[k].where.line));
          std::string others;
          for (std::size_t k = 0; k < names.size(); ++k) others += (k ? ", " : "") + names[k];
          const std::string between = fmt::format("between {} and {}", body_label(j.body_a), body_label(j.body_b));
          const toml::table& t = *joint_tables_[i];
          // A repeat at another point is what engineers write on purpose (a
          // shaft in two bearings, a door on two hinges): accepted as
          // redundancy, its rows set aside at the start and its reactions split
          // by minimum norm (multibody/minimum_norm_reactions.cpp). The same
          // joint at the same point again is a slip of the pen: refused.
          bool same_point = false;
          for (std::size_t k : earlier)
            same_point = same_point || (space_point(spec.joints[k]) - ref).norm() <= 1e-9 * std::max(1.0, ref.norm());
          if (r_all == r_before && !same_point) {
            earlier.push_back(i);
            continue;
          }
          if (r_all == r_before)
            r_.fail(t.source(),
                    fmt::format("joint \"{}\" repeats what {} {} already impose{} {}: it adds no condition of its "
                                "own at the same point, so it is the same joint twice; remove it (a second bearing "
                                "on the same axis elsewhere is accepted as redundant)",
                                j.name, names.size() > 1 ? "joints" : "joint", others,
                                names.size() > 1 ? "" : "s", between));
          r_.fail(t.source(),
                  fmt::format("joint \"{}\" fights {} {}: together they impose {} conditions on the relative motion "
                              "at the initial pose, of which only {} are independent, leaving {} degree{} of freedom{}; "
                              "the reactions of dependent conditions are not determined (replace them by one joint "
                              "that allows the motion wanted)",
                              j.name, others, between, all.rows(), r_all, 6 - r_all, 6 - r_all == 1 ? "" : "s",
                              r_all == 6 ? " (none: use one 'fixed' joint, or none at all for the ground)" : ""));
        }
      }
      earlier.push_back(i);
    }
  }

  // A body welded to the ground, directly or through other welded bodies,
  // cannot move: its unknowns would only carry the weld's reactions. Refused
  // (the ground is rigid already; leave the body out).
  void check_welds(const MultibodySpec& spec) const {
    std::vector<int> parent(spec.bodies.size() + 1);  // 0 = ground, i + 1 = body i
    std::iota(parent.begin(), parent.end(), 0);
    const auto find = [&](int x) {
      while (parent[static_cast<std::size_t>(x)] != x) x = parent[static_cast<std::size_t>(x)];
      return x;
    };
    for (std::size_t i = 0; i < spec.joints.size(); ++i) {
      const JointSpec& j = spec.joints[i];
      if (j.type->freedoms.total() != 0) continue;
      const int a = find(j.body_a + 1), b = find(j.body_b + 1);
      if ((a == find(0)) != (b == find(0))) {
        // Every body of the group this weld joins to the ground.
        const int group = a == find(0) ? b : a;
        std::vector<std::string> held;
        for (std::size_t k = 0; k < spec.bodies.size(); ++k)
          if (find(static_cast<int>(k) + 1) == group) held.push_back(body_label(static_cast<int>(k)));
        std::string list;
        for (std::size_t k = 0; k < held.size(); ++k)
          list += (k == 0 ? "" : k + 1 == held.size() ? " and " : ", ") + held[k];
        r_.fail(joint_tables_[i]->source(),
                fmt::format("{} joint \"{}\" welds {} {} to the ground{}: {} cannot move, and a part that cannot "
                            "move is part of the ground (leave it out, or give the joint a type that allows motion)",
                            j.type->name, j.name, held.size() > 1 ? "bodies" : "body", list,
                            held.size() > 1 ? " (with the fixed joints that join them)" : "",
                            held.size() > 1 ? "they" : "it"));
      }
      parent[static_cast<std::size_t>(a)] = b;
    }
  }

  // --- springs and loads --------------------------------------------------------

  void read_springs(MultibodySpec& spec) {
    const auto list = tables("springs", false, "spring");
    for (std::size_t i = 0; i < list.size(); ++i) {
      const toml::table& t = *list[i];
      const std::string prefix = item("springs", i);
      const auto key = [&](std::string_view k) { return join_key(prefix, k); };
      r_.check_keys(t, "springs", kSpringKeys, sections());
      SpringSpec s;
      s.where = where(t);
      const toml::node* name_node = t.get("name");
      s.name = name_node ? r_.string(*name_node, key("name")) : fmt::format("spring{}", i + 1);
      if (name_node) check_part_name(r_, *name_node, key("name"), s.name);
      claim_name(name_node, t, "spring", s.name);
      std::tie(s.body_a, s.body_b) = body_pair(t, prefix, "springs");
      bool body_frame = false;
      if (const toml::node* f = t.get("frame")) body_frame = r_.choice(*f, key("frame"), kFrames) == 1;
      const Pose pa = pose(s.body_a), pb = pose(s.body_b);
      const char* frame_what = body_frame ? "in m, in that body's frame from its centre of mass"
                                          : "in m, in space at the initial pose";
      const toml::node& na = r_.required(t, "springs", "point_a", fmt::format("the end on the first body, {}", frame_what));
      const toml::node& nb = r_.required(t, "springs", "point_b", fmt::format("the end on the second body, {}", frame_what));
      const Vec3 a = bounded_vec3(r_, na, key("point_a"), kMaxLength, "m");
      const Vec3 b = bounded_vec3(r_, nb, key("point_b"), kMaxLength, "m");
      s.point_a = body_frame ? a : Vec3(pa.R.transpose() * (a - pa.x));
      s.point_b = body_frame ? b : Vec3(pb.R.transpose() * (b - pb.x));
      // A particle has no extent: a spring acts at its position.
      for (int side = 0; side < 2; ++side) {
        const int body = side == 0 ? s.body_a : s.body_b;
        const Vec3& off = side == 0 ? s.point_a : s.point_b;
        const Vec3 x = pose(body).x;
        if (is_particle(body) && off.norm() > 1e-9 * std::max(1.0, x.norm()))
          r_.fail(side == 0 ? na : nb,
                  fmt::format("spring \"{}\" is attached to {}, a particle, {:.6g} m away from it: a point mass has no "
                              "extent; attach it at the particle's position {}",
                              s.name, body_label(body), off.norm(), body_frame ? fmt_vec6(Vec3::Zero()) : fmt_vec6(x)));
      }
      const double length = ((pb.R * s.point_b + pb.x) - (pa.R * s.point_a + pa.x)).norm();
      if (length < kMinSpringLength)
        r_.fail(nb, fmt::format("the ends of spring \"{}\" coincide at the initial pose ({:.3g} m apart), where its "
                                "direction is undefined; attach them at distinct points",
                                s.name, length));
      s.stiffness = bounded_number(r_, r_.required(t, "springs", "stiffness", "N/m, >= 0"), key("stiffness"), 0.0,
                                   kMaxCoefficient, "N/m");
      if (const toml::node* n = t.get("damping"))
        s.damping = bounded_number(r_, *n, key("damping"), 0.0, kMaxCoefficient, "N s/m");
      s.rest_length = length;
      if (const toml::node* n = t.get("rest_length"))
        s.rest_length = bounded_number(r_, *n, key("rest_length"), 0.0, kMaxLength, "m");
      spec.springs.push_back(s);
    }
  }

  void read_loads(MultibodySpec& spec) {
    const auto list = tables("loads", false, "load");
    for (std::size_t i = 0; i < list.size(); ++i) {
      const toml::table& t = *list[i];
      const std::string prefix = item("loads", i);
      const auto key = [&](std::string_view k) { return join_key(prefix, k); };
      r_.check_keys(t, "loads", kLoadKeys, sections());
      BodyLoadSpec l;
      l.where = where(t);
      l.body = body_index(r_.required(t, "loads", "body", "the name of the body it acts on"), key("body"), false);
      const toml::node* f = t.get("force");
      const toml::node* m = t.get("torque");
      if (!f && !m)
        r_.fail(t.source(), fmt::format("{} needs 'force' (N, at the centre of mass) or 'torque' (N m), or both",
                                        prefix));
      if (f) l.force = bounded_vec3(r_, *f, key("force"), kMaxForce, "N");
      if (m) l.torque = bounded_vec3(r_, *m, key("torque"), kMaxForce, "N m");
      if (const toml::node* fr = t.get("frame")) l.body_frame = r_.choice(*fr, key("frame"), kFrames) == 1;
      if (const toml::node* pr = t.get("profile"))
        l.profile = read_time_function(r_, *pr, key("profile"),
                                       "the factor (dimensionless) that scales 'force' and 'torque' at time t", false);
      if (is_particle(l.body)) {
        if (m)
          r_.fail(*m, fmt::format("'{}': {} is a particle, which has no rotation for a torque to act on (give 'force' "
                                  "only)",
                                  key("torque"), body_label(l.body)));
        if (l.body_frame)
          r_.fail(*t.get("frame"), fmt::format("'{}' = \"body\": {} is a particle, which has no body frame (give the "
                                               "force in space)",
                                               key("frame"), body_label(l.body)));
      }
      spec.loads.push_back(l);
    }
  }

  // [[drivers]]: joint = "NAME", coordinate = "angle" (optional when the
  // joint's type has one coordinate), motion = { type = ..., ... }.
  void read_drivers(MultibodySpec& spec) {
    const auto list = tables("drivers", false, "driver");
    for (std::size_t i = 0; i < list.size(); ++i) {
      const toml::table& t = *list[i];
      const std::string prefix = item("drivers", i);
      const auto key = [&](std::string_view k) { return join_key(prefix, k); };
      r_.check_keys(t, "drivers", kDriverKeys, sections());
      DriverSpec d;
      d.where = where(t);
      const toml::node& jn = r_.required(t, "drivers", "joint", "the name of the joint whose coordinate it prescribes");
      const std::string jname = r_.string(jn, key("joint"));
      int joint = -1;
      std::vector<std::string_view> driveable;
      for (std::size_t j = 0; j < spec.joints.size(); ++j) {
        if (spec.joints[j].name == jname) joint = static_cast<int>(j);
        if (!spec.joints[j].type->coordinates.empty()) driveable.push_back(spec.joints[j].name);
      }
      if (joint < 0) {
        std::string msg = fmt::format("'{}' = \"{}\" is not a joint of this scene", key("joint"), printable(jname));
        if (auto best = closest(jname, driveable)) msg += fmt::format("; did you mean \"{}\"?", *best);
        msg += driveable.empty() ? std::string(" (no joint here has a coordinate to drive)")
                                 : fmt::format(" (joints with coordinates: {})", quoted_list(driveable));
        r_.fail(jn, msg);
      }
      const JointSpec& js = spec.joints[static_cast<std::size_t>(joint)];
      const auto coords = js.type->coordinates;
      if (coords.empty())
        r_.fail(jn, fmt::format("joint \"{}\" is a {} joint, which has no coordinate to drive (drivable types: "
                                "revolute, prismatic, cylindrical, universal)",
                                printable(jname), js.type->name));
      std::vector<std::string_view> names;
      for (const JointCoordinate& c : coords) names.push_back(c.name);
      if (const toml::node* cn = t.get("coordinate")) {
        d.coordinate = static_cast<int>(r_.choice(*cn, key("coordinate"), names));
      } else if (coords.size() > 1) {
        r_.fail(t.source(), fmt::format("{} drives joint \"{}\", a {} joint with {} coordinates: say which with "
                                        "'coordinate' (valid: {})",
                                        prefix, printable(jname), js.type->name, coords.size(), quoted_list(names)));
      }
      for (const DriverSpec& other : spec.drivers)
        if (other.joint == joint && other.coordinate == d.coordinate)
          r_.fail(jn, fmt::format("joint \"{}\"'s {} is driven twice (also at line {}): one driver per coordinate",
                                  printable(jname), names[static_cast<std::size_t>(d.coordinate)], other.where.line));
      d.joint = joint;
      const bool angle = coords[static_cast<std::size_t>(d.coordinate)].kind == CoordinateKind::Angle;
      const toml::node& mn = r_.required(t, "drivers", "motion",
                                         "the coordinate as a function of time, e.g. { type = \"rate\", rate = 6.283 }");
      d.motion = read_time_function(r_, mn, key("motion"),
                                    angle ? "the joint angle, rad" : "the joint displacement, m", true);
      spec.drivers.push_back(std::move(d));
    }
  }

  // [[markers]]: name, body, point (space at the initial pose, or frame = "body").
  void read_markers(MultibodySpec& spec) {
    const auto list = tables("markers", false, "marker");
    for (std::size_t i = 0; i < list.size(); ++i) {
      const toml::table& t = *list[i];
      const std::string prefix = item("markers", i);
      const auto key = [&](std::string_view k) { return join_key(prefix, k); };
      r_.check_keys(t, "markers", kMarkerKeys, sections());
      MarkerSpec mk;
      mk.where = where(t);
      const toml::node& name_node = r_.required(t, "markers", "name", "a name such as \"tip\" (it names the columns)");
      mk.name = r_.string(name_node, key("name"));
      check_part_name(r_, name_node, key("name"), mk.name);
      claim_name(&name_node, t, "marker", mk.name);
      mk.body = body_index(r_.required(t, "markers", "body", "the name of the body it is fixed in"), key("body"), false);
      bool body_frame = false;
      if (const toml::node* f = t.get("frame")) body_frame = r_.choice(*f, key("frame"), kFrames) == 1;
      const Pose p = pose(mk.body);
      if (const toml::node* n = t.get("point")) {
        const Vec3 v = bounded_vec3(r_, *n, key("point"), kMaxLength, "m");
        mk.point = body_frame ? v : Vec3(p.R.transpose() * (v - p.x));
        if (is_particle(mk.body) && mk.point.norm() > 1e-9 * std::max(1.0, p.x.norm()))
          r_.fail(*n, fmt::format("marker \"{}\" is on {}, a particle, {:.6g} m away from it: a point mass has no "
                                  "extent (leave 'point' out: the marker is the particle's position)",
                                  mk.name, body_label(mk.body), mk.point.norm()));
      } else if (!is_particle(mk.body)) {
        r_.required(t, "markers", "point",
                    "[x, y, z] in m: the point, in space at the initial pose (or frame = \"body\": in the body's frame)");
      }
      spec.markers.push_back(mk);
    }
  }

  void read_reference(Scene& scene) const {
    const toml::node* n = root_.get("reference");
    if (!n) return;
    read_top_level_settings(r_, root_, scene);
    if (scene.reference == ReferenceKind::Exact)
      r_.fail(*n, "'reference' = \"exact\" but a scene of bodies and joints has no closed-form solution (use "
                  "\"auto\" or \"tight\" for a tight run)");
  }
};

}  // namespace

Scene read_multibody_scene(const TomlReader& r, const toml::table& root) { return MultibodyReader(r, root).read(); }

}  // namespace rigidae::io::detail
