#pragma once
// The iteration matrix dF/dy + cj dF/dy' of any DaeProblem by differencing
// its residual (internal to solver/): dF/dy by central differences, whose
// O(d^2) error (~1e-11 relative) keeps Newton converging on index-2 forms at
// tight tolerances, where IDA's forward differences (~1e-8) do not; dF/dy'
// exactly (F is affine in y'), by a difference with a large step. 3n + 1
// residual evaluations per matrix.
#include <Eigen/Core>

#include "rigidae/solver/problem.hpp"

namespace rigidae::solver {

class CentralDifferences {
 public:
  explicit CentralDifferences(int n);

  // Dense, column-major n x n into J.
  void dense(DaeProblem& p, double t, double cj, const double* y, const double* yp, double* J);
  // The entries of `pattern`, in its order, into values.
  void sparse(DaeProblem& p, const SparsityPattern& pattern, double t, double cj, const double* y, const double* yp,
              double* values);

  long residual_evaluations() const { return evaluations_; }

 private:
  // Column j: writes (F(y + d e_j) - F(y - d e_j)) / 2d into `put(row, value)`
  // and then adds cj (F(y' + d' e_j) - F) / d' through `add(row, value)`.
  template <class Put, class Add>
  void column(DaeProblem& p, int j, double t, double cj, const double* y, const double* yp, Put put, Add add);
  void base(DaeProblem& p, double t, const double* y, const double* yp);

  Eigen::VectorXd y_, yp_, F_plus_, F_minus_, F_base_;  // scratch, n each
  long evaluations_ = 0;
};

}  // namespace rigidae::solver
