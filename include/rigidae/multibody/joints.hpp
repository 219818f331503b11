#pragma once
// Joints as short lists of primitive rows (multibody.md, "Joints as short
// lists of primitives"), on bodies a and b with points p, axes z and normals
// n given in each body's frame (JointSpec):
//   spherical   coincident points                                     3
//   universal   coincident points + z_a . z_b = 0                      4
//   revolute    coincident points + z_a . n_b = 0, z_a . (z_b x n_b) = 0  5
//   cylindrical point p_b on the line (p_a, z_a) + the two axis rows   4
//   prismatic   cylindrical + n_a . (z_b x n_b) = 0 (no turn about z)   5
//   fixed       coincident points + the two axis rows + n_a . (z_b x n_b) = 0  6
// Point on a line: (p_b - p_a) . n_a = 0 and (p_b - p_a) . (z_a x n_a) = 0.
// Coincident points: p_a - p_b = 0, so the multipliers of those rows are the
// force the joint exerts on body b (N); a perpendicular pair's multiplier is
// the torque (N m) on b about d_a x d_b.
#include <vector>

#include "rigidae/model/multibody_spec.hpp"
#include "rigidae/multibody/constraint_rows.hpp"

namespace rigidae::multibody {

// The rows of a joint (at most kMaxBlockRows).
std::vector<ConstraintRow> joint_rows(const JointSpec& joint);

// Name of a joint type, as a scene writes it.
const char* joint_type_name(JointType type);

}  // namespace rigidae::multibody
