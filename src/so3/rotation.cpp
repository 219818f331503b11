#include "rigidae/so3/rotation.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/SVD>

namespace rigidae::so3 {

Mat3 hat(const Vec3& a) {
  Mat3 M;
  M << 0.0, -a.z(), a.y(),  //
      a.z(), 0.0, -a.x(),   //
      -a.y(), a.x(), 0.0;
  return M;
}

Vec3 vee(const Mat3& M) {
  return 0.5 * Vec3(M(2, 1) - M(1, 2), M(0, 2) - M(2, 0), M(1, 0) - M(0, 1));
}

Mat3 quaternion_to_matrix(const Vec4& q) {
  // Homogeneous quadratic: no normalisation, so R(q) = |q|^2 * rotation.
  const double w = q[0];
  const Vec3 v = q.tail<3>();
  Mat3 R = (w * w - v.squaredNorm()) * Mat3::Identity();
  R.noalias() += 2.0 * v * v.transpose();
  R += 2.0 * w * hat(v);
  return R;
}

Vec4 matrix_to_quaternion(const Mat3& R) {
  // Shepperd: 4w^2 = 1 + tr, 4x^2 = 1 + 2 R00 - tr, ... Divide by the largest
  // of the four so the division is never by a small number.
  const double tr = R.trace();
  Vec4 q;
  if (tr >= R(0, 0) && tr >= R(1, 1) && tr >= R(2, 2)) {
    const double w = 0.5 * std::sqrt(std::max(0.0, 1.0 + tr));
    const double f = 0.25 / w;
    q << w, f * (R(2, 1) - R(1, 2)), f * (R(0, 2) - R(2, 0)), f * (R(1, 0) - R(0, 1));
  } else if (R(0, 0) >= R(1, 1) && R(0, 0) >= R(2, 2)) {
    const double x = 0.5 * std::sqrt(std::max(0.0, 1.0 + 2.0 * R(0, 0) - tr));
    const double f = 0.25 / x;
    q << f * (R(2, 1) - R(1, 2)), x, f * (R(0, 1) + R(1, 0)), f * (R(0, 2) + R(2, 0));
  } else if (R(1, 1) >= R(2, 2)) {
    const double y = 0.5 * std::sqrt(std::max(0.0, 1.0 + 2.0 * R(1, 1) - tr));
    const double f = 0.25 / y;
    q << f * (R(0, 2) - R(2, 0)), f * (R(0, 1) + R(1, 0)), y, f * (R(1, 2) + R(2, 1));
  } else {
    const double z = 0.5 * std::sqrt(std::max(0.0, 1.0 + 2.0 * R(2, 2) - tr));
    const double f = 0.25 / z;
    q << f * (R(1, 0) - R(0, 1)), f * (R(0, 2) + R(2, 0)), f * (R(1, 2) + R(2, 1)), z;
  }
  q.normalize();  // removes the round-off of a not-quite-orthogonal R
  if (q[0] < 0.0) q = -q;
  return q;
}

Vec4 quaternion_product(const Vec4& p, const Vec4& q) {
  const double pw = p[0];
  const double qw = q[0];
  const Vec3 pv = p.tail<3>();
  const Vec3 qv = q.tail<3>();
  Vec4 r;
  r[0] = pw * qw - pv.dot(qv);
  r.tail<3>() = pw * qv + qw * pv + pv.cross(qv);
  return r;
}

Mat3 axis_angle_to_matrix(const Vec3& axis, double angle) {
  // R = I + sin(t) hat(n) + (1 - cos t) hat(n)^2, with 1 - cos t = 2 sin^2(t/2)
  // to keep small angles accurate.
  const Mat3 K = hat(axis);
  const double s = std::sin(0.5 * angle);
  return Mat3::Identity() + std::sin(angle) * K + (2.0 * s * s) * (K * K);
}

Vec3 matrix_to_rotation_vector(const Mat3& R) {
  // Through the quaternion (w >= 0): angle = 2 atan2(|v|, w) in [0, pi],
  // accurate at both ends (no acos of a trace).
  const Vec4 q = matrix_to_quaternion(R);
  const Vec3 v = q.tail<3>();
  const double n = v.norm();
  if (n == 0.0) return Vec3::Zero();
  const double angle = 2.0 * std::atan2(n, q[0]);
  return (angle / n) * v;
}

double rotation_distance(const Mat3& R1, const Mat3& R2) {
  const Vec4 q = matrix_to_quaternion(R1.transpose() * R2);
  return 2.0 * std::atan2(q.tail<3>().norm(), std::abs(q[0]));
}

double quaternion_distance(const Vec4& q1, const Vec4& q2) {
  // The unit quaternions make an angle alpha = theta/2 on S^3 (theta the
  // rotation angle of q1^-1 q2), after choosing the sign of q2 that brings
  // it closer to q1. With d = |q1 - s q2| and e = |q1 + s q2|,
  // atan2(d, e) = alpha/2, so theta = 4 atan2(d, e), in [0, pi].
  const double s = (q1.dot(q2) >= 0.0) ? 1.0 : -1.0;
  return 4.0 * std::atan2((q1 - s * q2).norm(), (q1 + s * q2).norm());
}

Mat3 nearest_rotation(const Mat3& M) {
  Eigen::JacobiSVD<Mat3> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat3 U = svd.matrixU();
  const Mat3& V = svd.matrixV();
  if ((U * V.transpose()).determinant() < 0.0) U.col(2) = -U.col(2);  // smallest singular value
  return U * V.transpose();
}

Mat3 axis_rotation(int axis, double angle) {
  if (axis < 0 || axis > 2) {
    throw std::invalid_argument("axis_rotation: axis must be 0 (x), 1 (y) or 2 (z), got " +
                                std::to_string(axis));
  }
  const double c = std::cos(angle);
  const double s = std::sin(angle);
  const int j = (axis + 1) % 3;
  const int k = (axis + 2) % 3;
  Mat3 R = Mat3::Zero();
  R(axis, axis) = 1.0;
  R(j, j) = c;
  R(k, k) = c;
  R(k, j) = s;
  R(j, k) = -s;
  return R;
}

}  // namespace rigidae::so3
