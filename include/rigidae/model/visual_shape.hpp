#pragma once
// A shape that draws a body (the viewer, ParaView files, animations): the
// scene's optional `visual` entries of a body. It has no mass and takes no
// part in the dynamics; a body without one is drawn as its inertia
// ellipsoid (app/scene_geometry.hpp).
//
// Conventions: the shape's own frame V sits at `position_B` in the body
// frame B and is turned by R_BV (x_B = position_B + R_BV x_V). In V, a box
// is centred at the origin with edge lengths `size`; a sphere is centred at
// the origin; a cylinder and a capsule have their axis along z_V, centred at
// the origin, `length` the length of the cylinder (a capsule adds a
// hemisphere of `radius` at each end).
#include <string_view>

#include "rigidae/core/types.hpp"

namespace rigidae {

enum class VisualKind { Box, Cylinder, Sphere, Capsule };

struct VisualShape {
  VisualKind kind = VisualKind::Sphere;
  Vec3 size = Vec3::Zero();  // m, box edge lengths along x_V, y_V, z_V
  double radius = 0.0;       // m, sphere, cylinder, capsule
  double length = 0.0;       // m, cylinder, capsule: along z_V
  Vec3 position_B = Vec3::Zero();
  Mat3 R_BV = Mat3::Identity();
};

inline std::string_view visual_kind_name(VisualKind k) {
  switch (k) {
    case VisualKind::Box: return "box";
    case VisualKind::Cylinder: return "cylinder";
    case VisualKind::Sphere: return "sphere";
    case VisualKind::Capsule: return "capsule";
  }
  return "sphere";
}

}  // namespace rigidae
