#include "rigidae/exact/jacobi_elliptic.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

namespace rigidae::exact {

SnCnDn jacobi_sn_cn_dn(double u, double m, double m1) {
  if (m <= 0.0) return {std::sin(u), std::cos(u), 1.0};
  if (m1 <= 0.0) {
    // k = 1: the separatrix limit, hyperbolic functions.
    const double sech = 1.0 / std::cosh(u);
    return {std::tanh(u), sech, sech};
  }
  // Descending Landen: the modulus k_{j+1} = (1 - k'_j)/(1 + k'_j) = k_j^2/(1 + k'_j)^2
  // falls quadratically; with v = u/(1 + k_{j+1}) (DLMF 22.7.1-3)
  //   sn(u, k_j) = (1 + k_{j+1}) sn(v)/(1 + k_{j+1} sn^2(v)),
  //   cn(u, k_j) = cn(v) dn(v)/(1 + k_{j+1} sn^2(v)),
  //   dn(u, k_j) = (1 - k_{j+1} sn^2(v))/(1 + k_{j+1} sn^2(v)).
  // Once k is below 1e-10, sn = sin and cn = cos to round-off. Going back up,
  // the ratio rho = cn/sn obeys rho_j = rho_{j+1} dn_{j+1}/(1 + k_{j+1}) and
  //   dn_j = (rho_{j+1}^2 + (1 - k_{j+1}))/(rho_{j+1}^2 + (1 + k_{j+1})),
  // a ratio of sums of positive terms (with 1 - k_{j+1} = 2 k'_j/(1 + k'_j)
  // formed without cancellation), so dn keeps its relative accuracy even
  // where it is as small as k'.
  constexpr int kMaxLevels = 16;
  std::array<double, kMaxLevels> k_next{};
  std::array<double, kMaxLevels> one_minus_k_next{};
  double k = std::sqrt(m);
  double kp = std::sqrt(m1);
  double v = u;
  int levels = 0;
  while (k > 1e-10 && levels < kMaxLevels) {
    const double kn = (k / (1.0 + kp)) * (k / (1.0 + kp));
    one_minus_k_next[levels] = 2.0 * kp / (1.0 + kp);
    kp = 2.0 * std::sqrt(kp) / (1.0 + kp);
    k = kn;
    k_next[levels] = kn;
    v /= 1.0 + kn;
    ++levels;
  }
  const double s = std::sin(v);
  const double c = std::cos(v);
  // sn(u) has the sign of sn at every level, hence of sin(v). For |s| this
  // small u itself is tiny and sn = u, cn = dn = 1 exactly in double.
  if (std::abs(s) < 1e-100) return {u, 1.0, 1.0};
  double dn = std::sqrt(1.0 - k * k * s * s);
  double rho = c / s;
  for (int j = levels - 1; j >= 0; --j) {
    const double r2 = rho * rho;
    const double dn_up = (r2 + one_minus_k_next[j]) / (r2 + 1.0 + k_next[j]);
    rho *= dn / (1.0 + k_next[j]);
    dn = dn_up;
  }
  const double sn = std::copysign(1.0 / std::sqrt(1.0 + rho * rho), s);
  return {sn, rho * sn, dn};
}

double complete_elliptic_k(double m1) {
  if (m1 <= 0.0) return std::numeric_limits<double>::infinity();
  // K = pi / (2 AGM(1, k')).
  double a = 1.0;
  double b = std::sqrt(m1);
  for (int i = 0; i < 64 && std::abs(a - b) > 1e-16 * a; ++i) {
    const double an = 0.5 * (a + b);
    b = std::sqrt(a * b);
    a = an;
  }
  return std::numbers::pi / (a + b);
}

double carlson_rf(double x, double y, double z) {
  // Duplication theorem R_F(x, y, z) = R_F((x+l)/4, (y+l)/4, (z+l)/4) with
  // l = sqrt(xy) + sqrt(yz) + sqrt(zx), until the three arguments agree to
  // 1e-3; then the symmetric-function series of DLMF 19.36.1, whose first
  // neglected terms are of order (1e-3)^6.
  for (int i = 0; i < 100; ++i) {
    const double mu = (x + y + z) / 3.0;
    const double dx = (mu - x) / mu;
    const double dy = (mu - y) / mu;
    const double dz = (mu - z) / mu;
    if (std::max({std::abs(dx), std::abs(dy), std::abs(dz)}) < 1e-3) {
      const double e2 = dx * dy - dz * dz;
      const double e3 = dx * dy * dz;
      return (1.0 - e2 / 10.0 + e3 / 14.0 + e2 * e2 / 24.0 - 3.0 * e2 * e3 / 44.0) / std::sqrt(mu);
    }
    const double sx = std::sqrt(x);
    const double sy = std::sqrt(y);
    const double sz = std::sqrt(z);
    const double l = sx * sy + sy * sz + sz * sx;
    x = 0.25 * (x + l);
    y = 0.25 * (y + l);
    z = 0.25 * (z + l);
  }
  return std::numeric_limits<double>::quiet_NaN();
}

double incomplete_elliptic_f(double phi, double m, double m1) {
  // F(phi) = sin(phi) R_F(cos^2, 1 - m sin^2, 1) on [-pi/2, pi/2], with
  // 1 - m sin^2 = cos^2 + m1 sin^2 near m = 1 (no cancellation); beyond,
  // F(phi + j pi) = F(phi) + 2 j K.
  const double j = std::round(phi / std::numbers::pi);
  const double r = phi - j * std::numbers::pi;
  const double s = std::sin(r);
  const double c = std::cos(r);
  const double delta2 = m < 0.5 ? 1.0 - m * s * s : c * c + m1 * s * s;
  const double f = s * carlson_rf(c * c, delta2, 1.0);
  return j == 0.0 ? f : f + 2.0 * j * complete_elliptic_k(m1);
}

double jacobi_argument(double sn, double cn, double dn, double m1) {
  const double f = sn * carlson_rf(cn * cn, dn * dn, 1.0);
  return cn >= 0.0 ? f : std::copysign(2.0 * complete_elliptic_k(m1), sn) - f;
}

}  // namespace rigidae::exact
