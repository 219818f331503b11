// Primitive joint rows (see primitives.hpp).
#include "primitives.hpp"

namespace rigidae::joint_rows {

namespace {
BodyVector point(int body, const Vec3& s) { return {body, s, true}; }
BodyVector direction(int body, const Vec3& s) { return {body, s, false}; }
}  // namespace

void coincident_points(const JointSpec& j, std::vector<ConstraintRow>& rows) {
  const char* names[3] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k) {
    ConstraintRow r;
    r.name = names[k];
    r.terms[0] = {1.0, point(j.body_a, j.point_a), direction(kGround, Vec3::Unit(k))};
    r.terms[1] = {-1.0, point(j.body_b, j.point_b), direction(kGround, Vec3::Unit(k))};
    r.n_terms = 2;
    r.reaction = RowReaction::Point;
    rows.push_back(r);
  }
}

void perpendicular(const char* name, int body_a, const Vec3& da, int body_b, const Vec3& db,
                   std::vector<ConstraintRow>& rows) {
  ConstraintRow r;
  r.name = name;
  r.terms[0] = {1.0, direction(body_a, da), direction(body_b, db)};
  r.n_terms = 1;
  r.reaction = RowReaction::Turn;
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
    r.reaction = RowReaction::Line;
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

void fixed_distance(const JointSpec& j, std::vector<ConstraintRow>& rows) {
  const double L = j.length;
  const BodyVector pa = point(j.body_a, j.point_a), pb = point(j.body_b, j.point_b);
  ConstraintRow r;
  r.name = "rod";
  r.terms[0] = {0.5 / L, pb, pb};
  r.terms[1] = {-1.0 / L, pa, pb};
  r.terms[2] = {0.5 / L, pa, pa};
  r.n_terms = 3;
  r.constant = -0.5 * L;
  r.reaction = RowReaction::Distance;
  rows.push_back(r);
}

void angle_of(int body_a, const Vec3& w_a, const Vec3& u_a, int body_b, const Vec3& v_b, ConstraintRow out[2]) {
  out[0] = ConstraintRow{};
  out[0].name = "cos";
  out[0].terms[0] = {1.0, direction(body_a, u_a), direction(body_b, v_b)};
  out[1] = ConstraintRow{};
  out[1].name = "sin";
  out[1].terms[0] = {1.0, direction(body_a, w_a.cross(u_a)), direction(body_b, v_b)};
}

void turn_about_axis(const JointSpec& j, ConstraintRow out[2]) {
  angle_of(j.body_a, j.axis_a, j.normal_a, j.body_b, j.normal_b, out);
}

void slide_along_axis(const JointSpec& j, ConstraintRow out[2]) {
  out[0] = ConstraintRow{};
  out[0].name = "slide";
  out[0].terms[0] = {1.0, point(j.body_b, j.point_b), direction(j.body_a, j.axis_a)};
  out[0].terms[1] = {-1.0, point(j.body_a, j.point_a), direction(j.body_a, j.axis_a)};
  out[0].n_terms = 2;
}

}  // namespace rigidae::joint_rows
