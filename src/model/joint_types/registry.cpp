// The joint-type registry: one line per type (model/joint_type.hpp). The
// scene loader takes the valid `type` names from here, in this order.
#include <stdexcept>
#include <string>

#include "rigidae/model/joint_type.hpp"

namespace rigidae {

// Each defined in its own file, src/model/joint_types/<name>_joint.cpp.
const JointType& spherical_joint();
const JointType& revolute_joint();
const JointType& universal_joint();
const JointType& prismatic_joint();
const JointType& cylindrical_joint();
const JointType& fixed_joint();
const JointType& distance_joint();

const std::vector<const JointType*>& joint_types() {
  static const std::vector<const JointType*> kTypes{
      &spherical_joint(),
      &revolute_joint(),
      &universal_joint(),
      &prismatic_joint(),
      &cylindrical_joint(),
      &fixed_joint(),
      &distance_joint(),
  };
  return kTypes;
}

std::vector<std::string_view> joint_type_names() {
  std::vector<std::string_view> names;
  for (const JointType* t : joint_types()) names.push_back(t->name);
  return names;
}

const JointType* find_joint_type(std::string_view name) {
  for (const JointType* t : joint_types())
    if (t->name == name) return t;
  return nullptr;
}

const JointType& joint_type(std::string_view name) {
  if (const JointType* t = find_joint_type(name)) return *t;
  throw std::invalid_argument("unknown joint type '" + std::string(name) + "'");
}

}  // namespace rigidae
