// Joint rows from primitives (see joints.hpp).
#include "rigidae/multibody/joints.hpp"

#include <array>

namespace rigidae::multibody {

namespace {

BodyVector point(int body, const Vec3& s) { return {body, s, true}; }
BodyVector direction(int body, const Vec3& s) { return {body, s, false}; }

void coincident_points(const JointSpec& j, std::vector<ConstraintRow>& rows) {
  const char* names[3] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k) {
    ConstraintRow r;
    r.name = names[k];
    r.terms[0] = {1.0, point(j.body_a, j.point_a), direction(kGround, Vec3::Unit(k))};
    r.terms[1] = {-1.0, point(j.body_b, j.point_b), direction(kGround, Vec3::Unit(k))};
    r.n_terms = 2;
    rows.push_back(r);
  }
}

void perpendicular(const char* name, int body_a, const Vec3& da, int body_b, const Vec3& db,
                   std::vector<ConstraintRow>& rows) {
  ConstraintRow r;
  r.name = name;
  r.terms[0] = {1.0, direction(body_a, da), direction(body_b, db)};
  r.n_terms = 1;
  rows.push_back(r);
}

void point_on_line(const JointSpec& j, std::vector<ConstraintRow>& rows) {
  const Vec3 n[2] = {j.normal_a, j.axis_a.cross(j.normal_a)};
  const char* names[2] = {"line_n1", "line_n2"};
  for (int i = 0; i < 2; ++i) {
    ConstraintRow r;
    r.name = names[i];
    r.terms[0] = {1.0, point(j.body_b, j.point_b), direction(j.body_a, n[i])};
    r.terms[1] = {-1.0, point(j.body_a, j.point_a), direction(j.body_a, n[i])};
    r.n_terms = 2;
    rows.push_back(r);
  }
}

// z_a perpendicular to the two normals of z_b: the axes stay parallel.
void parallel_axes(const JointSpec& j, std::vector<ConstraintRow>& rows) {
  perpendicular("axis_n1", j.body_a, j.axis_a, j.body_b, j.normal_b, rows);
  perpendicular("axis_n2", j.body_a, j.axis_a, j.body_b, j.axis_b.cross(j.normal_b), rows);
}

void no_turn(const JointSpec& j, std::vector<ConstraintRow>& rows) {
  perpendicular("turn", j.body_a, j.normal_a, j.body_b, j.axis_b.cross(j.normal_b), rows);
}

}  // namespace

std::vector<ConstraintRow> joint_rows(const JointSpec& j) {
  std::vector<ConstraintRow> rows;
  switch (j.type) {
    case JointType::Spherical: coincident_points(j, rows); break;
    case JointType::Universal:
      coincident_points(j, rows);
      perpendicular("cross", j.body_a, j.axis_a, j.body_b, j.axis_b, rows);
      break;
    case JointType::Revolute:
      coincident_points(j, rows);
      parallel_axes(j, rows);
      break;
    case JointType::Cylindrical:
      point_on_line(j, rows);
      parallel_axes(j, rows);
      break;
    case JointType::Prismatic:
      point_on_line(j, rows);
      parallel_axes(j, rows);
      no_turn(j, rows);
      break;
    case JointType::Fixed:
      coincident_points(j, rows);
      parallel_axes(j, rows);
      no_turn(j, rows);
      break;
  }
  return rows;
}

const char* joint_type_name(JointType type) {
  static constexpr std::array<const char*, 6> kNames{"spherical", "revolute", "universal",
                                                     "prismatic", "cylindrical", "fixed"};
  return kNames[static_cast<int>(type)];
}

}  // namespace rigidae::multibody
