// The rank decision over the Force rows (row_rank.hpp).
#include "row_rank.hpp"

#include <Eigen/QR>

#include <algorithm>
#include <cmath>

#include "rigidae/core/error.hpp"

namespace rigidae::multibody {

using Triplet = Eigen::Triplet<double, SuiteSparse_long>;

bool is_point_row(const ConstraintRow& r) {
  for (int t = 0; t < r.n_terms; ++t)
    if (r.terms[t].a.point || r.terms[t].b.point) return true;
  return false;
}

Rank spqr_rank(const SparseL& Gt, double threshold, bool fixed) {
  Rank out;
  if (Gt.cols() == 0) return out;
  Eigen::SPQR<SparseL> qr;
  if (threshold >= 0.0) qr.setPivotThreshold(threshold);
  if (fixed) qr.setSPQROrdering(SPQR_ORDERING_FIXED);
  qr.compute(Gt);
  if (qr.info() != Eigen::Success)
    throw InputError("the rank check of the joints' constraint rows failed (SuiteSparseQR could not factorise G^T)");
  out.rank = static_cast<int>(qr.rank());
  // SPQR's colsPermutation() is a temporary: copy it (see git log: ASan).
  const Eigen::Matrix<SuiteSparse_long, Eigen::Dynamic, 1> perm = qr.colsPermutation().indices();
  out.perm.assign(perm.data(), perm.data() + perm.size());
  const SparseL R = qr.matrixR();
  for (int k = 0; k < out.rank && k < R.rows() && k < R.cols(); ++k)
    out.rmax = std::max(out.rmax, std::abs(R.coeff(k, k)));
  return out;
}

SparseL scaled_transpose(const std::vector<ForceRowRef>& rows, const std::vector<BodyModel>& bodies,
                         const std::vector<int>& velocity_offset, int nv_total,
                         const std::function<const BodyState*(int)>& state,
                         const std::function<const MatCV*(int)>& internal_G, double L, BlockEval& e, double t) {
  std::vector<Triplet> trip;
  BlockEval scratch;
  for (int c = 0; c < static_cast<int>(rows.size()); ++c) {
    const ForceRowRef& f = rows[c];
    if (f.joint < 0) {
      const MatCV& G = *internal_G(f.body);
      const int o = velocity_offset[f.body] + bodies[f.body].nx;  // after its translations (none when pivoted)
      for (int k = 0; k < bodies[f.body].nvr; ++k)
        if (G(f.index, k) != 0.0) trip.emplace_back(o + k, c, G(f.index, k));
      continue;
    }
    BlockSides sides;
    // The row's bodies: those its vectors live on.
    int side_body[2] = {kGround, kGround};
    int n = 0;
    const ConstraintRow* own = f.drive ? f.drive->rows : f.row;
    const int own_rows = f.drive ? f.drive->row_count() : 1;
    for (int r = 0; r < own_rows; ++r)
      for (int k = 0; k < own[r].n_terms; ++k)
        for (const BodyVector* v : {&own[r].terms[k].a, &own[r].terms[k].b})
          if (v->body != kGround && v->body != side_body[0] && v->body != side_body[1] && n < 2)
            side_body[n++] = v->body;
    for (int x = 0; x < 2; ++x) {
      sides.body[x] = side_body[x];
      sides.state[x] = side_body[x] == kGround ? nullptr : state(side_body[x]);
    }
    double s = 1.0;
    if (f.drive) {
      // A driven length is in metres; an angle's row is r sin(theta - f).
      evaluate_driver(*f.drive, t, sides, scratch, e);
      if (f.drive->coordinate->kind == CoordinateKind::Length) s = 1.0 / L;
    } else {
      evaluate_rows(f.row, 1, sides, e);
      s = is_point_row(*f.row) ? 1.0 / L : 1.0;
    }
    for (int x = 0; x < 2; ++x) {
      if (side_body[x] == kGround) continue;
      for (int k = 0; k < e.G[x].cols(); ++k)
        if (e.G[x](0, k) != 0.0) trip.emplace_back(velocity_offset[side_body[x]] + k, c, s * e.G[x](0, k));
    }
  }
  SparseL Gt(nv_total, static_cast<SuiteSparse_long>(rows.size()));
  Gt.setFromTriplets(trip.begin(), trip.end());
  Gt.makeCompressed();
  return Gt;
}

std::vector<ForceRowRef> internal_force_rows(const std::vector<BodyModel>& bodies) {
  std::vector<ForceRowRef> rows;
  for (int i = 0; i < static_cast<int>(bodies.size()); ++i)
    if (bodies[i].rep->nc() > 0 && bodies[i].rep->constraint_kind() == ConstraintKind::Force)
      for (int r = 0; r < bodies[i].rep->nc(); ++r) rows.push_back({i, -1, r, nullptr});
  return rows;
}

namespace {

// Below this many entries of S G^T the dependencies are solved dense.
constexpr long kDenseEntries = 40000;

// The columns `cols` of Gt.
SparseL columns(const SparseL& Gt, const std::vector<int>& cols) {
  std::vector<Triplet> trip;
  for (int k = 0; k < static_cast<int>(cols.size()); ++k)
    for (SparseL::InnerIterator it(Gt, cols[k]); it; ++it) trip.emplace_back(it.row(), k, it.value());
  SparseL out(Gt.rows(), static_cast<SuiteSparse_long>(cols.size()));
  out.setFromTriplets(trip.begin(), trip.end());
  out.makeCompressed();
  return out;
}

}  // namespace

Eigen::MatrixXd row_dependencies(const SparseL& Gt, const std::vector<int>& kept, const std::vector<int>& aside,
                                 double& residual) {
  residual = 0.0;
  const int nk = static_cast<int>(kept.size()), na = static_cast<int>(aside.size());
  Eigen::MatrixXd alpha = Eigen::MatrixXd::Zero(nk, na);
  if (na == 0) return alpha;
  const SparseL GK = columns(Gt, kept);
  Eigen::MatrixXd B(Gt.rows(), na);
  for (int d = 0; d < na; ++d) B.col(d) = Gt.col(aside[d]);
  if (static_cast<long>(Gt.rows()) * Gt.cols() <= kDenseEntries) {
    const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr{Eigen::MatrixXd(GK)};
    alpha = qr.solve(B);
  } else {
    Eigen::SPQR<SparseL> qr;
    qr.compute(GK);
    if (qr.info() != Eigen::Success) {
      residual = 1.0;
      return alpha;
    }
    // One right-hand side at a time (redundancy.cpp says why).
    for (int d = 0; d < na; ++d) alpha.col(d) = qr.solve(Eigen::VectorXd(B.col(d)));
  }
  for (int d = 0; d < na; ++d) {
    const double r = (GK * alpha.col(d) - B.col(d)).norm() / std::max(B.col(d).norm(), 1e-300);
    residual = std::max(residual, std::isfinite(r) ? r : 1.0);
  }
  return alpha;
}

std::vector<int> best_set_aside(const SparseL& Gt, const std::vector<int>& kept, const std::vector<int>& aside,
                                int n_internal) {
  if (aside.empty()) return {};
  double residual = 0.0;
  const Eigen::MatrixXd alpha = row_dependencies(Gt, kept, aside, residual);
  const int m = static_cast<int>(Gt.cols()), nd = static_cast<int>(aside.size());
  Eigen::MatrixXd Nt = Eigen::MatrixXd::Zero(nd, m);  // one dependency per row
  for (int d = 0; d < nd; ++d) {
    for (int k = 0; k < static_cast<int>(kept.size()); ++k) Nt(d, kept[k]) = alpha(k, d);
    Nt(d, aside[d]) = -1.0;
  }
  Nt.leftCols(n_internal).setZero();  // a body's own rows stay
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(Nt);
  std::vector<int> chosen;
  const auto& perm = qr.colsPermutation().indices();
  for (int d = 0; d < nd; ++d) chosen.push_back(perm(d));
  std::sort(chosen.begin(), chosen.end());
  // A pivot on a zero column (a dependency among the bodies' own rows only):
  // keep SPQR's choice.
  if (qr.rank() < nd) return aside;
  return chosen;
}

}  // namespace rigidae::multibody
