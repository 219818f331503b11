#pragma once
// The ODE form's saddle-point (KKT) solve by the Schur complement of the
// mass matrix, for large mechanisms (multibody_ode.cpp's sparse path takes
// it before KLU): the mass matrix is block diagonal by body and each block
// is positive definite in every combination (the Euler form's diag(m I, J),
// the paper's regular mass matrices of the Lagrange form: quaternions'
// quadratic one, linear coordinates' blockdiag(E, E, E), Euler angles' B^T J B
// away from a chart's singularity).
//
// Equations (multibody_ode.hpp's KKT system, rows v and lambda):
//   M v' + G^T lambda = r_v,     w_A G v' = r_l     (active rows)
//                                lambda_r = 0        (rows set aside)
// so, with M = diag(M_b) and S = G M^-1 G^T over the active rows,
//   S lambda = G M^-1 r_v - r_l / w_A,   v' = M^-1 (r_v - G^T lambda).
// S is symmetric positive definite while G has full row rank (M_b > 0),
// and its pattern joins two multiplier blocks only where they share a body:
// for a chain, 3 x 3 blocks on three diagonals; in general, joints that
// meet at a body. It is factorised by a sparse LDL^T (Eigen's simplicial one) in a
// fill-reducing order (AMD on S's pattern) chosen once; S is assembled in
// that order (upper triangle) straight from the per-body products, so a
// factorisation copies nothing and allocates nothing up to 16,384
// multipliers (5,461 spherical joints); above that Eigen's LDL^T takes its
// work vectors from the heap (EIGEN_STACK_ALLOCATION_LIMIT, 128 KiB).
//
// Against KLU on the whole KKT matrix (velocities and multipliers, with
// partial pivoting) it factorises a matrix of the multipliers' size only,
// without pivoting, and the bodies' blocks are inverted one by one (at most
// 12 x 12). Measured on the 1000-link spherical chain, docs/benchmarks.md.
//
// Regularity: a body's block that is not positive definite makes
// factorise() answer NotApplicable (the caller keeps KLU from then on); an
// LDL^T pivot below 1e-13 of the largest is Singular (the caller tries KLU,
// whose pivoting may still succeed: S's condition is about the square of
// G's), as the other paths' test (multibody_ode.hpp, "Rank").
//
// Input: the KKT matrix's values in its compressed-column pattern
// (multibody_ode.cpp's KKT block: unknowns velocities then multipliers),
// read at the positions found here once: each body's M_b (the diagonal block
// of its velocity range) and each (body, multiplier block) pair's G^T
// (velocity rows, multiplier columns). The lower-left block w_A G and the
// multipliers' diagonal are not read: w_A and the active rows come from the
// caller. An entry between two bodies' velocities makes the matrix not of
// this form (make() returns nullptr).
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include <cstdint>
#include <memory>
#include <vector>

namespace rigidae::multibody {

// A contiguous range of KKT unknowns.
struct KktRange {
  int start = 0, size = 0;
};

class SchurSaddle {
 public:
  static constexpr int kMaxBody = 12;  // velocities of one body (linear coordinates, Lagrange form: 3 + 9)
  static constexpr int kMaxRows = 12;  // rows of one multiplier block
  enum class Outcome { Factorised, Singular, NotApplicable };

  // bodies: each body's velocity range; blocks: each multiplier block's
  // range (both in KKT order, velocities before multipliers); the pattern
  // of the KKT matrix (compressed columns, n = velocities + multipliers).
  // nullptr when the matrix is not block diagonal in the velocities or a
  // block is larger than the fixed capacities.
  static std::unique_ptr<SchurSaddle> make(const std::vector<KktRange>& bodies, const std::vector<KktRange>& blocks,
                                           const std::vector<int>& col_start, const std::vector<int>& rows);

  // Factorises at the KKT values kkt (the pattern's order); active[k] for
  // multiplier k (0: set aside, lambda_k = 0), inv_weight[k] = 1 / w_A of
  // its block.
  Outcome factorise(const double* kkt, const char* active);
  // b = (r_v; r_l) -> (v'; lambda) in place, with the last factorisation
  // (and its active rows: the caller keeps that array unchanged meanwhile).
  void solve(double* b, const double* inv_weight);

 private:
  using BodyMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxBody, kMaxBody>;
  using Sparse = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
  // Eigen's simplicial LDL^T with its preordered factorisation exposed:
  // S is assembled already permuted, so nothing is copied per factorisation.
  class Ldlt : public Eigen::SimplicialLDLT<Sparse, Eigen::Upper, Eigen::NaturalOrdering<int>> {
   public:
    void analyse(const Sparse& a) { analyzePattern_preordered(a, true); }
    void factorise(const Sparse& a) { factorize_preordered<true>(a); }
    const Eigen::VectorXd& diagonal() const { return m_diag; }  // D (vectorD() returns a copy)
  };
  // The per-body numbers live in three flat arrays, body after body, so a
  // factorisation streams through memory (fixed-capacity 12 x 12 matrices
  // per body made the 1000-link chain's working set ~7 MB: cache misses
  // cost more than the arithmetic).
  // A multiplier block acting on a body: G^T's positions in the KKT values
  // (body row i, block column j at idx_[pos + i + m j]), its values Gt and
  // W = M_b^-1 G^T at the last factorisation (val_[gt ..], val_[w ..]).
  struct Coupling {
    int block = 0, nr = 0;
    std::size_t pos = 0, gt = 0, w = 0;
  };
  struct Body {
    KktRange v;
    std::size_t mass = 0;      // idx_: M_b's entries, column-major
    std::size_t M = 0, Minv = 0;  // val_: M_b and its inverse at the last factorisation
    bool inverted = false;
    int first = 0, count = 0;  // couplings_[first .. first + count)
    // spos_[s_pos ..]: per ordered pair (c1, c2) of its couplings, c1
    // major, per (row of c1's block, row of c2's block) column-major, the
    // entry of S's values (-1: the lower triangle in the permuted order,
    // written by its mirror).
    std::size_t s_pos = 0;
  };

  SchurSaddle() = default;
  template <int M>
  void body_products(const Body& b, const double* kkt, const char* active, double* sv);

  std::vector<Body> bodies_;
  std::vector<Coupling> couplings_;
  std::vector<int> idx_;
  std::vector<int> spos_;
  std::vector<double> val_;
  std::vector<KktRange> blocks_;
  int nv_ = 0, nl_ = 0;
  std::vector<int> perm_;      // multiplier k (0-based) -> its row in S
  std::vector<int> diag_pos_;  // per multiplier k, S's diagonal entry
  Sparse S_;                   // permuted, upper triangle
  Ldlt ldlt_;
  Eigen::VectorXd rhs_, x_;    // S's right side and solution, permuted
  const char* active_ = nullptr;  // the last factorisation's (the caller's array)
};

}  // namespace rigidae::multibody
