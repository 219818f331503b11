// The force-element registry: one line per element type
// (multibody/force_element.hpp). Each adds the elements of its kind that a
// scene holds; the order here is the order of summation in the residual.
#include "rigidae/multibody/force_element.hpp"

namespace rigidae::multibody {

// Each defined in its own file in this folder.
void add_gravity(const MultibodySpec&, ForceElements&);
void add_body_loads(const MultibodySpec&, ForceElements&);
void add_springs(const MultibodySpec&, ForceElements&);
void add_torsion_springs(const MultibodySpec&, ForceElements&);
void add_joint_forces(const MultibodySpec&, ForceElements&);

namespace {
using AddElements = void (*)(const MultibodySpec&, ForceElements&);
constexpr AddElements kForceElements[] = {
    add_gravity,
    add_body_loads,
    add_springs,
    add_torsion_springs,
    add_joint_forces,
};
}  // namespace

ForceElements make_force_elements(const MultibodySpec& spec) {
  ForceElements out;
  for (AddElements add : kForceElements) add(spec, out);
  return out;
}

}  // namespace rigidae::multibody
