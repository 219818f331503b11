#pragma once
// Maps shared by the representation files (internal header).
#include <array>
#include <utility>

#include "rigidae/core/types.hpp"
#include "rigidae/so3/rotation.hpp"

namespace rigidae::coords {

// Quaternion kinematics, scalar first: q' = 1/2 L(q) omega_B with
// L(q) = [ -v^T ; w I + hat(v) ] (4x3); L^T L = |q|^2 I and L^T q = 0.
inline Eigen::Matrix<double, 4, 3> quaternion_rate_map(const Vec4& q) {
  Eigen::Matrix<double, 4, 3> L;
  L.row(0) = -q.tail<3>().transpose();
  L.bottomRows<3>() = q(0) * Mat3::Identity() + so3::hat(q.tail<3>());
  return L;
}

// R_k = dR/dq_k of the homogeneous quadratic R(q) = (w^2 - v.v) I + 2 v v^T
// + 2 w hat(v). Each R_k is linear in q, and R_k(e_m) = d^2 R/dq_k dq_m is
// symmetric in k and m.
inline std::array<Mat3, 4> quaternion_placement_partials(const Vec4& q) {
  const double w = q(0);
  const Vec3 v = q.tail<3>();
  std::array<Mat3, 4> Rk;
  Rk[0] = 2.0 * (w * Mat3::Identity() + so3::hat(v));
  for (int i = 0; i < 3; ++i) {
    const Vec3 e = Vec3::Unit(i);
    Rk[i + 1] = 2.0 * (-v(i) * Mat3::Identity() + e * v.transpose() + v * e.transpose() + w * so3::hat(e));
  }
  return Rk;
}

// Linear coordinates: the 9 entries of R, row by row: r = (row1, row2, row3).
inline Mat3 rows_to_matrix(const VecQ& r) {
  Mat3 R;
  R << r(0), r(1), r(2), r(3), r(4), r(5), r(6), r(7), r(8);
  return R;
}
inline void matrix_to_rows(const Mat3& R, VecQ& r) {
  r.resize(9);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r(3 * i + j) = R(i, j);
}

// The six independent orthonormality conditions c_j . c_k - delta_jk = 0,
// j <= k, on the columns c_j of R, in this order.
inline constexpr std::array<std::pair<int, int>, 6> kColumnPairs{{{0, 0}, {0, 1}, {0, 2}, {1, 1}, {1, 2}, {2, 2}}};

// Phi and Phi_q (6 x 9, with respect to r row by row).
inline void orthonormality_constraints(const Mat3& R, VecC& phi, MatCQ& phi_q) {
  phi.resize(6);
  phi_q.setZero(6, 9);
  for (int a = 0; a < 6; ++a) {
    const auto [j, k] = kColumnPairs[a];
    phi(a) = R.col(j).dot(R.col(k)) - (j == k ? 1.0 : 0.0);
    // d(c_j . c_k)/dR_il = delta_lj R_ik + delta_lk R_ij
    for (int i = 0; i < 3; ++i) {
      phi_q(a, 3 * i + j) += R(i, k);
      phi_q(a, 3 * i + k) += R(i, j);
    }
  }
}

// d(Phi_q^T m)/dr for multipliers m: Phi is quadratic, its Hessians are
// constant. Entry (3i+l, 3i'+l') is delta_ii' S_ll' with the symmetric
// S = sum_a m_a (e_j e_k^T + e_k e_j^T) over the pairs (j, k) of a.
inline void orthonormality_hessian_weighted(const VecC& m, MatQQ& out) {
  Mat3 S = Mat3::Zero();
  for (int a = 0; a < 6; ++a) {
    const auto [j, k] = kColumnPairs[a];
    S(j, k) += m(a);
    S(k, j) += m(a);
  }
  out.setZero(9, 9);
  for (int i = 0; i < 3; ++i) out.block<3, 3>(3 * i, 3 * i) = S;
}

// d(Phi_q w)/dr: Phi_q(R) w is bilinear and symmetric in (R, W), W the
// matrix of w, so its derivative in r is Phi_q(W).
inline void orthonormality_hessian_applied(const VecQ& w, MatCQ& out) {
  VecC phi_unused;
  orthonormality_constraints(rows_to_matrix(w), phi_unused, out);
}

// Acceleration level of the same conditions, with R'' left out:
// d^2/dt^2 (c_j . c_k) = G r'' + 2 (R'^T R')_jk, so gamma = -2 (R'^T R')_jk.
inline void orthonormality_gamma(const Mat3& Rdot, VecC& gamma) {
  gamma.resize(6);
  const Mat3 P = Rdot.transpose() * Rdot;
  for (int a = 0; a < 6; ++a) gamma(a) = -2.0 * P(kColumnPairs[a].first, kColumnPairs[a].second);
}

}  // namespace rigidae::coords
