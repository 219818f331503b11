// Revolute joint (hinge): the points coincide and the axes stay parallel.
//   rows      p_a - p_b = 0 (x, y, z); z_a . n_b = 0, z_a . (z_b x n_b) = 0   5
//   freedoms  1 rotation (about z), no translation
//   reaction  force on b at its joint point (the point rows, N) and the
//             torque on b normal to the axis (the axis rows: lambda (z_a x d_b), N m)
//   coordinate "angle" (rad): the rotation of b relative to a about z, from
//             n_a to n_b, right-handed: C = n_a . n_b, S = (z_a x n_a) . n_b,
//             theta = atan2(S, C); zero at the initial pose unless the scene
//             gives both normals (frame = "body"): then their angle there
// It carries a torsional spring-damper and a motor (src/multibody/
// force_elements/torsion_spring.cpp) under the keys stiffness, damping,
// rest_angle, motor_torque, motor_profile.
#include <array>

#include "primitives.hpp"
#include "rigidae/model/joint_type.hpp"

namespace rigidae {

namespace {
constexpr std::array<std::string_view, 5> kTorsionKeys{"stiffness", "damping", "rest_angle", "motor_torque",
                                                      "motor_profile"};

constexpr JointCoordinate kCoordinates[] = {{"angle", CoordinateKind::Angle, joint_rows::turn_about_axis}};

void rows(const JointSpec& j, std::vector<ConstraintRow>& out) {
  joint_rows::coincident_points(j, out);
  joint_rows::parallel_axes(j, out);
}
}  // namespace

const JointType& revolute_joint() {
  static const JointType type{
      .name = "revolute",
      .description = "a hinge: the points coincide, one rotation about the axis",
      .axes = JointAxes::Axis,
      .freedoms = {1, 0},
      .force_keys = kTorsionKeys,
      .rows = rows,
      .reaction = "force on b at the joint point (N) and torque on b normal to the axis (N m)",
      .coordinates = kCoordinates,
  };
  return type;
}

}  // namespace rigidae
