#include "central_differences.hpp"

#include <algorithm>
#include <cmath>

namespace rigidae::solver {

namespace {
constexpr double kCentralStep = 6.0e-6;  // ~ cbrt(machine epsilon)
}

CentralDifferences::CentralDifferences(int n) : y_(n), yp_(n), F_plus_(n), F_minus_(n), F_base_(n) {}

void CentralDifferences::base(DaeProblem& p, double t, const double* y, const double* yp) {
  const int n = static_cast<int>(y_.size());
  y_ = Eigen::Map<const Eigen::VectorXd>(y, n);
  yp_ = Eigen::Map<const Eigen::VectorXd>(yp, n);
  p.residual(t, y, yp, F_base_.data());
  evaluations_ += 3 * n + 1;
}

template <class Put, class Add>
void CentralDifferences::column(DaeProblem& p, int j, double t, double cj, const double* y, const double* yp,
                                Put put, Add add) {
  // d/dy_j by central differences.
  const double yj = y[j];
  const double dy = kCentralStep * std::max(1.0, std::abs(yj));
  y_(j) = yj + dy;
  p.residual(t, y_.data(), yp, F_plus_.data());
  y_(j) = yj - dy;
  p.residual(t, y_.data(), yp, F_minus_.data());
  y_(j) = yj;
  const double two_dy = 2.0 * dy;
  put([&](int r) { return (F_plus_(r) - F_minus_(r)) / two_dy; });
  // d/dy'_j exactly (F is affine in y'), by a difference with a large step.
  const double ypj = yp[j];
  const double dyp = std::max(1.0, std::abs(ypj));
  yp_(j) = ypj + dyp;
  p.residual(t, y, yp_.data(), F_plus_.data());
  yp_(j) = ypj;
  add([&](int r) { return cj * (F_plus_(r) - F_base_(r)) / dyp; });
}

void CentralDifferences::dense(DaeProblem& p, double t, double cj, const double* y, const double* yp, double* J) {
  const int n = static_cast<int>(y_.size());
  base(p, t, y, yp);
  for (int j = 0; j < n; ++j) {
    double* col = J + static_cast<std::ptrdiff_t>(j) * n;
    column(
        p, j, t, cj, y, yp, [&](auto value) { for (int r = 0; r < n; ++r) col[r] = value(r); },
        [&](auto value) { for (int r = 0; r < n; ++r) col[r] += value(r); });
  }
}

void CentralDifferences::sparse(DaeProblem& p, const SparsityPattern& pattern, double t, double cj, const double* y,
                                const double* yp, double* values) {
  const int n = static_cast<int>(y_.size());
  base(p, t, y, yp);
  for (int j = 0; j < n; ++j) {
    const std::int64_t begin = pattern.col_start[j], end = pattern.col_start[j + 1];
    column(
        p, j, t, cj, y, yp,
        [&](auto value) { for (std::int64_t k = begin; k < end; ++k) values[k] = value(static_cast<int>(pattern.rows[k])); },
        [&](auto value) { for (std::int64_t k = begin; k < end; ++k) values[k] += value(static_cast<int>(pattern.rows[k])); });
  }
}

}  // namespace rigidae::solver
