// What a mechanism knows when the step size has collapsed
// (DaeProblem::describe_stall): its scheme, and whether the joints'
// constraint rows still have full rank at the state where the run stalled.
// Rows that lost rank (a slider-crank at its dead point, two revolute axes
// come into line) make the saddle-point matrix singular and the step size
// collapses there; naming their joints says where to look. Rows of full
// rank but nearly dependent (smallest singular value below 1e-3 of the
// largest: the run stopped next to a singular pose) are named the same way.
// Also appended to IDA's convergence failures (ida_driver.cpp), which is
// how a run usually stops at a singular pose.
#include <Eigen/SPQRSupport>
#include <Eigen/SVD>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "rigidae/multibody/multibody_problem.hpp"
#include "rigidae/core/text.hpp"

namespace rigidae::multibody {

std::string MultibodyProblem::describe_stall(double t, const double* y) {
  // The formulation as summary.json names it (the first body's coordinates
  // and form: a scene has one formulation), then the system's size.
  std::string formulation = "point masses";
  for (const BodyModel& b : bodies_)
    if (!b.particle) {
      formulation = b.rep->name();
      break;
    }
  std::string text = fmt::format("Formulation: {} with scheme {}", formulation, scheme_.name);
  text += !spec_.joints.empty() || bodies_.size() > 1
              ? fmt::format(", on {} and {}.", text::count(bodies_.size(), "body", "bodies"),
                            text::count(spec_.joints.size(), "joint", "joints"))
              : std::string(".");
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
  if (rank == G.rows()) {
    // Full rank at 1e-10, but perhaps nearly singular: the smallest singular
    // value of the rows (scaled by their largest entry) and the joints in
    // its left singular vector (the combination of rows that nearly
    // vanishes). Dense: only for small mechanisms.
    if (G.rows() * G.cols() <= 40000) {
      const Eigen::MatrixXd Gd(G);
      const Eigen::JacobiSVD<Eigen::MatrixXd> svd(Gd, Eigen::ComputeThinU);
      const Eigen::VectorXd& sv = svd.singularValues();
      const double ratio = sv(sv.size() - 1) / std::max(sv(0), 1e-300);
      // Against the same rows at the start (their own scale: a mechanism
      // may be poorly conditioned everywhere).
      double ratio0 = 1.0;
      {
        evaluate(t, y0_.data(), 2);
        for (int j = 0; j < static_cast<int>(blocks_.size()); ++j) evaluate_block(j, y0_.data(), nullptr);
        Eigen::SparseMatrix<double> G0;
        Eigen::VectorXd phi0;
        constraint_matrices(G0, phi0, nullptr, nullptr);
        const Eigen::JacobiSVD<Eigen::MatrixXd> svd0{Eigen::MatrixXd(G0)};
        const Eigen::VectorXd& s0 = svd0.singularValues();
        if (s0.size() == sv.size()) ratio0 = s0(s0.size() - 1) / std::max(s0(0), 1e-300);
        evaluate(t, y, 2);
      }
      if (ratio < 0.1 * ratio0) {
        const Eigen::VectorXd u = svd.matrixU().col(sv.size() - 1);
        std::vector<std::string> joints;
        for (int i = 0; i < static_cast<int>(u.size()); ++i)
          if (std::abs(u(i)) > 0.1 * u.cwiseAbs().maxCoeff() && !blocks_[row_block[i]].internal) {
            const std::string& name = spec_.joints[blocks_[row_block[i]].joint].name;
            if (std::find(joints.begin(), joints.end(), name) == joints.end()) joints.push_back(name);
          }
        std::string list;
        for (const std::string& n : joints) list += (list.empty() ? "'" : ", '") + n + "'";
        return text + fmt::format(" The {} constraint rows are nearly dependent at t = {:.9g} s (smallest singular "
                                  "value {:.3g} of the largest, {:.3g} at the start): the mechanism is at or next to "
                                  "a singular pose, where assembly branches cross; the rows of joints {} lose rank "
                                  "together there",
                                  G.rows(), t, ratio, ratio0, list);
      }
    }
    return text + fmt::format(" The {} constraint rows keep full rank at t = {:.9g} s: no joint lost a direction.",
                              G.rows(), t);
  }
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
