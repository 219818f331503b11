// A driver's rheonomic row from its coordinate's rows (equations in
// include/rigidae/multibody/driver_rows.hpp).
#include "rigidae/multibody/driver_rows.hpp"

#include <cmath>

namespace rigidae::multibody {

namespace {

// alpha_k and their first two time derivatives; beta and its derivatives.
struct Weights {
  double a[2] = {0, 0}, ad[2] = {0, 0}, add[2] = {0, 0};
  double b = 0, bd = 0, bdd = 0;
  int n = 1;
};

Weights weights(const DriverRow& d, double t) {
  double f, fd, fdd;
  d.motion->evaluate(t, f, fd, fdd);
  Weights w;
  w.n = d.row_count();
  if (d.coordinate->kind == CoordinateKind::Length) {
    w.a[0] = 1.0;
    w.b = -f;
    w.bd = -fd;
    w.bdd = -fdd;
    return w;
  }
  const double s = std::sin(f), c = std::cos(f);
  w.a[0] = -s;
  w.a[1] = c;
  w.ad[0] = -c * fd;
  w.ad[1] = -s * fd;
  w.add[0] = s * fd * fd - c * fdd;
  w.add[1] = -c * fd * fd - s * fdd;
  return w;
}

// The one-row values from the coordinate rows' (scratch, values only).
void combine_values(const Weights& w, const BlockEval& s, BlockEval& out) {
  out.nr = 1;
  out.phi.setZero(1);
  out.Gv.setZero(1);
  out.cacc.setZero(1);
  out.phi(0) = w.b;
  out.Gv(0) = w.bd;
  out.cacc(0) = w.bdd;
  for (int k = 0; k < w.n; ++k) {
    out.phi(0) += w.a[k] * s.phi(k);
    out.Gv(0) += w.a[k] * s.Gv(k) + w.ad[k] * s.phi(k);
    out.cacc(0) += w.a[k] * s.cacc(k) + 2.0 * w.ad[k] * s.Gv(k) + w.add[k] * s.phi(k);
  }
  for (int x = 0; x < 2; ++x) {
    out.phi_q[x].setZero(1, s.phi_q[x].cols());
    out.G[x].setZero(1, s.G[x].cols());
    for (int k = 0; k < w.n; ++k) {
      out.phi_q[x].row(0) += w.a[k] * s.phi_q[x].row(k);
      out.G[x].row(0) += w.a[k] * s.G[x].row(k);
    }
  }
}

}  // namespace

void evaluate_driver(const DriverRow& d, double t, const BlockSides& sides, BlockEval& scratch, BlockEval& out) {
  evaluate_rows(d.rows, d.row_count(), sides, scratch);
  combine_values(weights(d, t), scratch, out);
}

void differentiate_driver(const DriverRow& d, double t, const BlockSides& sides, const double* const a[2],
                          const double* lambda, const double* mu, BlockEval& scratch, BlockEval& out) {
  const Weights w = weights(d, t);
  evaluate_rows(d.rows, d.row_count(), sides, scratch);
  combine_values(w, scratch, out);
  double l[2] = {0, 0}, m[2] = {0, 0};
  for (int k = 0; k < w.n; ++k) {
    if (lambda) l[k] = w.a[k] * lambda[0];
    if (mu) m[k] = w.a[k] * mu[0];
  }
  differentiate_rows(d.rows, w.n, sides, a, lambda ? l : nullptr, mu ? m : nullptr, scratch);
  for (int x = 0; x < 2; ++x) {
    const int nq = scratch.dGv_q[x].cols(), nv = scratch.dc_v[x].cols();
    out.dGv_q[x].setZero(1, nq);
    out.dGa_q[x].setZero(1, nq);
    out.dc_q[x].setZero(1, nq);
    out.dPqp_q[x].setZero(1, nq);
    out.dc_v[x].setZero(1, nv);
    for (int k = 0; k < w.n; ++k) {
      out.dGv_q[x].row(0) += w.a[k] * scratch.dGv_q[x].row(k) + w.ad[k] * scratch.phi_q[x].row(k);
      out.dGa_q[x].row(0) += w.a[k] * scratch.dGa_q[x].row(k);
      out.dc_q[x].row(0) += w.a[k] * scratch.dc_q[x].row(k) + 2.0 * w.ad[k] * scratch.dGv_q[x].row(k) +
                            w.add[k] * scratch.phi_q[x].row(k);
      out.dc_v[x].row(0) += w.a[k] * scratch.dc_v[x].row(k) + 2.0 * w.ad[k] * scratch.G[x].row(k);
    }
    for (int y = 0; y < 2; ++y) {
      out.HL[x][y] = scratch.HL[x][y];
      out.HM[x][y] = scratch.HM[x][y];
    }
  }
}

double driving_effort(const DriverRow& d, const BlockEval& scratch, double lambda) {
  if (d.coordinate->kind == CoordinateKind::Length) return -lambda;
  return -lambda * std::hypot(scratch.phi(0), scratch.phi(1));
}

double prescribed_miss(const DriverRow& d, const BlockEval& scratch, double t) {
  const double f = d.motion->value(t);
  if (d.coordinate->kind == CoordinateKind::Length) return scratch.phi(0) - f;
  const double C = scratch.phi(0), S = scratch.phi(1), s = std::sin(f), c = std::cos(f);
  return std::atan2(S * c - C * s, C * c + S * s);
}

double coordinate_angle(const BlockEval& scratch) { return std::atan2(scratch.phi(1), scratch.phi(0)); }

}  // namespace rigidae::multibody
