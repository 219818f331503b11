#pragma once
// Joint constraint rows as sums of dot products of body vectors.
//
// Every primitive of multibody.md is a constant plus a sum of terms
// c (alpha . beta), alpha and beta body vectors (points, directions, or
// constants of the ground):
//   coincident points, row k:  p_a . e_k - p_b . e_k
//   perpendicular directions:  d_a . d_b
//   point on a line, row i:    p_b . n_i - p_a . n_i   (n_i fixed in a)
//   distance (rod of length L): (p_b.p_b - 2 p_a.p_b + p_a.p_a) / (2L) - L/2
// (alpha = beta in a squared length: the rules below hold with X = Y and
// both sides' contributions added, which is the product rule).
// So one derivation serves them all. For a term with alpha on body X and
// beta on body Y (X = Y allowed; a constant contributes no derivatives):
//   Phi   += c a.b
//   Phi_q: X += c b^T D_a,          Y += c a^T D_b
//   G:     X += c b^T W_a,          Y += c a^T W_b        (G = Phi_q N)
//   Phi'' - G v' = c (b.bias_a + a.bias_b + 2 (W_a v).(W_b v))  =: cacc
//   d(G w)/dq_X = c (b^T dWw_a(w) + (W_b w)^T D_a)
//   d(cacc)/dq_X = c (b^T dbias_a/dq + bias_b^T D_a + 2 (W_b v)^T dWw_a(v))
//   d(cacc)/dv_X = c (b^T dbias_a/dv + 2 (W_b v)^T W_a)
//   d(G^T l)/dq: (X, X) c dWtm_a(l b), (X, Y) c l W_a^T D_b
//   d(Phi_q^T m)/dq: (X, X) c dDtm_a(m b), (X, Y) c m D_a^T D_b
// and the same with a and b exchanged. Rows keep their natural units: metres
// for point rows (multipliers in N), dimensionless for perpendicular pairs
// (multipliers in N m: the torque about d_a x d_b).
#include <string>
#include <vector>

#include "rigidae/model/constraint_row.hpp"
#include "rigidae/multibody/body_vector.hpp"

namespace rigidae::multibody {

// The rows as plain data (model/constraint_row.hpp); joint types state them.
using rigidae::ConstraintRow;
using rigidae::DotTerm;

inline constexpr int kMaxBlockRows = 6;
using BlockVec = BoundedVec<kMaxBlockRows>;
using BlockMatQ = BoundedMat<kMaxBlockRows, kMaxBodyQ>;
using BlockMatV = BoundedMat<kMaxBlockRows, kMaxBodyV>;

// A block's rows evaluated at one state, over the columns of its (up to)
// two bodies, side 0 and side 1. Used for joints and internal blocks alike.
struct BlockEval {
  int nr = 0;
  BlockVec phi, Gv, cacc;  // Phi, G v, Phi'' - G v'
  BlockMatQ phi_q[2];
  BlockMatV G[2];
  // Jacobian parts (filled by the derivative pass).
  BlockMatQ dGv_q[2], dGa_q[2], dc_q[2];  // d(G v)/dq, d(G v')/dq, d(cacc)/dq
  BlockMatV dc_v[2];
  MatBVQ HL[2][2];  // d(G^T lambda)/dq: rows of side X's v, columns of side Y's q
  MatBQQ HM[2][2];  // d(Phi_q^T mu)/dq
  BlockMatQ dPqp_q[2];  // Kinematic kind: d(Phi_q q')/dq
};

// The two bodies of a block (kGround for none) and their states.
struct BlockSides {
  int body[2] = {kGround, kGround};
  const BodyState* state[2] = {nullptr, nullptr};
  int side_of(int body_index) const { return body_index == kGround ? -1 : body_index == body[0] ? 0 : 1; }
};

// Values: phi, phi_q, G, Gv, cacc. Allocates nothing.
void evaluate_rows(const ConstraintRow* rows, int nr, const BlockSides& sides, BlockEval& out);
// Derivatives: dGv_q, dGa_q (with accelerations a[side]), dc_q, dc_v, and
// HL, HM contracted with the block's lambda and mu (null when absent).
void differentiate_rows(const ConstraintRow* rows, int nr, const BlockSides& sides, const double* const a[2],
                        const double* lambda, const double* mu, BlockEval& out);

}  // namespace rigidae::multibody
