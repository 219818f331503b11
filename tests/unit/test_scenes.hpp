#pragma once
// Scenes built in code, independent of the scene-file loader.
#include "rigidae/model/scene.hpp"
#include "rigidae/so3/rotation.hpp"

namespace rigidae::test {

// Bruls, Cardona & Arnold (2012): the heavy top benchmark.
inline Scene heavy_top_scene(Coordinates c = Coordinates::Quaternion, Equations e = Equations::Euler,
                             const std::string& scheme = "ggl") {
  Scene s;
  s.name = "heavy_top";
  s.body.mass = 15.0;
  s.body.inertia_com = Vec3(0.234375, 0.46875, 0.234375).asDiagonal();
  s.body.com_B = Vec3(0, 1, 0);
  s.support = Support::FixedPoint;
  s.gravity_W = Vec3(0, 0, -9.81);
  s.R0_WB = Mat3::Identity();
  s.omega0_B = Vec3(0, 150, -4.61538);
  s.time = {0.0, 2.0, 0.01};
  s.formulation.coordinates = c;
  s.formulation.equations = e;
  s.formulation.scheme = scheme;
  return s;
}

// An asymmetric body with a tilted start: no symmetry hides a wrong sign.
inline Scene asymmetric_top_scene(Coordinates c, Equations e, const std::string& scheme = "ggl") {
  Scene s = heavy_top_scene(c, e, scheme);
  s.body.inertia_com << 0.4, 0.05, -0.02, 0.05, 0.7, 0.03, -0.02, 0.03, 0.9;
  s.body.com_B = Vec3(0.1, 0.3, -0.2);
  s.R0_WB = so3::axis_angle_to_matrix(Vec3(1, 2, 3).normalized(), 0.7);
  s.omega0_B = Vec3(1.5, -2.0, 3.0);
  return s;
}

}  // namespace rigidae::test
