// Prismatic joint (slider): a cylindrical joint that does not turn.
//   rows      (p_b - p_a) . n_a = 0, (p_b - p_a) . (z_a x n_a) = 0;
//             z_a . n_b = 0, z_a . (z_b x n_b) = 0; n_a . (z_b x n_b) = 0   5
//   freedoms  1 translation along z
//   coordinate "displacement" (m): d = (p_b - p_a) . z_a, b's joint point
//             along the axis from a's; zero at the initial pose with
//             frame = "space" (one point), else where the points coincide
//   reaction  force on b normal to the axis (N) and the full torque on b (N m)
// It carries a linear motor (src/multibody/force_elements/joint_force.cpp)
// under the keys motor_force, motor_profile.
#include <array>

#include "primitives.hpp"
#include "rigidae/model/joint_type.hpp"

namespace rigidae {

namespace {
constexpr std::array<std::string_view, 2> kMotorKeys{"motor_force", "motor_profile"};

constexpr JointCoordinate kCoordinates[] = {{"displacement", CoordinateKind::Length, joint_rows::slide_along_axis}};

void rows(const JointSpec& j, std::vector<ConstraintRow>& out) {
  joint_rows::point_on_line(j, out);
  joint_rows::parallel_axes(j, out);
  joint_rows::no_turn(j, out);
}
}  // namespace

const JointType& prismatic_joint() {
  static const JointType type{
      .name = "prismatic",
      .description = "a slider: slides along the axis without turning",
      .axes = JointAxes::Axis,
      .freedoms = {0, 1},
      .force_keys = kMotorKeys,
      .rows = rows,
      .reaction = "force on b normal to the axis (N) and torque on b (N m)",
      .coordinates = kCoordinates,
  };
  return type;
}

}  // namespace rigidae
