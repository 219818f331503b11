// Cylindrical joint: b's point stays on the line (p_a, z_a) and the axes stay
// parallel; b turns about and slides along the axis.
//   rows      (p_b - p_a) . n_a = 0, (p_b - p_a) . (z_a x n_a) = 0;
//             z_a . n_b = 0, z_a . (z_b x n_b) = 0                     4
//   freedoms  1 rotation, 1 translation (both along z)
//   coordinates "angle" (rad) about z as a revolute joint's, and
//             "displacement" (m) along z as a prismatic joint's
//   reaction  force on b normal to the axis at b's joint point (N) and
//             torque on b normal to the axis (N m)
#include "primitives.hpp"
#include "rigidae/model/joint_type.hpp"

namespace rigidae {

namespace {
constexpr JointCoordinate kCoordinates[] = {
    {"angle", CoordinateKind::Angle, joint_rows::turn_about_axis},
    {"displacement", CoordinateKind::Length, joint_rows::slide_along_axis},
};

void rows(const JointSpec& j, std::vector<ConstraintRow>& out) {
  joint_rows::point_on_line(j, out);
  joint_rows::parallel_axes(j, out);
}
}  // namespace

const JointType& cylindrical_joint() {
  static const JointType type{
      .name = "cylindrical",
      .description = "a sleeve on a rod: turns about and slides along the axis",
      .axes = JointAxes::Axis,
      .freedoms = {1, 1},
      .force_keys = {},
      .rows = rows,
      .reaction = "force on b normal to the axis (N) and torque on b normal to the axis (N m)",
      .coordinates = kCoordinates,
  };
  return type;
}

}  // namespace rigidae
