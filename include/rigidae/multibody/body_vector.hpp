#pragma once
// What a joint or a force needs from a body: a body-fixed vector in space and
// its derivatives, written with the placement partials alone (multibody.md,
// "What a joint needs from a representation").
//
// Body i has coordinates (x, q) (centre of mass in space, rotation
// coordinates) and velocities (x', v): v = q' (Lagrange form) or v = Omega_B
// (Euler form). A body vector is a point p = x + R(q) s or a direction
// d = R(q) s, s fixed in the body (from the centre of mass). For u = R s:
//   U = du/dq, columns R_k s                            (position level)
//   W with u' = W v: Lagrange W = U; Euler W = -R hat(s) (R' = R hat(Omega))
//   bias b = u'' - W v': Lagrange sum_km R_km s v_k v_m; Euler R hat(Omega)^2 s
// and the contractions for the exact Jacobian:
//   d(W w)/dq:   Lagrange col m = sum_k R_km s w_k;  Euler col m = R_m (w x s)
//   d(W^T m)/dq: Lagrange (k, n) = m^T R_kn s;       Euler col n = s x (R_n^T m)
//   d(U^T m)/dq: (k, n) = m^T R_kn s (both forms)
//   db/dq:       Lagrange col n = sum_km R_kmn s v_k v_m; Euler col n = R_n hat(Omega)^2 s
//   db/dv:       Lagrange col k = 2 sum_m R_km s v_m;     Euler -R (hat(Omega x s) + hat(Omega) hat(s))
// A point adds the identity on x (and x') to U and W, and nothing else.
// The ground (body kGround) has no unknowns: its vectors are constants.
#include "rigidae/core/types.hpp"
#include "rigidae/model/multibody_spec.hpp"
#include "rigidae/multibody/rotation_map.hpp"

namespace rigidae::multibody {

// Unknowns of one body: 3 + up to 9 coordinates, 3 + up to 9 velocities.
inline constexpr int kMaxBodyQ = 12;
inline constexpr int kMaxBodyV = 12;
using BodyVecQ = BoundedVec<kMaxBodyQ>;
using Mat3BQ = BoundedMat<3, kMaxBodyQ>;
using Mat3BV = BoundedMat<3, kMaxBodyV>;
using MatBVQ = BoundedMat<kMaxBodyV, kMaxBodyQ>;
using MatBQQ = BoundedMat<kMaxBodyQ, kMaxBodyQ>;
using RowBQ = BoundedMat<1, kMaxBodyQ>;
using RowBV = BoundedMat<1, kMaxBodyV>;

// One body's state at an evaluation: its slices of y, the placement
// partials, and the form. Filled by the assembler, read by joints and forces.
struct BodyState {
  bool lagrange = true;
  int nqr = 0, nvr = 0;  // rotation coordinates and velocities
  const double* q = nullptr;  // (x, q_rot), 3 + nqr
  const double* v = nullptr;  // (x', v_rot), 3 + nvr
  RotationPartials P;
  int nq() const { return 3 + nqr; }
  int nv() const { return 3 + nvr; }
  Vec3 x() const { return Vec3(q[0], q[1], q[2]); }
  Vec3 omega() const { return Vec3(v[3], v[4], v[5]); }  // Euler form only
};

// A vector fixed in a body (or in space, for the ground): model/constraint_row.hpp.
using rigidae::BodyVector;

// Value, position map D = dp/d(x, q), velocity map Wm (p' = Wm (x', v)) and
// bias of a body vector. For the ground: the constant s, empty maps.
struct VectorEval {
  Vec3 value = Vec3::Zero();
  Mat3BQ D;
  Mat3BV Wm;
  Vec3 bias = Vec3::Zero();
  Vec3 Wv = Vec3::Zero();  // Wm times the body's velocities: the vector's rate
};

// `bias` needs RotationPartials of order 2 in the Lagrange form.
void evaluate_vector(const BodyState& b, const BodyVector& bv, VectorEval& out);

// Contractions (3 x nq, nv x nq, nq x nq, 3 x nq, 3 x nv for the body); see above.
// w has the body's nv entries (velocities or accelerations).
void vector_dWw_dq(const BodyState& b, const BodyVector& bv, const double* w, Mat3BQ& out);
void vector_dWtm_dq(const BodyState& b, const BodyVector& bv, const Vec3& m, MatBVQ& out);
void vector_dDtm_dq(const BodyState& b, const BodyVector& bv, const Vec3& m, MatBQQ& out);
void vector_dbias_dq(const BodyState& b, const BodyVector& bv, Mat3BQ& out);  // order 3 (Lagrange)
void vector_dbias_dv(const BodyState& b, const BodyVector& bv, Mat3BV& out);

}  // namespace rigidae::multibody
