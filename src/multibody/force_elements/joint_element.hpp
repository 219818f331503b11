#pragma once
// What the force elements that act in a joint (a torsional spring or motor,
// a linear motor) share: the rows of the joint type's coordinate they act
// on, and the joint's two sides at an evaluation.
#include <stdexcept>
#include <string>

#include "rigidae/multibody/constraint_rows.hpp"
#include "rigidae/multibody/force_element.hpp"

namespace rigidae::multibody {

// The rows of the joint type's first coordinate of `kind` (an angle: C, S;
// a length: d) into out; `element` names the caller for the error raised
// when the type has none (the loader only gives the keys to types that do).
inline void joint_coordinate_rows(const JointSpec& js, CoordinateKind kind, ConstraintRow* out, const char* element) {
  for (const JointCoordinate& c : js.type->coordinates)
    if (c.kind == kind) {
      c.rows(js, out);
      return;
    }
  throw std::logic_error(std::string(element) + " on a joint type without that coordinate: " +
                         std::string(js.type->name));
}

// The joint's bodies a and b and their states (nullptr for the ground).
inline BlockSides joint_sides(const int (&body)[2], const ForceBodies& b) {
  BlockSides s;
  for (int x = 0; x < 2; ++x) {
    s.body[x] = body[x];
    s.state[x] = b.of(body[x]);
  }
  return s;
}

}  // namespace rigidae::multibody
