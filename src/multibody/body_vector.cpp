// Body vectors and their derivatives (formulas in body_vector.hpp).
#include "rigidae/multibody/body_vector.hpp"

#include "rigidae/so3/rotation.hpp"

namespace rigidae::multibody {

namespace {

// Rotation velocities (v_rot) of a body as a vector.
inline double vrot(const BodyState& b, int k) { return b.v[b.nx + k]; }

}  // namespace

void evaluate_vector(const BodyState& b, const BodyVector& bv, VectorEval& out) {
  const RotationPartials& P = b.P;
  const Vec3 s = b.lever_of(bv);
  const int o = b.nx;
  out.value = P.R * s;
  if (bv.point) out.value += o == 3 ? b.x() : b.pivot;
  out.D.setZero(3, b.nq());
  out.Wm.setZero(3, b.nv());
  if (bv.point && o == 3) {
    out.D.leftCols<3>().setIdentity();
    out.Wm.leftCols<3>().setIdentity();
  }
  for (int k = 0; k < b.nqr; ++k) out.D.col(o + k) = P.d1[k] * s;
  if (b.lagrange) {
    out.Wm.rightCols(b.nvr) = out.D.rightCols(b.nqr);
    out.bias.setZero();
    if (!P.d2_zero)
      for (int k = 0; k < b.nqr; ++k)
        for (int m = 0; m < b.nqr; ++m) out.bias += (vrot(b, k) * vrot(b, m)) * (P.d2[k][m] * s);
  } else {
    out.Wm.rightCols<3>() = -P.R * so3::hat(s);
    const Vec3 w = b.omega();
    out.bias = P.R * w.cross(w.cross(s));
  }
  out.Wv.setZero();
  for (int k = 0; k < b.nv(); ++k) out.Wv += out.Wm.col(k) * b.v[k];
}

void vector_dWw_dq(const BodyState& b, const BodyVector& bv, const double* w, Mat3BQ& out) {
  const RotationPartials& P = b.P;
  const Vec3 s = b.lever_of(bv);
  const int o = b.nx;
  out.setZero(3, b.nq());
  if (b.lagrange) {
    if (P.d2_zero) return;
    for (int m = 0; m < b.nqr; ++m)
      for (int k = 0; k < b.nqr; ++k) out.col(o + m) += w[o + k] * (P.d2[k][m] * s);
  } else {
    const Vec3 ws = Vec3(w[o], w[o + 1], w[o + 2]).cross(s);
    for (int m = 0; m < b.nqr; ++m) out.col(o + m) = P.d1[m] * ws;
  }
}

void vector_dWtm_dq(const BodyState& b, const BodyVector& bv, const Vec3& m, MatBVQ& out) {
  const RotationPartials& P = b.P;
  const Vec3 s = b.lever_of(bv);
  const int o = b.nx;
  out.setZero(b.nv(), b.nq());
  if (b.lagrange) {
    if (P.d2_zero) return;
    for (int k = 0; k < b.nqr; ++k)
      for (int n = 0; n < b.nqr; ++n) out(o + k, o + n) = m.dot(P.d2[k][n] * s);
  } else {
    for (int n = 0; n < b.nqr; ++n) out.block<3, 1>(o, o + n) = s.cross(P.d1[n].transpose() * m);
  }
}

void vector_dDtm_dq(const BodyState& b, const BodyVector& bv, const Vec3& m, MatBQQ& out) {
  const RotationPartials& P = b.P;
  const Vec3 s = b.lever_of(bv);
  const int o = b.nx;
  out.setZero(b.nq(), b.nq());
  if (P.d2_zero) return;
  for (int k = 0; k < b.nqr; ++k)
    for (int n = 0; n < b.nqr; ++n) out(o + k, o + n) = m.dot(P.d2[k][n] * s);
}

void vector_dbias_dq(const BodyState& b, const BodyVector& bv, Mat3BQ& out) {
  const RotationPartials& P = b.P;
  const Vec3 s = b.lever_of(bv);
  const int o = b.nx;
  out.setZero(3, b.nq());
  if (b.lagrange) {
    if (P.d3_zero) return;  // only Euler angles have third partials (nqr = 3)
    for (int n = 0; n < 3; ++n)
      for (int k = 0; k < 3; ++k)
        for (int m = 0; m < 3; ++m) out.col(o + n) += (vrot(b, k) * vrot(b, m)) * (P.d3[k][m][n] * s);
  } else {
    const Vec3 w = b.omega();
    const Vec3 wws = w.cross(w.cross(s));
    for (int n = 0; n < b.nqr; ++n) out.col(o + n) = P.d1[n] * wws;
  }
}

void vector_dbias_dv(const BodyState& b, const BodyVector& bv, Mat3BV& out) {
  const RotationPartials& P = b.P;
  const Vec3 s = b.lever_of(bv);
  const int o = b.nx;
  out.setZero(3, b.nv());
  if (b.lagrange) {
    if (P.d2_zero) return;
    for (int k = 0; k < b.nqr; ++k)
      for (int m = 0; m < b.nqr; ++m) out.col(o + k) += (2.0 * vrot(b, m)) * (P.d2[k][m] * s);
  } else {
    const Vec3 w = b.omega();
    out.rightCols<3>() = -P.R * (so3::hat(w.cross(s)) + so3::hat(w) * so3::hat(s));
  }
}

}  // namespace rigidae::multibody
