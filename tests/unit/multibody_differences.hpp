#pragma once
// The independent truth of the mechanisms' exact iteration matrices: central
// differences of the residual, Richardson-extrapolated, and the comparison
// row by row (rows are equations with their own units). Shared by
// test_multibody_jacobians.cpp, test_drivers.cpp and test_multibody_pivot.cpp.
#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <random>

#include "rigidae/multibody/multibody_problem.hpp"

namespace rigidae::test {

// Row-relative largest difference of A and B.
inline double row_relative_difference(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B) {
  double worst = 0.0;
  for (int i = 0; i < A.rows(); ++i) {
    const double scale = std::max({A.row(i).cwiseAbs().maxCoeff(), B.row(i).cwiseAbs().maxCoeff(), 1e-300});
    worst = std::max(worst, (A.row(i) - B.row(i)).cwiseAbs().maxCoeff() / scale);
  }
  return worst;
}

// dF/dy + cj dF/dy' by central differences, Richardson-extrapolated:
// (4 D(d/2) - D(d)) / 3, d = 1e-3 max(1, |y_j|) (as in test_jacobians.cpp).
inline Eigen::MatrixXd richardson_matrix(multibody::MultibodyProblem& p, double t, double cj,
                                         const Eigen::VectorXd& y, const Eigen::VectorXd& yp) {
  const int n = p.size();
  Eigen::MatrixXd J(n, n);
  Eigen::VectorXd Fp(n), Fm(n), yy = y, yyp = yp;
  const auto difference = [&](Eigen::VectorXd& x, int j, double d, bool in_yp) {
    const double xj = x(j);
    x(j) = xj + d;
    p.residual(t, in_yp ? y.data() : x.data(), in_yp ? x.data() : yp.data(), Fp.data());
    x(j) = xj - d;
    p.residual(t, in_yp ? y.data() : x.data(), in_yp ? x.data() : yp.data(), Fm.data());
    x(j) = xj;
    return Eigen::VectorXd((Fp - Fm) / (2.0 * d));
  };
  for (int j = 0; j < n; ++j) {
    const double d = 1e-3 * std::max(1.0, std::abs(y(j)));
    J.col(j) = (4.0 * difference(yy, j, 0.5 * d, false) - difference(yy, j, d, false)) / 3.0;
    const double dp = 1e-3 * std::max(1.0, std::abs(yp(j)));
    J.col(j) += cj * (4.0 * difference(yyp, j, 0.5 * dp, true) - difference(yyp, j, dp, true)) / 3.0;
  }
  return J;
}

// A state off the start: each entry of y and y' moved by up to 5 % of
// max(1, |entry|), uniformly at random (the matrices must hold off the
// constraint manifold too).
inline void perturb_state(std::mt19937& rng, Eigen::VectorXd& y, Eigen::VectorXd& yp) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (Eigen::Index i = 0; i < y.size(); ++i) {
    y(i) += 0.05 * u(rng) * std::max(1.0, std::abs(y(i)));
    yp(i) += 0.05 * u(rng) * std::max(1.0, std::abs(yp(i)));
  }
}

}  // namespace rigidae::test
