// A body's optional `visual` shapes (schema 1: [body]; schema 2: each
// [[bodies]] entry): what the viewer, the ParaView files and the animations
// draw. They carry no mass. One shape is an inline table or a table; several
// are an array of tables ([[bodies.visual]] after the body's [[bodies]]).
//   shape = "box"      size = [lx, ly, lz]      edge lengths, m
//   shape = "sphere"   radius
//   shape = "cylinder" radius, length           axis z of the shape
//   shape = "capsule"  radius, length           the cylinder's length; a
//                                               hemisphere at each end
// and, for any shape, `position` (m, body frame, from the body origin) and
// either `quaternion` (w, x, y, z: R_BV, the shape's axes in the body frame)
// or, for a cylinder or capsule, `axis` (its z axis in the body frame).
#include <fmt/format.h>

#include <array>
#include <cmath>

#include "rigidae/so3/rotation.hpp"
#include "scene_sections.hpp"

namespace rigidae::io::detail {

namespace {

constexpr std::array<std::string_view, 4> kShapes{"box", "cylinder", "sphere", "capsule"};
constexpr std::array<VisualKind, 4> kShapeKinds{VisualKind::Box, VisualKind::Cylinder, VisualKind::Sphere,
                                                VisualKind::Capsule};
constexpr double kMaxSize = 1e6;      // m, as positions
constexpr double kUnitTolerance = 1e-6;  // |q| - 1 accepted (and normalised)

// The keys each shape takes besides position and orientation.
bool takes(VisualKind k, std::string_view key) {
  if (key == "size") return k == VisualKind::Box;
  if (key == "radius") return k != VisualKind::Box;
  if (key == "length" || key == "axis") return k == VisualKind::Cylinder || k == VisualKind::Capsule;
  return true;
}

std::string_view needs(VisualKind k) {
  switch (k) {
    case VisualKind::Box: return "'size' = [lx, ly, lz] (edge lengths, m)";
    case VisualKind::Sphere: return "'radius' (m)";
    case VisualKind::Cylinder:
    case VisualKind::Capsule: return "'radius' and 'length' (m; the axis is the shape's z)";
  }
  return "";
}

double positive_length(const TomlReader& r, const toml::node& n, const std::string& name) {
  const double v = r.number(n, name);
  if (!(v > 0.0 && v <= kMaxSize))
    r.fail(n, fmt::format("'{}' = {} m must be > 0 and at most {:g} m", name, v, kMaxSize));
  return v;
}

VisualShape read_one(const TomlReader& r, const toml::table& t, std::string_view table, const std::string& name,
                     std::span<const SectionKeys> schema) {
  r.check_keys(t, table, kVisualKeys, schema);
  const auto key = [&](std::string_view k) { return fmt::format("{}.{}", name, k); };
  VisualShape v;
  const toml::node& shape = r.required(t, table, "shape", "\"box\", \"cylinder\", \"sphere\" or \"capsule\"");
  v.kind = kShapeKinds[r.choice(shape, key("shape"), kShapes)];
  for (std::string_view k : kVisualKeys)
    if (const toml::node* n = t.get(k); n && !takes(v.kind, k))
      r.fail(*n, fmt::format("'{}' does not apply to a {} (it takes {}, and 'position', 'quaternion'{})", key(k),
                             visual_kind_name(v.kind), needs(v.kind),
                             takes(v.kind, "axis") ? " or 'axis'" : ""));
  const auto required = [&](std::string_view k) -> const toml::node& {
    const toml::node* n = t.get(k);
    if (!n)
      r.fail(t.source(), fmt::format("missing required key '{}' in '{}': a {} needs {}", k, name,
                                     visual_kind_name(v.kind), needs(v.kind)));
    return *n;
  };
  if (v.kind == VisualKind::Box) {
    const toml::node& n = required("size");
    const Vec3 s = r.vec3(n, key("size"));
    for (int i = 0; i < 3; ++i)
      if (!(s[i] > 0.0 && s[i] <= kMaxSize))
        r.fail(n, fmt::format("'{}[{}]' = {} m must be > 0 and at most {:g} m (the box's edge lengths)", key("size"),
                              i, s[i], kMaxSize));
    v.size = s;
  } else {
    v.radius = positive_length(r, required("radius"), key("radius"));
    if (v.kind != VisualKind::Sphere) v.length = positive_length(r, required("length"), key("length"));
  }
  if (const toml::node* p = t.get("position")) {
    v.position_B = r.vec3(*p, key("position"));
    if (v.position_B.norm() > kMaxSize)
      r.fail(*p, fmt::format("|{}| = {:g} m must be at most {:g} m", key("position"), v.position_B.norm(), kMaxSize));
  }
  const toml::node* q = t.get("quaternion");
  const toml::node* axis = t.get("axis");
  if (q && axis)
    r.fail(*axis, fmt::format("give '{}' or '{}', not both: both set the shape's orientation", key("quaternion"),
                              key("axis")));
  if (q) {
    const Vec4 qv = r.vector<4>(*q, key("quaternion"));
    const double n = qv.norm();
    if (std::abs(n - 1.0) > kUnitTolerance)
      r.fail(*q, fmt::format("'{}' has norm {:.9g}; give a unit quaternion (w, x, y, z), scalar first, e.g. "
                             "[1.0, 0.0, 0.0, 0.0] for the body's own axes",
                             key("quaternion"), n));
    v.R_BV = so3::quaternion_to_matrix(qv / n);
  }
  if (axis) {
    const Vec3 a = r.vec3(*axis, key("axis"));
    if (!(a.norm() > 0.0)) r.fail(*axis, fmt::format("'{}' is zero; give the direction of the shape's axis", key("axis")));
    // The shortest rotation taking z_V onto the axis (any will do: the shape
    // is round about it).
    v.R_BV = Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), a.normalized()).toRotationMatrix();
  }
  return v;
}

}  // namespace

std::vector<VisualShape> read_visuals(const TomlReader& r, const toml::table& body, std::string_view table,
                                      std::string_view prefix, std::span<const SectionKeys> schema) {
  std::vector<VisualShape> shapes;
  const toml::node* n = body.get("visual");
  if (!n) return shapes;
  const std::string name = fmt::format("{}.visual", prefix);
  const std::string vtable = fmt::format("{}.visual", table);
  if (const toml::table* t = n->as_table()) {
    shapes.push_back(read_one(r, *t, vtable, name, schema));
    return shapes;
  }
  const toml::array* a = n->as_array();
  if (!a || a->empty())
    r.fail(*n, fmt::format("'{}' must be a table {{ shape = \"box\", size = [...] }} or an array of them "
                           "([[{}]] entries), not {}",
                           name, vtable, a ? "an empty array" : type_name(*n)));
  for (std::size_t i = 0; i < a->size(); ++i) {
    const toml::table* t = a->get(i)->as_table();
    const std::string item = fmt::format("{}[{}]", name, i);
    if (!t) r.fail(*a->get(i), fmt::format("'{}' must be a table {{ shape = ..., ... }}, not {}", item, type_name(*a->get(i))));
    shapes.push_back(read_one(r, *t, vtable, item, schema));
  }
  return shapes;
}

}  // namespace rigidae::io::detail
