// Euler angles in the twelve sequences: composition, inverse, charts and the
// angular-velocity map, checked against Eigen's angle-axis rotations and
// against finite differences of the rotation itself.
#include <doctest/doctest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>

#include "rigidae/so3/euler_sequence.hpp"
#include "rigidae/so3/rotation.hpp"

TEST_SUITE_BEGIN("unit");

using namespace rigidae;
using namespace rigidae::so3;

namespace {

constexpr double kPi = std::numbers::pi;

double max_abs(const Mat3& M) { return M.cwiseAbs().maxCoeff(); }

// Independent truth: Eigen's rotation about a coordinate axis.
Mat3 eigen_axis(int axis, double angle) { return Eigen::AngleAxisd(angle, Vec3::Unit(axis)).toRotationMatrix(); }

// Random angles inside the chart of `seq`, at least `margin` from its singularity.
Vec3 random_regular_angles(const EulerSequence& seq, std::mt19937& rng, double margin) {
  std::uniform_real_distribution<double> ac(-kPi + 1e-6, kPi - 1e-6);
  std::uniform_real_distribution<double> bp(margin, kPi - margin);
  std::uniform_real_distribution<double> bt(-kPi / 2 + margin, kPi / 2 - margin);
  return Vec3(ac(rng), seq.proper() ? bp(rng) : bt(rng), ac(rng));
}

Mat3 random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  return Eigen::Quaterniond(Eigen::Vector4d(n(rng), n(rng), n(rng), n(rng)).normalized()).toRotationMatrix();
}

}  // namespace

TEST_CASE("Euler sequences: the twelve are listed in the documented order with their names") {
  const auto& all = all_euler_sequences();
  const char* names[12] = {"xyz", "xzy", "yxz", "yzx", "zxy", "zyx", "xyx", "xzx", "yxy", "yzy", "zxz", "zyz"};
  for (int n = 0; n < 12; ++n) {
    CHECK(all[n].name() == names[n]);
    CHECK(all[n].proper() == (n >= 6));
    CHECK(parse_euler_sequence(names[n], false) == all[n]);
  }
  CHECK(EulerSequence{}.name() == "zxz");
}

TEST_CASE("Euler sequences: parsing is case-insensitive and rejects invalid letters naming what is valid") {
  CHECK(parse_euler_sequence("ZYX", false).name() == "zyx");
  CHECK(parse_euler_sequence("zXz", false).name() == "zxz");
  for (const char* bad : {"", "xy", "xyzx", "xxy", "xyy", "zzz", "abc", "xwz", "x y", "zx1"}) {
    CAPTURE(bad);
    CHECK_THROWS_AS(parse_euler_sequence(bad, false), std::invalid_argument);
    try {
      parse_euler_sequence(bad, true);
      FAIL("no exception");
    } catch (const std::invalid_argument& e) {
      const std::string msg = e.what();
      CHECK(msg.find("x, y, z") != std::string::npos);
      CHECK(msg.find("zxz") != std::string::npos);
      CHECK(msg.find("zyx") != std::string::npos);
    }
  }
  // Angles are left alone on failure and for intrinsic input.
  Vec3 angles(0.1, 0.2, 0.3);
  CHECK(parse_euler_sequence("xyz", false, &angles).name() == "xyz");
  CHECK(angles == Vec3(0.1, 0.2, 0.3));
}

TEST_CASE("Euler sequences: intrinsic angles compose as R_i(a) R_j(b) R_k(c) about body axes") {
  std::mt19937 rng(1);
  for (const EulerSequence& seq : all_euler_sequences()) {
    for (int t = 0; t < 50; ++t) {
      const Vec3 e = random_regular_angles(seq, rng, 0.0);
      const Mat3 truth = eigen_axis(seq.axes[0], e[0]) * eigen_axis(seq.axes[1], e[1]) * eigen_axis(seq.axes[2], e[2]);
      CHECK(max_abs(euler_to_matrix(seq, e) - truth) < 1e-15 * 8);
    }
  }
  // Yaw-pitch-roll (z-y-x): a pure yaw of 90 degrees points the body x axis along space y.
  const Mat3 R = euler_to_matrix(parse_euler_sequence("zyx", false), Vec3(kPi / 2, 0, 0));
  CHECK((R.col(0) - Vec3::UnitY()).norm() < 1e-15);
}

TEST_CASE("Euler sequences: extrinsic x-y-z(a, b, c) is Rz(c) Ry(b) Rx(a), the intrinsic z-y-x sequence") {
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(-kPi, kPi);
  for (int t = 0; t < 100; ++t) {
    const Vec3 given(u(rng), u(rng) / 2, u(rng));
    Vec3 angles = given;
    const EulerSequence seq = parse_euler_sequence("xyz", true, &angles);
    CHECK(seq.name() == "zyx");
    CHECK(angles == Vec3(given[2], given[1], given[0]));
    const Mat3 truth = eigen_axis(2, given[2]) * eigen_axis(1, given[1]) * eigen_axis(0, given[0]);
    CHECK(max_abs(euler_to_matrix(seq, angles) - truth) < 1e-15 * 8);

    // A proper sequence keeps its name but still reverses the angles.
    Vec3 zxz = given;
    const EulerSequence pseq = parse_euler_sequence("ZXZ", true, &zxz);
    CHECK(pseq.name() == "zxz");
    const Mat3 ptruth = eigen_axis(2, given[2]) * eigen_axis(0, given[1]) * eigen_axis(2, given[0]);
    CHECK(max_abs(euler_to_matrix(pseq, zxz) - ptruth) < 1e-15 * 8);
  }
  CHECK(parse_euler_sequence("yzx", true).name() == "xzy");
}

TEST_CASE("Euler angles round-trip through the rotation matrix for all twelve sequences") {
  std::mt19937 rng(20240601);
  for (const EulerSequence& seq : all_euler_sequences()) {
    CAPTURE(seq.name());
    for (int t = 0; t < 500; ++t) {
      // Angles -> matrix -> angles recovers the angles inside the chart.
      const Vec3 e = random_regular_angles(seq, rng, 1e-2);
      const Mat3 R = euler_to_matrix(seq, e);
      const Vec3 back = matrix_to_euler(seq, R);
      CAPTURE(e.transpose());
      CAPTURE(back.transpose());
      CHECK((back - e).cwiseAbs().maxCoeff() < 1e-12);
      CHECK(max_abs(euler_to_matrix(seq, back) - R) < 1e-14);

      // Matrix -> angles -> matrix for arbitrary rotations, angles in range.
      const Mat3 Q = random_rotation(rng);
      const Vec3 a = matrix_to_euler(seq, Q);
      CHECK(max_abs(euler_to_matrix(seq, a) - Q) < 1e-14);
      CHECK(a[0] > -kPi);
      CHECK(a[0] <= kPi);
      CHECK(a[2] > -kPi);
      CHECK(a[2] <= kPi);
      if (seq.proper()) {
        CHECK(a[1] >= 0.0);
        CHECK(a[1] <= kPi);
      } else {
        CHECK(a[1] >= -kPi / 2);
        CHECK(a[1] <= kPi / 2);
      }
    }
  }
}

TEST_CASE("Euler angles: the matrix round trip holds at and near gimbal lock for all twelve sequences") {
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> ac(-kPi, kPi);
  for (const EulerSequence& seq : all_euler_sequences()) {
    CAPTURE(seq.name());
    // Singular middle angles of the chart: 0 and pi (proper), +-pi/2 (Tait-Bryan).
    const double singular[2] = {seq.proper() ? 0.0 : -kPi / 2, seq.proper() ? kPi : kPi / 2};
    for (double bs : singular) {
      const double inward = (bs == singular[0]) ? 1.0 : -1.0;
      for (double delta : {0.0, 1e-15, 1e-12, 1e-9, 1e-7, 1e-5, 1e-3}) {
        for (int t = 0; t < 50; ++t) {
          CAPTURE(bs);
          CAPTURE(delta);
          const Vec3 e(ac(rng), bs + inward * delta, ac(rng));
          const Mat3 R = euler_to_matrix(seq, e);
          const Vec3 back = matrix_to_euler(seq, R);
          CAPTURE(back.transpose());
          CHECK(max_abs(euler_to_matrix(seq, back) - R) < 1e-13);
          // The middle angle is always well determined.
          CHECK(std::abs(back[1] - e[1]) < 1e-13);
          if (delta == 0.0) {
            // Exactly at the singularity only one combination of a and c is
            // defined; the decomposition reports c = 0.
            CHECK(back[2] == 0.0);
            CHECK(singularity_margin(seq, back) < 1e-15);
          }
          if (delta >= 1e-3) CHECK((back - e).cwiseAbs().maxCoeff() < 1e-11);
        }
      }
    }
  }
}

TEST_CASE("Euler rate matrix B maps angle rates to body angular velocity, hat(omega_B) = R^T dR/dt") {
  std::mt19937 rng(3);
  std::normal_distribution<double> n(0.0, 1.0);
  const double h = 1e-5;
  for (const EulerSequence& seq : all_euler_sequences()) {
    CAPTURE(seq.name());
    for (int t = 0; t < 50; ++t) {
      const Vec3 e = random_regular_angles(seq, rng, 0.0);
      const Vec3 rates(n(rng), n(rng), n(rng));
      const Mat3 R = euler_to_matrix(seq, e);
      const Mat3 dR = (euler_to_matrix(seq, e + h * rates) - euler_to_matrix(seq, e - h * rates)) / (2 * h);
      const Mat3 W = R.transpose() * dR;
      // Central differences err by ~h^2 |rates|^3 / 6.
      const double tol = 1e-9 * (1 + rates.squaredNorm() * rates.norm());
      CHECK(max_abs(W + W.transpose()) < tol);  // skew, as it must be
      const Vec3 omega_B = euler_rate_matrix(seq, e) * rates;
      CHECK((vee(W) - omega_B).norm() < tol);
      // Space angular velocity: dR/dt R^T = hat(R omega_B).
      CHECK((vee(dR * R.transpose()) - R * omega_B).norm() < tol);
    }
  }
}

TEST_CASE("Euler rate bias is dB/dt times the rates, so d(omega_B)/dt = B angles'' + bias") {
  std::mt19937 rng(4);
  std::normal_distribution<double> n(0.0, 1.0);
  const double h = 1e-5;
  for (const EulerSequence& seq : all_euler_sequences()) {
    CAPTURE(seq.name());
    for (int t = 0; t < 50; ++t) {
      const Vec3 e = random_regular_angles(seq, rng, 0.0);
      const Vec3 rates(n(rng), n(rng), n(rng));
      const Vec3 acc(n(rng), n(rng), n(rng));
      const Vec3 bias = euler_rate_bias(seq, e, rates);
      // d/dt of B(angles + t rates) * rates.
      const Vec3 fd =
          (euler_rate_matrix(seq, e + h * rates) - euler_rate_matrix(seq, e - h * rates)) * rates / (2 * h);
      CHECK((bias - fd).norm() < 1e-8 * (1 + rates.squaredNorm() * rates.norm()));
      // Along angles(t) = e + rates t + acc t^2 / 2, omega_B(t) comes from the
      // rotation alone: hat(omega_B) = R^T dR/dt. Differentiate it once more.
      const auto angles_at = [&](double s) -> Vec3 { return e + s * rates + 0.5 * s * s * acc; };
      const auto omega_at = [&](double s) -> Vec3 {
        const double k = 1e-4;
        const Mat3 R = euler_to_matrix(seq, angles_at(s));
        // Fourth-order central difference of R in time.
        const Mat3 dR = (-euler_to_matrix(seq, angles_at(s + 2 * k)) + 8 * euler_to_matrix(seq, angles_at(s + k)) -
                         8 * euler_to_matrix(seq, angles_at(s - k)) + euler_to_matrix(seq, angles_at(s - 2 * k))) /
                        (12 * k);
        return vee(R.transpose() * dR);
      };
      const double H = 1e-3;
      const Vec3 domega = (omega_at(H) - omega_at(-H)) / (2 * H);
      const Vec3 predicted = euler_rate_matrix(seq, e) * acc + bias;
      CHECK((domega - predicted).norm() < 1e-5 * (1 + rates.squaredNorm() * rates.norm() + acc.norm()));
    }
  }
}

TEST_CASE("Euler singularity margin is |det B|: |sin b| for proper, |cos b| for Tait-Bryan sequences") {
  std::mt19937 rng(6);
  for (const EulerSequence& seq : all_euler_sequences()) {
    CAPTURE(seq.name());
    for (int t = 0; t < 100; ++t) {
      const Vec3 e = random_regular_angles(seq, rng, 0.0);
      const double det = euler_rate_matrix(seq, e).determinant();
      CHECK(singularity_margin(seq, e) == doctest::Approx(std::abs(det)).epsilon(1e-13));
      CHECK(singularity_margin(seq, e) ==
            doctest::Approx(seq.proper() ? std::abs(std::sin(e[1])) : std::abs(std::cos(e[1]))));
    }
    const double lock = seq.proper() ? 0.0 : kPi / 2;
    const double free = seq.proper() ? kPi / 2 : 0.0;
    CHECK(singularity_margin(seq, Vec3(0.3, lock, -0.4)) < 1e-15);
    CHECK(std::abs(euler_rate_matrix(seq, Vec3(0.3, lock, -0.4)).determinant()) < 1e-15);
    CHECK(singularity_margin(seq, Vec3(0.3, free, -0.4)) == 1.0);
  }
}

TEST_CASE("Euler sequences: the most regular sequence is the one farthest from gimbal lock") {
  const auto& all = all_euler_sequences();
  // Identity: every Tait-Bryan sequence has b = 0 (margin 1), every proper
  // one is locked; the tie goes to the first, x-y-z.
  const EulerSequence at_identity = most_regular_sequence(Mat3::Identity());
  CHECK(at_identity.name() == "xyz");
  CHECK(singularity_margin(at_identity, matrix_to_euler(at_identity, Mat3::Identity())) == 1.0);

  // A quarter turn about y locks x-y-z and z-y-x (b = +-pi/2); x-z-y is the
  // first sequence left with b = 0.
  const Mat3 Ry = axis_rotation(1, kPi / 2);
  CHECK(singularity_margin(all[0], matrix_to_euler(all[0], Ry)) < 1e-15);
  CHECK(most_regular_sequence(Ry).name() == "xzy");

  // Body z axis horizontal, at 45 degrees to every coordinate plane it can be:
  // R = Rz(pi/4) Rx(pi/2) Rz(pi/4). The best Tait-Bryan margin is only
  // sqrt(3)/2, while z-x-z sees b = pi/2 exactly (margin 1).
  const Mat3 R = axis_rotation(2, kPi / 4) * axis_rotation(0, kPi / 2) * axis_rotation(2, kPi / 4);
  const EulerSequence best = most_regular_sequence(R);
  CHECK(best.name() == "zxz");
  const Vec3 e = matrix_to_euler(best, R);
  CHECK((e - Vec3(kPi / 4, kPi / 2, kPi / 4)).norm() < 1e-14);
  CHECK(singularity_margin(best, e) == doctest::Approx(1.0).epsilon(1e-15));
  for (const EulerSequence& seq : all) {
    if (!seq.proper()) CHECK(singularity_margin(seq, matrix_to_euler(seq, R)) <= std::sqrt(3.0) / 2 + 1e-14);
  }

  // In general the chosen margin is the maximum over all twelve.
  std::mt19937 rng(9);
  for (int t = 0; t < 200; ++t) {
    const Mat3 Q = random_rotation(rng);
    const EulerSequence s = most_regular_sequence(Q);
    const double m = singularity_margin(s, matrix_to_euler(s, Q));
    for (const EulerSequence& other : all) {
      CHECK(m >= singularity_margin(other, matrix_to_euler(other, Q)) - 1e-12);
    }
    // No rotation is far from every chart: a unit column has an entry with
    // square <= 1/3, and that entry's sequence has margin sqrt(1 - entry^2).
    CHECK(m >= std::sqrt(2.0 / 3.0) - 1e-12);
  }
}

TEST_SUITE_END();
