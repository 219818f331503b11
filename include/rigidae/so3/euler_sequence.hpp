#pragma once
// Euler angles in any of the twelve sequences.
//
// Internally every sequence is intrinsic: angles (a, b, c) about body axes
// (i, j, k) compose as R_WB = R_i(a) R_j(b) R_k(c). An extrinsic sequence
// (rotations about fixed space axes, first i then j then k) equals the
// intrinsic sequence (k, j, i) with the angles reversed; the conversion
// happens once, at the input boundary (`parse_euler_sequence`).
//
// Charts: a proper sequence (i == k, e.g. z-x-z) is singular where
// sin(b) = 0; a Tait-Bryan sequence (all distinct, e.g. z-y-x) where
// cos(b) = 0. `singularity_margin` is |det B| for the rate matrix B below,
// which is exactly |sin b| or |cos b|: 1 far from gimbal lock, 0 at it.
#include <array>
#include <string>
#include <string_view>

#include "rigidae/core/types.hpp"

namespace rigidae::so3 {

struct EulerSequence {
  std::array<int, 3> axes{2, 0, 2};  // intrinsic body axes, 0 = x, 1 = y, 2 = z

  bool proper() const { return axes[0] == axes[2]; }
  // Intrinsic name such as "zxz" or "zyx".
  std::string name() const;
  friend bool operator==(const EulerSequence& a, const EulerSequence& b) { return a.axes == b.axes; }
};

// The twelve intrinsic sequences, a fixed order: the six Tait-Bryan ones
// (xyz, xzy, yxz, yzx, zxy, zyx) then the six proper ones
// (xyx, xzx, yxy, yzy, zxz, zyz).
const std::array<EulerSequence, 12>& all_euler_sequences();

// Parses three letters from {x, y, z} (case-insensitive, e.g. "zxz", "ZYX")
// with consecutive axes distinct. `extrinsic` means rotations about fixed
// space axes in the order written; the result is the equivalent intrinsic
// sequence. If `angles` is non-null it is reordered to match.
// Throws std::invalid_argument naming what would be valid.
EulerSequence parse_euler_sequence(std::string_view letters, bool extrinsic, Vec3* angles = nullptr);

// R_WB = R_i(a) R_j(b) R_k(c).
Mat3 euler_to_matrix(const EulerSequence& seq, const Vec3& angles);
// Angles of a rotation: a, c in (-pi, pi]; b in [0, pi] (proper) or
// [-pi/2, pi/2] (Tait-Bryan). At the singularity a valid decomposition
// with c = 0 is returned.
Vec3 matrix_to_euler(const EulerSequence& seq, const Mat3& R);

// B(angles) with omega_B = B d(angles)/dt; columns
// (R_k(c)^T R_j(b)^T e_i, R_k(c)^T e_j, e_k).
Mat3 euler_rate_matrix(const EulerSequence& seq, const Vec3& angles);
// d/dt(B) * rates: the part of d(omega_B)/dt that does not involve the
// angular accelerations, so d(omega_B)/dt = B angles'' + euler_rate_bias(...).
Vec3 euler_rate_bias(const EulerSequence& seq, const Vec3& angles, const Vec3& rates);
// |det B|: |sin b| for proper sequences, |cos b| for Tait-Bryan ones.
double singularity_margin(const EulerSequence& seq, const Vec3& angles);

// The sequence, among all twelve, whose decomposition of R lies farthest from
// its singularity (ties broken by the order of all_euler_sequences()).
EulerSequence most_regular_sequence(const Mat3& R);

}  // namespace rigidae::so3
