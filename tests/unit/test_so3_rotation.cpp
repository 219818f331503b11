// Rotation matrices, quaternions and axis-angle, checked against Eigen's
// independent Geometry module and against closed-form physics relations.
#include <doctest/doctest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>

#include "rigidae/so3/rotation.hpp"

TEST_SUITE_BEGIN("unit");

using namespace rigidae;
using namespace rigidae::so3;

namespace {

constexpr double kPi = std::numbers::pi;

Vec4 random_unit_quaternion(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Vec4 q(n(rng), n(rng), n(rng), n(rng));
  return q.normalized();
}

Vec3 random_unit_vector(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  return Vec3(n(rng), n(rng), n(rng)).normalized();
}

// Eigen's own quaternion -> matrix (Eigen::Quaterniond takes w, x, y, z).
Mat3 eigen_rotation(const Vec4& q) {
  return Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized().toRotationMatrix();
}

double max_abs(const Mat3& M) { return M.cwiseAbs().maxCoeff(); }

}  // namespace

TEST_CASE("so3: hat is the cross-product matrix and vee inverts it") {
  std::mt19937 rng(11);
  std::normal_distribution<double> n(0.0, 1.0);
  for (int t = 0; t < 50; ++t) {
    const Vec3 a(n(rng), n(rng), n(rng));
    const Vec3 b(n(rng), n(rng), n(rng));
    CHECK((hat(a) * b - a.cross(b)).norm() < 1e-14);
    CHECK((hat(a) + hat(a).transpose()).norm() == 0.0);
    CHECK((vee(hat(a)) - a).norm() < 1e-15);
    // vee only sees the skew-symmetric part.
    const Mat3 S = Mat3::Random() + Mat3::Random().transpose();
    CHECK((vee(hat(a) + S + S.transpose()) - a).norm() < 1e-14);
  }
}

TEST_CASE("so3: elementary axis rotations match Eigen's angle-axis rotations") {
  for (double angle : {-2.5, -0.3, 0.0, 0.7, 3.0}) {
    CHECK(max_abs(axis_rotation(0, angle) - Eigen::AngleAxisd(angle, Vec3::UnitX()).toRotationMatrix()) < 1e-15);
    CHECK(max_abs(axis_rotation(1, angle) - Eigen::AngleAxisd(angle, Vec3::UnitY()).toRotationMatrix()) < 1e-15);
    CHECK(max_abs(axis_rotation(2, angle) - Eigen::AngleAxisd(angle, Vec3::UnitZ()).toRotationMatrix()) < 1e-15);
  }
  // A quarter turn about z takes the x axis to the y axis (active, body to space).
  CHECK((axis_rotation(2, kPi / 2) * Vec3::UnitX() - Vec3::UnitY()).norm() < 1e-15);
  CHECK_THROWS_AS(axis_rotation(3, 0.1), std::invalid_argument);
  CHECK_THROWS_AS(axis_rotation(-1, 0.1), std::invalid_argument);
}

TEST_CASE("so3: a unit quaternion maps to the same rotation as Eigen's and back, with w >= 0") {
  std::mt19937 rng(12345);
  for (int t = 0; t < 2000; ++t) {
    const Vec4 q = random_unit_quaternion(rng);
    const Mat3 R = quaternion_to_matrix(q);
    CAPTURE(q.transpose());
    CHECK(max_abs(R - eigen_rotation(q)) < 1e-15 * 8);
    CHECK(max_abs(R.transpose() * R - Mat3::Identity()) < 1e-14);
    CHECK(R.determinant() == doctest::Approx(1.0).epsilon(1e-14));
    // Both signs of q describe the same rotation; the recovered one has w >= 0.
    for (double sign : {1.0, -1.0}) {
      const Vec4 qs = sign * q;
      CHECK(max_abs(quaternion_to_matrix(qs) - R) < 1e-15);
      const Vec4 back = matrix_to_quaternion(quaternion_to_matrix(qs));
      CHECK(back[0] >= 0.0);
      CHECK(back.norm() == doctest::Approx(1.0).epsilon(1e-15));
      const Vec4 expected = (q[0] >= 0.0) ? q : Vec4(-q);
      CHECK((back - expected).norm() < 1e-14);
    }
  }
}

TEST_CASE("so3: quaternion recovery is accurate for half turns, where w = 0 and Shepperd divides by x, y or z") {
  std::mt19937 rng(7);
  for (int t = 0; t < 200; ++t) {
    const Vec3 n = random_unit_vector(rng);
    for (double angle : {kPi, kPi - 1e-9, kPi - 1e-4}) {
      const Mat3 R = Eigen::AngleAxisd(angle, n).toRotationMatrix();
      const Vec4 q = matrix_to_quaternion(R);
      CHECK(q[0] >= 0.0);
      CHECK(max_abs(quaternion_to_matrix(q) - R) < 1e-14);
      // Half turn about n: q = (cos(angle/2), sin(angle/2) n) up to sign.
      const Vec4 truth(std::cos(angle / 2), std::sin(angle / 2) * n.x(), std::sin(angle / 2) * n.y(),
                       std::sin(angle / 2) * n.z());
      CHECK(std::min((q - truth).norm(), (q + truth).norm()) < 1e-14);
    }
  }
  // The three coordinate half turns.
  CHECK((matrix_to_quaternion(Vec3(1, -1, -1).asDiagonal()).cwiseAbs() - Vec4(0, 1, 0, 0)).norm() < 1e-16);
  CHECK((matrix_to_quaternion(Vec3(-1, 1, -1).asDiagonal()).cwiseAbs() - Vec4(0, 0, 1, 0)).norm() < 1e-16);
  CHECK((matrix_to_quaternion(Vec3(-1, -1, 1).asDiagonal()).cwiseAbs() - Vec4(0, 0, 0, 1)).norm() < 1e-16);
  CHECK((matrix_to_quaternion(Mat3::Identity()) - Vec4(1, 0, 0, 0)).norm() == 0.0);
}

TEST_CASE("so3: the quaternion map is homogeneous quadratic, |q|^2 times a rotation for non-unit q") {
  std::mt19937 rng(99);
  std::uniform_real_distribution<double> scale(0.1, 5.0);
  for (int t = 0; t < 200; ++t) {
    const Vec4 u = random_unit_quaternion(rng);
    const double s = scale(rng);
    const Vec4 q = s * u;
    CHECK(max_abs(quaternion_to_matrix(q) - s * s * eigen_rotation(u)) < 1e-13 * s * s);
    CHECK(quaternion_to_matrix(q).determinant() == doctest::Approx(std::pow(s, 6)).epsilon(1e-12));
  }
  CHECK(max_abs(quaternion_to_matrix(Vec4(2, 0, 0, 0)) - 4.0 * Mat3::Identity()) == 0.0);
  CHECK(max_abs(quaternion_to_matrix(Vec4::Zero())) == 0.0);
}

TEST_CASE("so3: the Hamilton quaternion product composes rotations, R(p (x) q) = R(p) R(q)") {
  std::mt19937 rng(2024);
  for (int t = 0; t < 500; ++t) {
    const Vec4 p = random_unit_quaternion(rng);
    const Vec4 q = random_unit_quaternion(rng);
    const Vec4 pq = quaternion_product(p, q);
    CHECK(max_abs(quaternion_to_matrix(pq) - quaternion_to_matrix(p) * quaternion_to_matrix(q)) < 1e-14);
    // Same as Eigen's quaternion multiplication.
    const Eigen::Quaterniond e = Eigen::Quaterniond(p[0], p[1], p[2], p[3]) * Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
    CHECK((pq - Vec4(e.w(), e.x(), e.y(), e.z())).norm() < 1e-15 * 4);
    // Rotating a vector: q (x) (0, v) (x) q* = (0, R(q) v).
    const Vec3 v = random_unit_vector(rng);
    const Vec4 qconj(q[0], -q[1], -q[2], -q[3]);
    const Vec4 rotated = quaternion_product(quaternion_product(q, Vec4(0, v.x(), v.y(), v.z())), qconj);
    CHECK(std::abs(rotated[0]) < 1e-15);
    CHECK((rotated.tail<3>() - quaternion_to_matrix(q) * v).norm() < 1e-14);
  }
  // i j = k for the units.
  CHECK((quaternion_product(Vec4(0, 1, 0, 0), Vec4(0, 0, 1, 0)) - Vec4(0, 0, 0, 1)).norm() == 0.0);
}

TEST_CASE("so3: z-x-z Euler angles give the classical quaternion of Goldstein's relation") {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> ang(-kPi, kPi);
  std::uniform_real_distribution<double> tilt(0.0, kPi);
  for (int t = 0; t < 500; ++t) {
    const double phi = ang(rng), theta = tilt(rng), psi = ang(rng);
    const Mat3 R = axis_rotation(2, phi) * axis_rotation(0, theta) * axis_rotation(2, psi);
    const Vec4 truth(std::cos(theta / 2) * std::cos((phi + psi) / 2), std::sin(theta / 2) * std::cos((phi - psi) / 2),
                     std::sin(theta / 2) * std::sin((phi - psi) / 2), std::cos(theta / 2) * std::sin((phi + psi) / 2));
    const Vec4 q = matrix_to_quaternion(R);
    CHECK(std::min((q - truth).norm(), (q + truth).norm()) < 1e-14);
    CHECK(max_abs(quaternion_to_matrix(truth) - R) < 1e-14);
  }
}

TEST_CASE("so3: axis-angle round trip is accurate near 0 and near pi") {
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> mid(1e-3, kPi - 1e-3);
  for (int t = 0; t < 300; ++t) {
    const Vec3 n = random_unit_vector(rng);
    for (double angle : {1e-12, 1e-9, 1e-6, mid(rng), 1.0, 2.0, kPi - 1e-6, kPi - 1e-9}) {
      CAPTURE(angle);
      const Mat3 R = axis_angle_to_matrix(n, angle);
      CHECK(max_abs(R - Eigen::AngleAxisd(angle, n).toRotationMatrix()) < 1e-15 * 8);
      const Vec3 rv = matrix_to_rotation_vector(R);
      // Relative accuracy of the angle at both ends.
      CHECK(std::abs(rv.norm() - angle) < 1e-14 * angle + 1e-15 * 4);
      CHECK((rv - angle * n).norm() < 1e-14 * angle + 1e-15 * 4);
      // Negative angle: the same rotation as +angle about -n.
      const Vec3 rv_neg = matrix_to_rotation_vector(axis_angle_to_matrix(n, -angle));
      CHECK((rv_neg + angle * n).norm() < 1e-14 * angle + 1e-15 * 4);
    }
    // Exactly pi: the axis is defined only up to sign.
    const Vec3 rv = matrix_to_rotation_vector(axis_angle_to_matrix(n, kPi));
    CHECK(std::min((rv - kPi * n).norm(), (rv + kPi * n).norm()) < 1e-13);
    // Beyond pi: angle 2 pi - x about -n.
    const Vec3 rv2 = matrix_to_rotation_vector(axis_angle_to_matrix(n, 4.0));
    CHECK((rv2 + (2 * kPi - 4.0) * n).norm() < 1e-14);
  }
  CHECK(matrix_to_rotation_vector(Mat3::Identity()).norm() == 0.0);
}

TEST_CASE("so3: geodesic rotation distance is the angle of the relative rotation, even for tiny angles") {
  std::mt19937 rng(77);
  for (int t = 0; t < 300; ++t) {
    const Vec4 q1 = random_unit_quaternion(rng);
    const Mat3 R1 = quaternion_to_matrix(q1);
    const Vec3 n = random_unit_vector(rng);
    for (double angle : {0.0, 1e-10, 1e-7, 0.5, 2.0, kPi - 1e-7, kPi}) {
      CAPTURE(angle);
      // Relative rotation in the body frame and in the space frame: same distance.
      const Mat3 Rrel = Eigen::AngleAxisd(angle, n).toRotationMatrix();
      const Mat3 R2 = R1 * Rrel;
      const Mat3 R3 = Rrel * R1;
      // Absolute accuracy of a few ulps of the matrix entries: an acos of the
      // trace would lose everything below ~1e-8 rad.
      const double tol = 1e-14;
      CHECK(std::abs(rotation_distance(R1, R2) - angle) < tol);
      CHECK(std::abs(rotation_distance(R2, R1) - angle) < tol);
      CHECK(std::abs(rotation_distance(R1, R3) - angle) < tol);
      // Quaternions: independent of either sign.
      const Vec4 qrel(std::cos(angle / 2), std::sin(angle / 2) * n.x(), std::sin(angle / 2) * n.y(),
                      std::sin(angle / 2) * n.z());
      const Vec4 q2 = quaternion_product(q1, qrel);
      for (double s1 : {1.0, -1.0}) {
        for (double s2 : {1.0, -1.0}) {
          CHECK(std::abs(quaternion_distance(s1 * q1, s2 * q2) - angle) < tol);
        }
      }
    }
  }
}

TEST_CASE("so3: nearest rotation is the orthogonal polar factor with det +1") {
  std::mt19937 rng(4242);
  std::uniform_real_distribution<double> noise(-1.0, 1.0);
  for (int t = 0; t < 200; ++t) {
    const Mat3 R = quaternion_to_matrix(random_unit_quaternion(rng));
    // M = R S with S symmetric positive definite has polar factor exactly R.
    Mat3 A;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) A(r, c) = noise(rng);
    const Mat3 S = Mat3::Identity() + 0.2 * (A + A.transpose()) / 2.0 + 0.5 * A * A.transpose();
    REQUIRE(Eigen::SelfAdjointEigenSolver<Mat3>(S).eigenvalues().minCoeff() > 0.0);
    CHECK(max_abs(nearest_rotation(R * S) - R) < 1e-13);

    // A small arbitrary perturbation: orthogonal, det +1, and close to R.
    const Mat3 M = R + 1e-6 * A;
    const Mat3 Q = nearest_rotation(M);
    CHECK(max_abs(Q.transpose() * Q - Mat3::Identity()) < 1e-14);
    CHECK(Q.determinant() == doctest::Approx(1.0).epsilon(1e-14));
    CHECK(rotation_distance(Q, R) < 3e-6);
    // It is at least as close to M as R is (Frobenius).
    CHECK((Q - M).norm() <= (R - M).norm() + 1e-15);

    // A matrix containing a reflection: R diag(3, 2, -1); the nearest proper
    // rotation flips the smallest singular direction and is R itself.
    const Mat3 Mref = R * Vec3(3.0, 2.0, -1.0).asDiagonal();
    const Mat3 Qref = nearest_rotation(Mref);
    CHECK(Qref.determinant() == doctest::Approx(1.0).epsilon(1e-14));
    CHECK(max_abs(Qref - R) < 1e-13);
  }
  // A pure reflection of the identity still gives a proper rotation.
  const Mat3 Qm = nearest_rotation(Vec3(1.0, 1.0, -1.0).asDiagonal());
  CHECK(Qm.determinant() == doctest::Approx(1.0));
  CHECK(max_abs(Qm.transpose() * Qm - Mat3::Identity()) < 1e-14);
}

TEST_SUITE_END();
