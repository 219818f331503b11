#include "rigidae/so3/euler_sequence.hpp"

#include <cctype>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "rigidae/so3/rotation.hpp"

namespace rigidae::so3 {

namespace {

constexpr double kPi = std::numbers::pi;

// Below this value of sin(b/2), cos(b/2) (proper) or of the corresponding
// half-angle factor (Tait-Bryan) the decomposition is treated as singular and
// c is set to 0. Forcing c = 0 moves the matrix by at most ~4 times this, so
// it only catches round-off-level distances from the singularity.
constexpr double kSingularHalfAngle = 1e-14;

constexpr char kAxisLetters[3] = {'x', 'y', 'z'};

// Levi-Civita symbol of three distinct axes: +1 for a cyclic order of (x, y, z).
int parity(int i, int j) { return ((j - i + 3) % 3 == 1) ? 1 : -1; }

// Wraps an angle in (-3pi, 3pi) into (-pi, pi]; a = tp + tm lies in (-2pi, 2pi].
double wrap(double x) {
  if (x > kPi) x -= 2.0 * kPi;
  if (x <= -kPi) x += 2.0 * kPi;
  return x;
}

std::string valid_sequence_list() {
  std::string s;
  for (const EulerSequence& seq : all_euler_sequences()) {
    if (!s.empty()) s += ", ";
    s += seq.name();
  }
  return s;
}

}  // namespace

std::string EulerSequence::name() const {
  std::string s(3, '?');
  for (int n = 0; n < 3; ++n) {
    if (axes[n] >= 0 && axes[n] <= 2) s[n] = kAxisLetters[axes[n]];
  }
  return s;
}

const std::array<EulerSequence, 12>& all_euler_sequences() {
  static const std::array<EulerSequence, 12> kAll = {{
      {{0, 1, 2}}, {{0, 2, 1}}, {{1, 0, 2}}, {{1, 2, 0}}, {{2, 0, 1}}, {{2, 1, 0}},  // Tait-Bryan
      {{0, 1, 0}}, {{0, 2, 0}}, {{1, 0, 1}}, {{1, 2, 1}}, {{2, 0, 2}}, {{2, 1, 2}},  // proper
  }};
  return kAll;
}

EulerSequence parse_euler_sequence(std::string_view letters, bool extrinsic, Vec3* angles) {
  const auto fail = [&]() -> EulerSequence {
    throw std::invalid_argument(
        "invalid Euler sequence \"" + std::string(letters) +
        "\": expected three letters from x, y, z with consecutive letters distinct "
        "(e.g. \"zxz\", \"zyx\"); valid sequences: " +
        valid_sequence_list());
  };
  if (letters.size() != 3) return fail();
  EulerSequence seq;
  for (int n = 0; n < 3; ++n) {
    const char ch = static_cast<char>(std::tolower(static_cast<unsigned char>(letters[n])));
    if (ch < 'x' || ch > 'z') return fail();
    seq.axes[n] = ch - 'x';
  }
  if (seq.axes[0] == seq.axes[1] || seq.axes[1] == seq.axes[2]) return fail();
  if (extrinsic) {
    // Space-fixed i, j, k with angles (a, b, c): R = R_k(c) R_j(b) R_i(a),
    // i.e. the intrinsic sequence (k, j, i) with angles (c, b, a).
    std::swap(seq.axes[0], seq.axes[2]);
    if (angles != nullptr) std::swap((*angles)[0], (*angles)[2]);
  }
  return seq;
}

Mat3 euler_to_matrix(const EulerSequence& seq, const Vec3& angles) {
  return axis_rotation(seq.axes[0], angles[0]) * axis_rotation(seq.axes[1], angles[1]) *
         axis_rotation(seq.axes[2], angles[2]);
}

Vec3 matrix_to_euler(const EulerSequence& seq, const Mat3& R) {
  // Through the quaternion q = q_i(a) q_j(b) q_k(c) (one generic formula per
  // kind, indexed by axes and the parity eps). Both kinds reduce to
  //   (P0, P1) = rho_p (cos tp, sin tp),  (M0, M1) = rho_m (cos tm, sin tm)
  // with tp = (a + c)/2, tm = (a - c)/2 and (rho_p, rho_m) proportional to
  // the cosine and sine of a half angle that fixes b. Computing tp and tm
  // separately with atan2 keeps R -> angles -> R accurate arbitrarily close
  // to the singularity: the badly determined one is multiplied by its small
  // rho when the matrix is rebuilt.
  const Vec4 q = matrix_to_quaternion(R);
  const int i = seq.axes[0];
  const int j = seq.axes[1];
  const double w = q[0];
  const double qi = q[1 + i];
  const double qj = q[1 + j];
  double P0, P1, M0, M1, b;
  if (seq.proper()) {
    // m = the third axis, eps = eps_{ijm}:
    //   w  = cos(b/2) cos tp,   q_i = cos(b/2) sin tp,
    //   q_j = sin(b/2) cos tm,  q_m = eps sin(b/2) sin tm.
    const int m = 3 - i - j;
    const double eps = parity(i, j);
    P0 = w;
    P1 = qi;
    M0 = qj;
    M1 = eps * q[1 + m];
  } else {
    // k = third axis, eps = eps_{ijk}, beta = eps b/2 + pi/4 in [0, pi/2]:
    //   w + eps q_j = sqrt2 sin(beta) cos tp,  q_i + q_k = sqrt2 sin(beta) sin tp,
    //   w - eps q_j = sqrt2 cos(beta) cos tm,  q_i - q_k = sqrt2 cos(beta) sin tm.
    const int k = seq.axes[2];
    const double eps = parity(i, j);
    const double qk = q[1 + k];
    P0 = w + eps * qj;
    P1 = qi + qk;
    M0 = w - eps * qj;
    M1 = qi - qk;
  }
  const double rho_p = std::hypot(P0, P1);
  const double rho_m = std::hypot(M0, M1);
  const double half = std::atan2(rho_m, rho_p);  // in [0, pi/2]
  const double tp = std::atan2(P1, P0);
  const double tm = std::atan2(M1, M0);
  double a, c;
  // rho_p^2 + rho_m^2 is 1 (proper) or 2 (Tait-Bryan).
  const double scale = seq.proper() ? 1.0 : std::numbers::sqrt2;
  if (rho_m <= kSingularHalfAngle * scale) {
    a = 2.0 * tp;  // tm undefined: only a + c is determined
    c = 0.0;
  } else if (rho_p <= kSingularHalfAngle * scale) {
    a = 2.0 * tm;  // tp undefined: only a - c is determined
    c = 0.0;
  } else {
    a = tp + tm;
    c = tp - tm;
  }
  if (seq.proper()) {
    b = 2.0 * half;  // [0, pi]
  } else {
    // Here the half angle is pi/2 - beta = pi/4 - eps b/2.
    const double eps = parity(i, j);
    b = eps * (kPi / 2.0 - 2.0 * half);  // [-pi/2, pi/2]
  }
  return Vec3(wrap(a), b, wrap(c));
}

Mat3 euler_rate_matrix(const EulerSequence& seq, const Vec3& angles) {
  const Mat3 RkT = axis_rotation(seq.axes[2], angles[2]).transpose();
  const Mat3 RjT = axis_rotation(seq.axes[1], angles[1]).transpose();
  Mat3 B;
  B.col(0) = RkT * RjT.col(seq.axes[0]);
  B.col(1) = RkT.col(seq.axes[1]);
  B.col(2) = Vec3::Unit(seq.axes[2]);
  return B;
}

Vec3 euler_rate_bias(const EulerSequence& seq, const Vec3& angles, const Vec3& rates) {
  // With col1 = Rk^T Rj^T e_i, col2 = Rk^T e_j and d/dt Rk^T = -c' hat(e_k) Rk^T,
  // d/dt Rj^T = -b' hat(e_j) Rj^T:
  //   d col1/dt = -c' e_k x col1 - b' Rk^T (e_j x Rj^T e_i) = -c' e_k x col1 - b' col2 x col1,
  //   d col2/dt = -c' e_k x col2,
  // so dB/dt rates = a' dcol1 + b' dcol2 = (a' col1 + b' col2) x c' e_k + a' b' col1 x col2.
  const Mat3 B = euler_rate_matrix(seq, angles);
  const Vec3 col1 = B.col(0);
  const Vec3 col2 = B.col(1);
  const Vec3 ek = B.col(2);
  const Vec3 partial = rates[0] * col1 + rates[1] * col2;
  return partial.cross(rates[2] * ek) + (rates[0] * rates[1]) * col1.cross(col2);
}

double singularity_margin(const EulerSequence& seq, const Vec3& angles) {
  return seq.proper() ? std::abs(std::sin(angles[1])) : std::abs(std::cos(angles[1]));
}

EulerSequence most_regular_sequence(const Mat3& R) {
  // A later sequence must beat the best so far by more than round-off, so
  // exact ties (e.g. every Tait-Bryan sequence at the identity) go to the
  // first one in all_euler_sequences().
  constexpr double kTie = 1e-12;
  const auto& all = all_euler_sequences();
  EulerSequence best = all[0];
  double best_margin = -1.0;
  for (const EulerSequence& seq : all) {
    const double m = singularity_margin(seq, matrix_to_euler(seq, R));
    if (m > best_margin + kTie) {
      best = seq;
      best_margin = m;
    }
  }
  return best;
}

}  // namespace rigidae::so3
