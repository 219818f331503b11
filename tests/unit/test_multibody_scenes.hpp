#pragma once
// Multibody scenes built in code, independent of the schema-2 loader.
#include <string>

#include "rigidae/model/scene.hpp"
#include "rigidae/so3/rotation.hpp"

namespace rigidae::test {

inline Scene multibody_base(Coordinates c, Equations e, const std::string& scheme) {
  Scene s;
  s.name = "multibody";
  s.schema_version = 2;  // as a file of bodies and joints would say
  s.formulation.coordinates = c;
  s.formulation.equations = e;
  s.formulation.scheme = scheme;
  s.time = {0.0, 1.0, 0.01};
  s.multibody = MultibodySpec{};
  return s;
}

// The heavy top (Bruls, Cardona & Arnold 2012) as a free body held by a
// spherical joint to the ground at the origin: centre of mass at R0 (0, 1, 0).
inline Scene absolute_heavy_top(Coordinates c, Equations e, const std::string& scheme) {
  Scene s = multibody_base(c, e, scheme);
  s.name = "heavy_top_absolute";
  MultibodySpec& m = *s.multibody;
  BodySpec top;
  top.name = "top";
  top.mass = 15.0;
  top.inertia_com = Vec3(0.234375, 0.46875, 0.234375).asDiagonal();
  top.R0_WB = Mat3::Identity();
  top.x0_W = top.R0_WB * Vec3(0, 1, 0);
  top.omega0_B = Vec3(0, 150, -4.61538);
  top.v0_W = top.R0_WB * top.omega0_B.cross(Vec3(0, 1, 0));
  m.bodies.push_back(top);
  JointSpec pivot;
  pivot.name = "pivot";
  pivot.type = &joint_type("spherical");
  pivot.body_a = kGround;
  pivot.body_b = 0;
  pivot.point_a = Vec3::Zero();
  pivot.point_b = Vec3(0, -1, 0);
  m.joints.push_back(pivot);
  m.gravity_W = Vec3(0, 0, -9.81);
  return s;
}

// A joint between a and b (either may be kGround) at the space point P with
// the space axis z and normal n (perpendicular), placed so that it holds.
inline JointSpec joint_at(const MultibodySpec& m, const JointType* type, int a, int b, const Vec3& P, const Vec3& z,
                          const Vec3& n, const std::string& name) {
  JointSpec j;
  j.name = name;
  j.type = type;
  j.body_a = a;
  j.body_b = b;
  const auto to_body = [&](int i, const Vec3& p, bool point) -> Vec3 {
    if (i == kGround) return p;
    const BodySpec& bs = m.bodies[i];
    return bs.R0_WB.transpose() * (point ? Vec3(p - bs.x0_W) : p);
  };
  j.point_a = to_body(a, P, true);
  j.point_b = to_body(b, P, true);
  if (type->axes == JointAxes::TwoPoints) {
    // A rod from P to P + 0.3 z (its length at the assembled pose).
    j.point_b = to_body(b, Vec3(P + 0.3 * z), true);
    j.length = 0.3;
  }
  j.axis_a = to_body(a, z, false);
  j.normal_a = to_body(a, n, false);
  // Universal: the cross pins are perpendicular.
  const Vec3 zb = type == &joint_type("universal") ? n : z;
  const Vec3 nb = type == &joint_type("universal") ? Vec3(z.cross(n)) : n;
  j.axis_b = to_body(b, zb, false);
  j.normal_b = to_body(b, nb, false);
  j.where = {"built_in.toml", 10 + static_cast<int>(m.joints.size()), 1};
  return j;
}

// Two asymmetric bodies, the first joined to the ground and the second to
// the first by joints of `type`, with a spring between them and loads of
// every kind (revolute joints: torsional spring-dampers too): no symmetry
// hides a wrong sign.
inline Scene two_body_chain(const JointType* type, Coordinates c, Equations e, const std::string& scheme) {
  Scene s = multibody_base(c, e, scheme);
  MultibodySpec& m = *s.multibody;
  BodySpec a;
  a.name = "A";
  a.mass = 2.0;
  a.inertia_com << 0.4, 0.05, -0.02, 0.05, 0.7, 0.03, -0.02, 0.03, 0.9;
  a.x0_W = Vec3(0.3, -0.2, -0.5);
  a.R0_WB = so3::axis_angle_to_matrix(Vec3(1, 2, 3).normalized(), 0.7);
  a.v0_W = Vec3(0.5, -0.4, 0.3);
  a.omega0_B = Vec3(1.5, -2.0, 3.0);
  a.where = {"built_in.toml", 2, 1};
  BodySpec b = a;
  b.name = "B";
  b.mass = 1.3;
  b.inertia_com << 0.3, -0.04, 0.01, -0.04, 0.5, 0.02, 0.01, 0.02, 0.6;
  b.x0_W = Vec3(0.8, 0.4, -1.1);
  b.R0_WB = so3::axis_angle_to_matrix(Vec3(-2, 1, 0.5).normalized(), 1.1);
  b.v0_W = Vec3(-0.3, 0.6, 0.2);
  b.omega0_B = Vec3(-1.0, 0.7, 2.2);
  b.where = {"built_in.toml", 6, 1};
  m.bodies = {a, b};
  const Vec3 z = Vec3(0.2, 0.3, 1.0).normalized();
  const Vec3 n = z.cross(Vec3::UnitX()).normalized();
  m.joints.push_back(joint_at(m, type, kGround, 0, Vec3(0.1, 0.0, 0.0), z, n, "j0"));
  const Vec3 z2 = Vec3(1.0, -0.4, 0.2).normalized();
  const Vec3 n2 = z2.cross(Vec3::UnitZ()).normalized();
  m.joints.push_back(joint_at(m, type, 0, 1, Vec3(0.5, 0.1, -0.8), z2, n2, "j1"));
  if (type == &joint_type("revolute")) {
    // Torsional spring-dampers, wound at the start (rest angles not zero).
    m.joints[0].torsion_stiffness = 3.0;
    m.joints[0].torsion_damping = 0.4;
    m.joints[0].torsion_rest_angle = 0.6;
    m.joints[1].torsion_stiffness = 5.0;
    m.joints[1].torsion_damping = 0.7;
    m.joints[1].torsion_rest_angle = -2.5;
    // A motor whose torque varies in time (its matrix part is through the
    // angle's direction alone).
    m.joints[1].motor_torque = 0.6;
    m.joints[1].motor_profile = polynomial_function({1.0, 0.5, -0.25});
  }
  if (type == &joint_type("prismatic")) {
    // A linear motor whose force varies in time (its matrix part is through
    // the displacement's direction alone).
    m.joints[1].motor_force = 4.0;
    m.joints[1].motor_profile = polynomial_function({1.0, -0.5, 0.25});
  }
  SpringSpec sp;
  sp.name = "spring";
  sp.body_a = 0;
  sp.body_b = 1;
  sp.point_a = Vec3(0.1, 0.2, -0.1);
  sp.point_b = Vec3(-0.2, 0.05, 0.1);
  sp.stiffness = 40.0;
  sp.damping = 1.5;
  sp.rest_length = 0.3;
  m.springs.push_back(sp);
  SpringSpec sg = sp;
  sg.body_a = kGround;
  sg.point_a = Vec3(1.0, 1.0, 0.5);
  m.springs.push_back(sg);
  BodyLoadSpec l1;
  l1.body = 0;
  l1.force = Vec3(1.0, -2.0, 0.5);
  l1.torque = Vec3(0.3, 0.1, -0.4);
  l1.body_frame = true;
  BodyLoadSpec l2;
  l2.body = 1;
  l2.force = Vec3(-0.5, 0.2, 1.0);
  l2.torque = Vec3(-0.2, 0.5, 0.1);
  l2.body_frame = false;
  m.loads = {l1, l2};
  return s;
}

}  // namespace rigidae::test

namespace rigidae::test {

// A hanging chain of n identical links joined by spherical joints, the first
// to the ground at the origin, links along -z (length 0.5 m), slightly swinging.
inline Scene spherical_chain(int n, Coordinates c, Equations e, const std::string& scheme) {
  Scene s = multibody_base(c, e, scheme);
  MultibodySpec& m = *s.multibody;
  const double L = 0.5;
  for (int i = 0; i < n; ++i) {
    BodySpec b;
    b.name = "link" + std::to_string(i);
    b.mass = 0.3;
    b.inertia_com = Vec3(0.007, 0.007, 0.001).asDiagonal();
    b.x0_W = Vec3(0, 0, -L * (i + 0.5));
    b.v0_W = Vec3(0.1 * (i + 0.5) * L, 0, 0);
    b.omega0_B = Vec3(0, 0.1, 0);
    m.bodies.push_back(b);
  }
  for (int i = 0; i < n; ++i)
    m.joints.push_back(joint_at(m, &joint_type("spherical"), i == 0 ? kGround : i - 1, i, Vec3(0, 0, -L * i),
                                Vec3::UnitZ(), Vec3::UnitX(), "joint" + std::to_string(i)));
  return s;
}

}  // namespace rigidae::test
