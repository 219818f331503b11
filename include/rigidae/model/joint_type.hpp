#pragma once
// Joint types: each one file under src/model/joint_types/ stating what the
// rest of rigidae needs to know about it, and one registry table
// (src/model/joint_types/registry.cpp) that the scene loader, the
// assembler, the rank check and the mobility count, and the reports consult.
// Nothing else lists the joint types.
//
// A joint type states
//   - its name, as scenes write it (`type = "revolute"`);
//   - the geometry keys it needs (`JointAxes`: a point only, a point and an
//     axis, or a point and two perpendicular pins), and the keys of the
//     force elements it can carry (a revolute joint's torsional spring);
//   - its rows: dot products of body vectors (model/constraint_row.hpp),
//     built from the primitives of src/model/joint_types/primitives.hpp
//     (coincident points, point on a line, perpendicular directions); every
//     row is a constraint held by a force, so the multipliers are its
//     reaction, reported through each row's RowReaction;
//   - its freedoms: the relative rotations and translations it allows
//     (the Gruebler-Kutzbach count 6 n - sum (6 - freedoms)); a type has
//     exactly 6 - freedoms rows (checked by tests/unit/test_joint_types.cpp);
//   - its coordinates (issue 22 item 5): angles and displacements of b
//     relative to a, each as dot-product rows the assembler evaluates.
// The multibody module evaluates rows and coordinates; it never asks which
// type a joint is.
#include <span>
#include <string_view>
#include <vector>

#include "rigidae/model/constraint_row.hpp"

namespace rigidae {

struct JointSpec;

// The geometry a scene gives for a joint, beside its point (docs/scene_format.md):
//   Point      nothing else (spherical, fixed: the initial relative pose is kept)
//   Axis       one axis, fixed in both bodies (`axis`, or `axis_a`, `axis_b`
//              with frame = "body"), and optionally `normal_a`, `normal_b`
//   CrossPins  two perpendicular pins, `axis_a` fixed in a and `axis_b` in b
//   TwoPoints  two points, `point_a` on a and `point_b` on b (in space at the
//              initial pose, or in the bodies' frames), and a `length`
//              (distance: a rod between them)
enum class JointAxes { Point, Axis, CrossPins, TwoPoints };

struct JointFreedoms {
  int rotational = 0, translational = 0;
  int total() const { return rotational + translational; }
};

// A coordinate of b's motion relative to a (issue 22 item 5), from rows the
// assembler evaluates like constraint rows (values, G v):
//   Angle   theta = atan2(S, C) from the rows {C, S} (C = r cos theta,
//           S = r sin theta); reported unwrapped, counting whole turns: the
//           branch follows the motion from one accepted step to the next;
//           rate theta' = (C S' - S C') / (C^2 + S^2)
//   Length  d = the row's value {d}, rate d' = G v
// Zero where the type's file says (revolute: normal_b along normal_a). A
// torsional spring acts on a type's first angle; a driver (prescribed
// motion) would be a rheonomic row on one: Length d - f(t) = 0, Angle
// -sin f(t) C + cos f(t) S = 0 (= r sin(theta - f)), its multiplier the
// driving force or torque.
enum class CoordinateKind { Angle, Length };
inline constexpr int kMaxJointCoordinates = 2;  // per type (tests/unit/test_joint_types.cpp)
struct JointCoordinate {
  std::string_view name;  // the column JOINT.<name> (and JOINT.<name>_rate)
  CoordinateKind kind = CoordinateKind::Angle;
  // Writes the rows: {C, S} for an angle, {d} for a length.
  void (*rows)(const JointSpec& joint, ConstraintRow out[2]) = nullptr;
  int row_count() const { return kind == CoordinateKind::Angle ? 2 : 1; }
};

struct JointType {
  std::string_view name;         // as scenes write it
  std::string_view description;  // one phrase, for messages and docs
  JointAxes axes = JointAxes::Point;
  JointFreedoms freedoms;
  // Keys of the force elements this type carries in its [[joints]] table
  // (a revolute joint's torsional spring: stiffness, damping, rest_angle).
  std::span<const std::string_view> force_keys;
  // Appends the joint's 6 - freedoms.total() constraint rows.
  void (*rows)(const JointSpec& joint, std::vector<ConstraintRow>& out) = nullptr;
  // How the multipliers read as the reaction on body b (docs and --help).
  std::string_view reaction;
  // Its coordinates (none for spherical and fixed joints).
  std::span<const JointCoordinate> coordinates;
};

// The registry, in the order of docs/scene_format.md.
const std::vector<const JointType*>& joint_types();
std::vector<std::string_view> joint_type_names();
// nullptr for an unknown name.
const JointType* find_joint_type(std::string_view name);
// Throws std::invalid_argument for an unknown name (code and tests that name a type on purpose).
const JointType& joint_type(std::string_view name);

}  // namespace rigidae
