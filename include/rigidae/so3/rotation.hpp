#pragma once
// Rotations: matrices, unit quaternions and axis-angle.
//
// Conventions used everywhere in rigidae:
// - R_WB maps body-frame components to world (space) components: x_W = R_WB x_B.
// - Quaternions are scalar first, q = (w, x, y, z), and represent R_WB.
// - Body angular velocity omega_B: dR/dt = R hat(omega_B); space omega_W = R omega_B.
#include "rigidae/core/types.hpp"

namespace rigidae::so3 {

// hat(a) b = a x b.
Mat3 hat(const Vec3& a);
// Inverse of hat for the skew-symmetric part of M: vee(hat(a)) = a.
Vec3 vee(const Mat3& M);

// The homogeneous quadratic map R(q) = (w^2 - v.v) I + 2 v v^T + 2 w hat(v).
// It equals |q|^2 times a rotation; a rotation exactly when |q| = 1.
Mat3 quaternion_to_matrix(const Vec4& q);
// Unit quaternion of a rotation matrix, w >= 0 (Shepperd's branch choice,
// accurate for every rotation). R must be a rotation to round-off.
Vec4 matrix_to_quaternion(const Mat3& R);
// Hamilton product p (x) q, scalar first.
Vec4 quaternion_product(const Vec4& p, const Vec4& q);

// Rotation by `angle` rad about the unit vector `axis` (Rodrigues).
Mat3 axis_angle_to_matrix(const Vec3& axis, double angle);
// Rotation vector (axis * angle, angle in [0, pi]) of a rotation matrix,
// accurate near 0 and near pi.
Vec3 matrix_to_rotation_vector(const Mat3& R);

// Geodesic distance between two rotations, in rad, in [0, pi].
double rotation_distance(const Mat3& R1, const Mat3& R2);
// Same for two unit quaternions, independent of their signs.
double quaternion_distance(const Vec4& q1, const Vec4& q2);

// Nearest rotation in the Frobenius norm (the orthogonal polar factor, U V^T
// with the sign fixed so that det = +1).
Mat3 nearest_rotation(const Mat3& M);

// Elementary rotation about body axis 0 (x), 1 (y) or 2 (z).
Mat3 axis_rotation(int axis, double angle);

}  // namespace rigidae::so3
