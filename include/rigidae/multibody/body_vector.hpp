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
//
// A pivoted body (BodySpec::pivot_W) has no x: its unknowns are q_rot and
// v_rot only (nx = 0) and it turns about the fixed pivot o. Its points are
// p = o + R (c + s), c the pivot -> centre of mass vector in the body frame
// and s (as for every body) from the centre of mass: the formulas above hold
// with s replaced by the lever c + s, without the identity on x. Its
// directions are unchanged. x() is then its centre of mass o + R c.
#include "rigidae/core/types.hpp"
#include "rigidae/model/multibody_spec.hpp"
#include "rigidae/multibody/rotation_map.hpp"

namespace rigidae::multibody {

// Unknowns of one body: 3 (none when pivoted) + up to 9 coordinates, as many + up to 9 velocities.
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
  int nx = 3;            // translation unknowns: 3 (free body), 0 (pivoted)
  int nqr = 0, nvr = 0;  // rotation coordinates and velocities
  const double* q = nullptr;  // (x, q_rot), nx + nqr
  const double* v = nullptr;  // (x', v_rot), nx + nvr
  Vec3 pivot = Vec3::Zero();  // pivoted: the fixed point o in space
  Vec3 lever = Vec3::Zero();  // pivoted: c, pivot -> centre of mass, body frame (0 for a free body)
  RotationPartials P;
  int nq() const { return nx + nqr; }
  int nv() const { return nx + nvr; }
  // The centre of mass in space (a pivoted body's needs P evaluated).
  Vec3 x() const { return nx == 3 ? Vec3(q[0], q[1], q[2]) : Vec3(pivot + P.R * lever); }
  Vec3 omega() const { return Vec3(v[nx], v[nx + 1], v[nx + 2]); }  // Euler form only
  // The lever of a body vector: s from the centre of mass, c + s from a pivot.
  Vec3 lever_of(const BodyVector& bv) const { return bv.point && nx == 0 ? Vec3(lever + bv.s) : bv.s; }
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
