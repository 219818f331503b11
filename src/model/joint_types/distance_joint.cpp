// Distance joint (a massless rod with ball ends): two points, one on each
// body, stay at the distance L (the textbook pendulum: a particle on a rod
// to a ground point).
//   row       (|p_b - p_a|^2 - L^2) / (2L) = 0                          1
//             (dot products of the two points: primitives.hpp,
//             fixed_distance; its gradient is the unit vector along the
//             rod, so the row reads |p_b - p_a| - L near the constraint)
//   freedoms  3 rotations (about p_a), 2 translations (normal to the rod)
//   reaction  the multiplier is the rod's tension T (N): the force on b is
//             -T (p_b - p_a) / L, on a +T (p_b - p_a) / L; no torque about
//             the rod's ends
// Geometry keys (JointAxes::TwoPoints): point_a, point_b and length (the
// initial distance when left out). A rod of zero length is refused by the
// loader (use a spherical joint): its direction would be undefined.
#include "primitives.hpp"
#include "rigidae/model/joint_type.hpp"

namespace rigidae {

namespace {
void rows(const JointSpec& j, std::vector<ConstraintRow>& out) { joint_rows::fixed_distance(j, out); }
}  // namespace

const JointType& distance_joint() {
  static const JointType type{
      .name = "distance",
      .description = "a massless rod: the two points stay at the distance `length`, every other motion free",
      .axes = JointAxes::TwoPoints,
      .freedoms = {3, 2},
      .force_keys = {},
      .rows = rows,
      .reaction = "the rod's tension T (N): force -T (p_b - p_a) / L on b at its point",
      .coordinates = {},
  };
  return type;
}

}  // namespace rigidae
