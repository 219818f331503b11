#pragma once
// A dense LU with partial pivoting for small square systems, in storage of
// fixed capacity: the ODE form's KKT solve of small mechanisms
// (multibody_ode.cpp), where Eigen's dynamic-size LU spends most of its
// work on loop and block bookkeeping of an 11 x 11 matrix (callgrind on the
// pendulum over 10 periods: 6,650 of ~29,000 instructions per right-hand
// side in partial_lu_impl::unblocked_lu alone).
//
// Factorisation (Doolittle, row pivoting, in place, column-major):
//   P A = L U,  L unit lower triangular, U upper triangular;
// at column k the pivot is the entry of largest |.| on or below the
// diagonal (the first such, as LAPACK's and Eigen's), its row is swapped
// with row k, the multipliers l_ik = a_ik / a_kk are stored below the
// diagonal and the trailing block updated a_ij -= l_ik a_kj. Solve: apply
// P to b, forward substitution with L, back substitution with U.
// The regularity test is the caller's: pivot_ratio() = min |u_kk| / max
// |u_kk| (0 when a column has no nonzero pivot), as multibody_ode.cpp
// measures Eigen's factors. Nothing allocates; n <= kCapacity.
#include <algorithm>
#include <cmath>
#include <utility>

namespace rigidae::multibody {

class SmallLu {
 public:
  static constexpr int kCapacity = 48;

  // Sets the order n (0 < n <= kCapacity) and zeroes the matrix.
  void resize(int n) {
    n_ = n;
    std::fill(a_, a_ + n_ * n_, 0.0);
  }
  int size() const { return n_; }
  // Entry (i, j) of the matrix to factorise (column-major storage).
  double& operator()(int i, int j) { return a_[j * n_ + i]; }

  // Factorises a copy of the matrix (the matrix itself keeps its pattern for
  // the next assembly). Returns min |u_kk| / max |u_kk|.
  double factorise() {
    const int n = n_;
    std::copy(a_, a_ + n * n, lu_);
    double u_min = INFINITY, u_max = 0.0;
    for (int k = 0; k < n; ++k) {
      double* col_k = lu_ + k * n;
      int p = k;
      double best = std::abs(col_k[k]);
      for (int i = k + 1; i < n; ++i)
        if (std::abs(col_k[i]) > best) best = std::abs(col_k[i]), p = i;
      perm_[k] = p;
      if (p != k)
        for (int j = 0; j < n; ++j) std::swap(lu_[j * n + k], lu_[j * n + p]);
      const double pivot = col_k[k];
      u_min = std::min(u_min, std::abs(pivot));
      u_max = std::max(u_max, std::abs(pivot));
      if (pivot == 0.0) continue;  // a zero column below k: nothing to eliminate (singular; the ratio says so)
      const double inv = 1.0 / pivot;
      for (int i = k + 1; i < n; ++i) col_k[i] *= inv;
      for (int j = k + 1; j < n; ++j) {
        double* col_j = lu_ + j * n;
        const double u_kj = col_j[k];
        if (u_kj == 0.0) continue;
        for (int i = k + 1; i < n; ++i) col_j[i] -= col_k[i] * u_kj;
      }
    }
    return u_max > 0.0 ? u_min / u_max : 0.0;
  }

  // b := A^-1 b with the last factorisation.
  void solve(double* b) const {
    const int n = n_;
    for (int k = 0; k < n; ++k)
      if (perm_[k] != k) std::swap(b[k], b[perm_[k]]);
    for (int j = 0; j < n; ++j) {  // L y = P b, column by column
      const double* col_j = lu_ + j * n;
      const double y_j = b[j];
      if (y_j != 0.0)
        for (int i = j + 1; i < n; ++i) b[i] -= col_j[i] * y_j;
    }
    for (int j = n - 1; j >= 0; --j) {  // U x = y, column by column
      const double* col_j = lu_ + j * n;
      b[j] /= col_j[j];
      const double x_j = b[j];
      if (x_j != 0.0)
        for (int i = 0; i < j; ++i) b[i] -= col_j[i] * x_j;
    }
  }

 private:
  int n_ = 0;
  double a_[kCapacity * kCapacity];
  double lu_[kCapacity * kCapacity];
  int perm_[kCapacity];
};

}  // namespace rigidae::multibody
