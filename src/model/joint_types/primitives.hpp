#pragma once
// The primitive rows joint types are built from (multibody.md, "Joints as
// short lists of primitives"), on bodies a and b with points p, axes z and
// normals n in each body's frame (JointSpec):
//   coincident_points  p_a . e_k - p_b . e_k = 0, k = x, y, z         3 rows
//   point_on_line      (p_b - p_a) . n_a = 0, (p_b - p_a) . (z_a x n_a) = 0   2
//   parallel_axes      z_a . n_b = 0, z_a . (z_b x n_b) = 0             2
//   no_turn            n_a . (z_b x n_b) = 0 (no rotation about z)      1
//   perpendicular      d_a . d_b = 0                                    1
//   fixed_distance     (|p_b - p_a|^2 - L^2) / (2L) = 0                 1
//                      (as dot products: (p_b.p_b - 2 p_a.p_b + p_a.p_a)
//                      / (2L) - L/2; it reads |p_b - p_a| - L to first
//                      order, so its multiplier is the rod's tension in N)
// Row names ("x", "line_n1", "axis_n2", "turn", ...) name the multipliers'
// output columns: keep them stable.
// Coordinate rows (model/joint_type.hpp, JointCoordinate):
//   turn_about_axis    C = n_a . n_b, S = (z_a x n_a) . n_b: the angle of b
//                      about z from n_a to n_b (zero where n_b = n_a)
//   slide_along_axis   d = (p_b - p_a) . z_a (zero where the points coincide)
#include <vector>

#include "rigidae/model/multibody_spec.hpp"

namespace rigidae::joint_rows {

void coincident_points(const JointSpec& j, std::vector<ConstraintRow>& rows);
void point_on_line(const JointSpec& j, std::vector<ConstraintRow>& rows);
void parallel_axes(const JointSpec& j, std::vector<ConstraintRow>& rows);
void no_turn(const JointSpec& j, std::vector<ConstraintRow>& rows);
void fixed_distance(const JointSpec& j, std::vector<ConstraintRow>& rows);
void perpendicular(const char* name, int body_a, const Vec3& da, int body_b, const Vec3& db,
                   std::vector<ConstraintRow>& rows);

void turn_about_axis(const JointSpec& j, ConstraintRow out[2]);
void slide_along_axis(const JointSpec& j, ConstraintRow out[2]);
// The angle from u_a to v_b about w_a (w_a, u_a fixed in a, unit and
// perpendicular; v_b fixed in b): C = u_a . v_b, S = (w_a x u_a) . v_b.
void angle_of(int body_a, const Vec3& w_a, const Vec3& u_a, int body_b, const Vec3& v_b, ConstraintRow out[2]);

}  // namespace rigidae::joint_rows
