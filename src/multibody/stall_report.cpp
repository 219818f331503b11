// What a mechanism knows when the step size has collapsed
// (DaeProblem::describe_stall): its scheme, and whether the joints'
// constraint rows still have full rank at the state where the run stalled.
// Rows that lost rank (a slider-crank at its dead point, two revolute axes
// come into line) make the saddle-point matrix singular and the step size
// collapses there; naming their joints says where to look.
#include <Eigen/SPQRSupport>
#include <fmt/format.h>

#include <algorithm>

#include "rigidae/multibody/multibody_problem.hpp"

namespace rigidae::multibody {

std::string MultibodyProblem::describe_stall(double t, const double* y) {
  std::string text = fmt::format("Scheme: {} on {} bodies and {} joints.", scheme_.name, bodies_.size(),
                                 spec_.joints.size());
  evaluate(t, y, 2);
  for (int j = 0; j < static_cast<int>(blocks_.size()); ++j) evaluate_block(j, y, nullptr);
  Eigen::SparseMatrix<double> G;
  Eigen::VectorXd phi;
  std::vector<int> row_block, row_index;
  constraint_matrices(G, phi, &row_block, &row_index);
  if (G.rows() == 0) return text;
  // The start's rank check (consistent_start.cpp), at the stalled state.
  using SpqrMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, SuiteSparse_long>;
  const SpqrMatrix Gt = G.transpose();
  Eigen::SPQR<SpqrMatrix> qr;
  qr.setPivotThreshold(1e-10 * std::max(1.0, Gt.coeffs().cwiseAbs().maxCoeff()));
  qr.compute(Gt);
  if (qr.info() != Eigen::Success) return text;
  const int rank = static_cast<int>(qr.rank());
  if (rank == G.rows())
    return text + fmt::format(" The {} constraint rows keep full rank at t = {:.9g} s: no joint lost a direction.",
                              G.rows(), t);
  const Eigen::Matrix<SuiteSparse_long, Eigen::Dynamic, 1> perm = qr.colsPermutation().indices();  // a copy
  constexpr int kRowsListed = 8;
  std::string rows;
  for (int k = rank; k < G.rows() && k < rank + kRowsListed; ++k) {
    const int i = static_cast<int>(perm(k));
    rows += (k == rank ? "" : "; ") + row_label(row_block[i], row_index[i]);
  }
  if (G.rows() - rank > kRowsListed) rows += fmt::format("; and {} more", G.rows() - rank - kRowsListed);
  return text + fmt::format(" {} of the {} constraint rows lost rank at t = {:.9g} s (the mechanism is at a "
                            "singular configuration there): {}.",
                            G.rows() - rank, G.rows(), t, rows);
}

}  // namespace rigidae::multibody
