// Spherical joint (ball joint): the joint points of a and b coincide.
//   rows      p_a - p_b = 0 (x, y, z)                               3
//   freedoms  3 rotations, no translation
//   reaction  the rows' multipliers are the force on b at its joint point,
//             in space (N); no torque
#include "primitives.hpp"
#include "rigidae/model/joint_type.hpp"

namespace rigidae {

namespace {
void rows(const JointSpec& j, std::vector<ConstraintRow>& out) { joint_rows::coincident_points(j, out); }
}  // namespace

const JointType& spherical_joint() {
  static const JointType type{
      .name = "spherical",
      .description = "a ball joint: the points coincide, every rotation free",
      .axes = JointAxes::Point,
      .freedoms = {3, 0},
      .force_keys = {},
      .rows = rows,
      .reaction = "force on b at the joint point (N); no torque",
  };
  return type;
}

}  // namespace rigidae
