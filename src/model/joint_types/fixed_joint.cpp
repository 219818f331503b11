// Fixed joint (weld): the points coincide and the initial relative
// orientation is kept.
//   rows      p_a - p_b = 0 (x, y, z); z_a . n_b = 0, z_a . (z_b x n_b) = 0;
//             n_a . (z_b x n_b) = 0                                    6
//   freedoms  none (the loader refuses a body welded to the ground)
//   reaction  force on b at the joint point (N) and torque on b (N m)
#include "primitives.hpp"
#include "rigidae/model/joint_type.hpp"

namespace rigidae {

namespace {
void rows(const JointSpec& j, std::vector<ConstraintRow>& out) {
  joint_rows::coincident_points(j, out);
  joint_rows::parallel_axes(j, out);
  joint_rows::no_turn(j, out);
}
}  // namespace

const JointType& fixed_joint() {
  static const JointType type{
      .name = "fixed",
      .description = "a weld: no relative motion",
      .axes = JointAxes::Point,
      .freedoms = {0, 0},
      .force_keys = {},
      .rows = rows,
      .reaction = "force on b at the joint point (N) and torque on b (N m)",
  };
  return type;
}

}  // namespace rigidae
