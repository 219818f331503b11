#pragma once
// The rank decision over the Force rows, shared by the start's analysis
// (redundancy.cpp) and the re-check during the run (row_subset.cpp): the
// scaled transpose S G^T (one column per constraint row, point rows divided
// by the length scale L) and SuiteSparseQR's rank-revealing factorisation.
#include <Eigen/SPQRSupport>

#include <functional>
#include <vector>

#include "rigidae/multibody/multibody_problem.hpp"

namespace rigidae::multibody {

using SparseL = Eigen::SparseMatrix<double, Eigen::ColMajor, SuiteSparse_long>;

// One Force row: a body's internal row (body >= 0, joint < 0), a joint's, or
// a driver's (driver >= 0, joint its joint, row null; driver_rows.hpp).
struct ForceRowRef {
  int body = -1, joint = -1, index = 0;
  const ConstraintRow* row = nullptr;
  int driver = -1;
  const DriverRow* drive = nullptr;
};

struct Rank {
  int rank = 0;
  double rmax = 0.0;
  std::vector<int> perm;  // columns in SPQR's order; perm[rank..] set aside
};

// threshold < 0: SPQR's default. fixed: the columns in their order (no
// fill-reducing permutation), so the later of dependent columns are set aside.
Rank spqr_rank(const SparseL& Gt, double threshold, bool fixed = false);

// Whether a row measures a point (metres) rather than an angle.
bool is_point_row(const ConstraintRow& r);

// S G^T over all velocities at the bodies' last evaluate(), at time t (a
// driver's row depends on it).
SparseL scaled_transpose(const std::vector<ForceRowRef>& rows, const std::vector<BodyModel>& bodies,
                         const std::vector<int>& velocity_offset, int nv_total,
                         const std::function<const BodyState*(int)>& state,
                         const std::function<const MatCV*(int)>& internal_G, double L, BlockEval& e, double t);

// Least-squares coefficients of each `aside` column of Gt on the `kept`
// columns (kept x aside), and the largest residual relative to the column's
// norm (0 while the set-aside rows are implied). Dense below a size, sparse
// QR above.
Eigen::MatrixXd row_dependencies(const SparseL& Gt, const std::vector<int>& kept, const std::vector<int>& aside,
                                 double& residual);

// Given an independent `kept` set and the `aside` columns (as SPQR chose
// them), the rows to set aside instead: the pivots of a column-pivoted QR of
// the dependencies' basis N^T (N_aside = -I, N_kept = alpha), which picks the
// best-conditioned square block of N (for one dependency, the row with the
// largest coefficient). The first n_internal columns (the bodies' own rows)
// are never chosen. Sorted.
std::vector<int> best_set_aside(const SparseL& Gt, const std::vector<int>& kept, const std::vector<int>& aside,
                                int n_internal);

// The bodies' own Force rows (the Lagrange form's), body by body.
std::vector<ForceRowRef> internal_force_rows(const std::vector<BodyModel>& bodies);

}  // namespace rigidae::multibody
