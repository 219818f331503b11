// A one-body scene as a system of one pivoted body (see one_body_system.hpp).
#include "rigidae/model/one_body_system.hpp"

namespace rigidae {

Scene one_body_system(const Scene& s) {
  Scene out = s;
  const Vec3 c = s.support == Support::FixedPoint ? s.body.com_B : Vec3::Zero();
  BodySpec b;
  b.name = "body";
  b.mass = s.body.mass;
  b.inertia_com = s.body.inertia_com;
  b.R0_WB = s.R0_WB;
  b.omega0_B = s.omega0_B;
  b.pivot_W = Vec3::Zero();
  b.com_from_pivot_B = c;
  b.x0_W = s.R0_WB * c;
  b.v0_W = s.R0_WB * s.omega0_B.cross(c);
  // The shapes it is drawn with, from the body origin (a top's fixed point)
  // moved to the centre of mass, the origin of a system's body frame.
  b.visuals = s.body.visuals;
  for (VisualShape& v : b.visuals) v.position_B -= s.body.com_B;
  MultibodySpec m;
  m.bodies.push_back(b);
  m.gravity_W = s.gravity_W;
  m.one_body_scene = true;
  out.multibody = std::move(m);
  return out;
}

Scene as_system(const Scene& s) { return s.multibody ? s : one_body_system(s); }

}  // namespace rigidae
