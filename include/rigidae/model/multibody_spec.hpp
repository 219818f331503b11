#pragma once
// A validated multibody scene (schema_version 2): rigid bodies in absolute
// coordinates joined by joints, with forces. Plain, immutable data.
//
// Produced by the schema-2 scene loader (io/), which checks every value and
// reports file:line:col; consumed by the multibody assembler (multibody/).
//
// Conventions (SI units, radians):
//   - each body's frame B has its origin at the body's centre of mass;
//   - R_WB maps body components to space (world) components;
//   - every joint point and axis here is in the frame of the body it belongs
//     to (from that body's centre of mass); for the ground they are in space.
//     The loader converts what the user writes (space frame at the initial
//     pose, by default) into these body-frame values;
//   - axes are unit vectors.
#include <optional>
#include <string>
#include <vector>

#include "rigidae/core/types.hpp"
#include "rigidae/model/constraint_row.hpp"
#include "rigidae/model/coordinates.hpp"
#include "rigidae/model/joint_type.hpp"
#include "rigidae/model/time_function.hpp"
#include "rigidae/model/visual_shape.hpp"

namespace rigidae {

// Where a definition sits in the scene file, for messages raised after loading
// (e.g. redundant constraint rows found at the start).
struct SourcePosition {
  std::string file;
  int line = 0, column = 0;
};

struct BodySpec {
  std::string name;
  // A point mass ([[bodies]] kind = "particle"): mass and position only, no
  // rotation coordinates; inertia_com is zero, R0_WB the identity, omega0_B
  // zero (multibody/point_mass.hpp).
  bool particle = false;
  double mass = 1.0;                    // kg, > 0
  Mat3 inertia_com = Mat3::Identity();  // kg m^2 about the centre of mass, body axes, SPD (zero for a particle)
  // Initial state.
  Vec3 x0_W = Vec3::Zero();        // m, centre of mass in space
  Mat3 R0_WB = Mat3::Identity();   // an exact rotation after loading
  Vec3 v0_W = Vec3::Zero();        // m/s, centre-of-mass velocity in space
  Vec3 omega0_B = Vec3::Zero();    // rad/s, angular velocity in body components
  // Held at a fixed point (scene key `pivot`, m, space): the body only turns
  // about it, its unknowns are its rotation coordinates and velocities (the
  // one-body model of a top), and the support force is reported. Set: x0_W
  // stays the centre of mass (its distance from the pivot is fixed) and
  // v0_W = omega x (x0_W - pivot_W).
  std::optional<Vec3> pivot_W;
  // With a pivot: the pivot -> centre of mass vector in the body frame (m);
  // unset: R0_WB^T (x0_W - pivot_W). A one-body scene sets it to its
  // center_of_mass exactly (model/one_body_system.hpp), so the rotation block
  // is the one-body model's bit for bit.
  std::optional<Vec3> com_from_pivot_B;
  // Per-body override of the scene's coordinates (unset: the formulation's).
  std::optional<Coordinates> coordinates;
  std::vector<VisualShape> visuals;  // how to draw it (none: its inertia ellipsoid); body frame
  SourcePosition where;
};

// A joint's range of motion as a URDF states it (<limit>): kept as data and
// written to exported models, NOT enforced by the solver (no contact or
// stop rows exist); summary.json says so. Units: rad or m, N m or N, rad/s
// or m/s.
struct JointLimits {
  std::optional<double> lower, upper;  // unset: unbounded (a continuous joint)
  std::optional<double> effort, velocity;
};

struct JointSpec {
  std::string name;
  const JointType* type = nullptr;  // the registry's (model/joint_type.hpp); set by the loader
  int body_a = kGround, body_b = kGround;  // indices into bodies, or kGround
  // The joint point on each body (body frame, from its centre of mass).
  Vec3 point_a = Vec3::Zero(), point_b = Vec3::Zero();
  // The joint axis on each body (body frame, unit): the hinge axis (revolute),
  // the sliding axis (prismatic, cylindrical). Universal: axis_a is the
  // cross-pin axis fixed in a, axis_b the one fixed in b (perpendicular).
  Vec3 axis_a = Vec3::UnitZ(), axis_b = Vec3::UnitZ();
  // A direction on each body normal to the axis, perpendicular to it, used by
  // prismatic and fixed joints to stop the rotation about the axis, and as the
  // zero of a revolute joint's angle (unit, normal_a . axis_a = 0).
  Vec3 normal_a = Vec3::UnitX(), normal_b = Vec3::UnitX();
  // A distance joint's rod length |p_b - p_a| (m, > 0); the loader's default
  // is the distance at the initial pose.
  double length = 0.0;
  // Torsional spring-damper in a revolute joint: torque -k (theta - theta0) - c theta'.
  double torsion_stiffness = 0.0;  // N m / rad
  double torsion_damping = 0.0;    // N m s / rad
  double torsion_rest_angle = 0.0; // rad
  // A motor in a revolute joint: the torque motor_torque s(t) on b about the
  // axis in the angle's positive sense (and its opposite on a), s the
  // profile (unset: 1).
  double motor_torque = 0.0;              // N m
  // A linear motor in a prismatic joint: the force motor_force s(t) on b
  // along the axis (and its opposite on a).
  double motor_force = 0.0;               // N
  std::optional<TimeFunction> motor_profile;  // s(t) of either motor
  std::optional<JointLimits> limits;  // data only (URDF), never enforced
  SourcePosition where;
};

// A linear spring-damper between two body points: force along the line,
// k (|d| - L0) + c d/dt|d|.
struct SpringSpec {
  std::string name;
  int body_a = kGround, body_b = kGround;
  Vec3 point_a = Vec3::Zero(), point_b = Vec3::Zero();  // body frames (space for the ground)
  double stiffness = 0.0;    // N/m
  double damping = 0.0;      // N s/m
  double rest_length = 0.0;  // m
  SourcePosition where;
};

// A force (at the centre of mass) and torque on one body: constant, or
// scaled by a function of time (force(t) = profile(t) force, the same for the
// torque; scene key `profile`).
struct BodyLoadSpec {
  int body = 0;
  Vec3 force = Vec3::Zero();   // N
  Vec3 torque = Vec3::Zero();  // N m
  bool body_frame = false;     // components in the body frame (rotating with it), else space
  std::optional<TimeFunction> profile;  // unset: constant
  SourcePosition where;
};

// A driver ([[drivers]]): a joint coordinate prescribed as a function of
// time, a rheonomic constraint row (multibody/driver_rows.hpp) whose
// multiplier gives the driving torque (an angle) or force (a length).
struct DriverSpec {
  int joint = 0;       // index into joints
  int coordinate = 0;  // index into the joint type's coordinates
  TimeFunction motion;  // rad or m
  SourcePosition where;
};

// A marker ([[markers]]): a named point fixed in a body, whose position,
// velocity and acceleration in space are output columns MARKER.x..z,
// MARKER.vx..vz, MARKER.ax..az (issue 22 item 5).
struct MarkerSpec {
  std::string name;
  int body = 0;                // index into bodies (never the ground)
  Vec3 point = Vec3::Zero();   // body frame, from the centre of mass (zero on a particle)
  SourcePosition where;
};

// An assembled start ([mechanism] assemble / hold): the bodies' initial poses
// and velocities are guesses that the start moves onto the joints, keeping the
// held bodies' as given (multibody/assembly.hpp).
struct AssemblySpec {
  bool requested = false;
  std::vector<int> held;  // indices into bodies, in the scene's order
  SourcePosition where;   // the [mechanism] key that asked for it
};

struct MultibodySpec {
  std::vector<BodySpec> bodies;
  std::vector<JointSpec> joints;
  std::vector<SpringSpec> springs;
  std::vector<BodyLoadSpec> loads;
  std::vector<DriverSpec> drivers;
  std::vector<MarkerSpec> markers;
  Vec3 gravity_W = Vec3(0, 0, -9.81);  // m/s^2
  // Largest position-level joint miss at the start that is projected (with a
  // warning) rather than refused; larger misses are an error naming the joint.
  double start_tolerance = 1e-6;  // m (and rad for angular rows)
  // [output] bodies / joints: the parts whose columns are recorded (indices
  // into bodies / joints, in the scene's order); unset: the default
  // (model/recorded_parts.hpp).
  std::optional<std::vector<int>> output_bodies, output_joints;
  // The mobility the author expects (scene key expected_dof, top level or
  // [mechanism]); a start whose rank mobility differs warns.
  std::optional<int> expected_dof;
  SourcePosition expected_dof_where;
  AssemblySpec assembly;
  // [mechanism] singular_poses: "bridge" (true, the default) crosses a pose
  // where the rows lose rank by extrapolation and projection onto the
  // branch arrived on; "integrate" leaves it to the integrator
  // (multibody/pose_bridge.cpp).
  bool bridge_singular_poses = true;
  // Set by one_body_system(): the system is a one-body scene, whose records
  // keep the single-body files' columns (record/run_columns.hpp).
  bool one_body_scene = false;
};

}  // namespace rigidae
