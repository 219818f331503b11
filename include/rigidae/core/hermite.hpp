#pragma once
// Hermite interpolation through nodes with values and first derivatives
// (the bridge across singular poses, multibody/pose_bridge.cpp, extrapolates
// a mechanism's state with it).
//
// On K nodes t_0 < ... < t_{K-1} with values f_i and derivatives f'_i (each
// a vector, interpolated component by component) the interpolant p is the
// polynomial of degree 2K - 1 with p(t_i) = f_i, p'(t_i) = f'_i. Newton's
// form on the doubled nodes z = (t_0, t_0, t_1, t_1, ...):
//   p(t) = c_0 + (t - z_0)(c_1 + (t - z_1)(c_2 + ...)),
// c_k the divided differences f[z_0 .. z_k], where f[t_i, t_i] = f'_i.
// Error: f(t) - p(t) = f^(2K)(xi) / (2K)! prod_i (t - t_i)^2.
#include <vector>

#include <Eigen/Core>

namespace rigidae {

// The coefficients c (and doubled nodes z) of the interpolant of the first n
// components of f[i], fp[i] at nodes[i].
inline void hermite_coefficients(const std::vector<double>& nodes, const std::vector<const Eigen::VectorXd*>& f,
                                 const std::vector<const Eigen::VectorXd*>& fp, int n, std::vector<double>& z,
                                 std::vector<Eigen::VectorXd>& c) {
  const int m = 2 * static_cast<int>(nodes.size());
  z.resize(m);
  c.resize(m);
  for (int j = 0; j < m; ++j) {
    z[j] = nodes[j / 2];
    c[j] = f[j / 2]->head(n);
  }
  for (int k = 1; k < m; ++k)
    for (int j = m - 1; j >= k; --j)  // in place: c[j - 1] still holds level k - 1
      if (k == 1 && j % 2 == 1)
        c[j] = fp[j / 2]->head(n);  // a doubled node: the derivative
      else
        c[j] = (c[j] - c[j - 1]) / (z[j] - z[j - k]);
}

// p(t), and p'(t) when rate is given (Horner on Newton's form).
inline void hermite_value(const std::vector<double>& z, const std::vector<Eigen::VectorXd>& c, double t,
                          Eigen::VectorXd& value, Eigen::VectorXd* rate) {
  const int m = static_cast<int>(c.size());
  value = c[m - 1];
  if (rate) rate->setZero(value.size());
  for (int j = m - 2; j >= 0; --j) {
    if (rate) *rate = *rate * (t - z[j]) + value;
    value = value * (t - z[j]) + c[j];
  }
}

}  // namespace rigidae
