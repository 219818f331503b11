// Universal joint (Hooke's joint): the points coincide and the pin z_a fixed
// in a stays perpendicular to the pin z_b fixed in b.
//   rows      p_a - p_b = 0 (x, y, z); z_a . z_b = 0 ("cross")       4
//   freedoms  2 rotations (about each pin), no translation
//   coordinates "angle_a" (rad): the turn of the cross about z_a relative
//             to a, from n_a to z_b: C = n_a . z_b, S = (z_a x n_a) . z_b;
//             "angle_b" (rad): the turn of b about z_b relative to the cross,
//             measured as minus the angle of z_a seen from b, from n_b about
//             z_b: C = n_b . z_a, S = (n_b x z_b) . z_a. The loader sets
//             n_a = z_b and n_b = z_a at the initial pose: both zero there
//   reaction  force on b at the joint point (N) and the torque
//             lambda (z_a x z_b) on b (N m)
#include "primitives.hpp"
#include "rigidae/model/joint_type.hpp"

namespace rigidae {

namespace {
void cross_angle(const JointSpec& j, ConstraintRow out[2]) {
  joint_rows::angle_of(j.body_a, j.axis_a, j.normal_a, j.body_b, j.axis_b, out);
}
// The angle of z_a about -z_b from n_b, seen from b: S = (-z_b x n_b) . z_a.
void body_angle(const JointSpec& j, ConstraintRow out[2]) {
  joint_rows::angle_of(j.body_b, Vec3(-j.axis_b), j.normal_b, j.body_a, j.axis_a, out);
}
constexpr JointCoordinate kCoordinates[] = {
    {"angle_a", CoordinateKind::Angle, cross_angle},
    {"angle_b", CoordinateKind::Angle, body_angle},
};

void rows(const JointSpec& j, std::vector<ConstraintRow>& out) {
  joint_rows::coincident_points(j, out);
  joint_rows::perpendicular("cross", j.body_a, j.axis_a, j.body_b, j.axis_b, out);
}
}  // namespace

const JointType& universal_joint() {
  static const JointType type{
      .name = "universal",
      .description = "a cross of two pins: the points coincide, rotations about both pins",
      .axes = JointAxes::CrossPins,
      .freedoms = {2, 0},
      .force_keys = {},
      .rows = rows,
      .reaction = "force on b at the joint point (N) and torque on b about z_a x z_b (N m)",
      .coordinates = kCoordinates,
  };
  return type;
}

}  // namespace rigidae
