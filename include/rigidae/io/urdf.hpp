#pragma once
// URDF robot descriptions as rigidae scenes (docs/scene_format.md, "URDF").
//
// Three steps, each its own file:
//   src/io/urdf_reader.cpp  XML text -> UrdfModel: links and joints as the file
//                           states them, every value checked, with its line;
//   src/io/urdf_tree.cpp    UrdfModel + initial joint state -> MultibodySpec:
//                           the tree, the ground, links merged into bodies,
//                           forward kinematics of the initial pose and rates;
//   src/io/urdf_scene.cpp   a `.urdf` path (default run settings) or a TOML
//                           scene with a [urdf] table (file, base, initial
//                           joint positions and rates, plus [time], [solver]...).
//
// URDF conventions used (ROS's URDF specification):
//   - <origin xyz rpy>: a frame's pose in its parent frame; rpy = fixed-axis
//     roll about x, pitch about y, yaw about z: R = Rz(yaw) Ry(pitch) Rx(roll);
//   - a joint's frame is its <origin> in the parent link's frame; the child
//     link's frame is the joint frame at joint position 0, then turned by q
//     about <axis> (revolute, continuous) or moved by q along it (prismatic);
//     <axis> is in the joint frame, default (1, 0, 0);
//   - <inertial><origin>: the centre of mass and the axes of <inertia>
//     (ixx .. izz about the centre of mass) in the link's frame.
#include <optional>
#include <string>
#include <vector>

#include "rigidae/core/types.hpp"
#include "rigidae/model/multibody_spec.hpp"
#include "rigidae/model/scene.hpp"

namespace rigidae::io {

// A rigid transform: p_parent = R p_child + t.
struct UrdfFrame {
  Mat3 R = Mat3::Identity();
  Vec3 t = Vec3::Zero();
};

struct UrdfInertial {
  UrdfFrame origin;          // centre of mass and inertia axes in the link frame
  double mass = 0.0;         // kg, >= 0
  Mat3 inertia = Mat3::Zero();  // kg m^2 about the centre of mass, in origin's axes
  int line = 0;
};

struct UrdfLink {
  std::string name;
  std::optional<UrdfInertial> inertial;  // unset: massless (merged, or refused if it moves)
  int line = 0;
};

enum class UrdfJointType { Revolute, Continuous, Prismatic, Fixed, Floating };

struct UrdfJoint {
  std::string name;
  UrdfJointType type = UrdfJointType::Fixed;
  std::string parent, child;  // link names
  UrdfFrame origin;           // joint frame in the parent link's frame
  Vec3 axis = Vec3::UnitX();  // unit, joint frame
  std::optional<JointLimits> limits;
  double damping = 0.0;       // <dynamics damping>: N m s/rad (revolute, continuous)
  int line = 0;
};

struct UrdfModel {
  std::string source;  // the file, for messages
  std::string name;    // <robot name>
  std::vector<UrdfLink> links;
  std::vector<UrdfJoint> joints;
};

// Parses URDF text. Throws InputError "FILE:LINE: error: <element name=...>:
// what is wrong and what would be valid".
UrdfModel parse_urdf(const std::string& text, const std::string& source_name);

// How the root link is held when the file has no `world` link.
enum class UrdfBase { Fixed, Floating };

// The initial joint state, by URDF joint name (rad or m; rad/s or m/s).
struct UrdfJointState {
  std::string joint;
  double value = 0.0;
  std::string where;  // "FILE:LINE:COL" of the value, for messages ("" if none)
};

struct UrdfOptions {
  std::optional<UrdfBase> base;  // unset: Fixed (a `world` link decides by itself)
  std::string base_where;        // where `base` was given, for messages
  std::vector<UrdfJointState> positions, velocities;
};

// The mechanism the URDF describes (see urdf_tree.cpp for the rules: what is
// the ground, which links merge into which body, which are refused).
MultibodySpec urdf_to_multibody(const UrdfModel& model, const UrdfOptions& options);

// One rigid part of a merged body: its mass, centre of mass and inertia
// about that centre (in `frame`'s axes), placed by `frame` in the body's
// reference frame (the top link's frame).
struct MassPart {
  double mass = 0.0;
  Vec3 com = Vec3::Zero();      // in the reference frame
  Mat3 inertia = Mat3::Zero();  // about com, reference-frame axes
};
// The parts as one rigid body: total mass, centre of mass, and inertia about
// that centre by the parallel-axis theorem:
//   m = sum m_i,  c = sum m_i c_i / m,
//   I = sum [ I_i + m_i ( |d_i|^2 E - d_i d_i^T ) ],  d_i = c_i - c.
// A total mass of zero gives c = 0 and I = 0.
MassPart combine_mass_parts(const std::vector<MassPart>& parts);

// `rigidae solve arm.urdf`: the URDF as a scene with the default run settings
// (Scene{}'s: 0 to 1 s, output every 0.01 s, the default formulation and
// solver), the root link fixed unless a `world` link says otherwise.
Scene load_urdf_scene(const std::string& path);

}  // namespace rigidae::io
