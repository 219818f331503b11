// Dot-product constraint rows: values and exact derivatives (formulas in
// constraint_rows.hpp).
#include "rigidae/multibody/constraint_rows.hpp"

namespace rigidae::multibody {

namespace {

void size_sides(const BlockSides& sides, int nr, BlockEval& out, bool derivatives) {
  out.nr = nr;
  if (!derivatives) {
    out.phi.setZero(nr);
    out.Gv.setZero(nr);
    out.cacc.setZero(nr);
  }
  for (int x = 0; x < 2; ++x) {
    const int nq = sides.state[x] ? sides.state[x]->nq() : 0;
    const int nv = sides.state[x] ? sides.state[x]->nv() : 0;
    if (!derivatives) {
      out.phi_q[x].setZero(nr, nq);
      out.G[x].setZero(nr, nv);
    } else {
      out.dGv_q[x].setZero(nr, nq);
      out.dGa_q[x].setZero(nr, nq);
      out.dc_q[x].setZero(nr, nq);
      out.dc_v[x].setZero(nr, nv);
      out.dPqp_q[x].setZero(nr, nq);
      for (int y = 0; y < 2; ++y) {
        const int nqy = sides.state[y] ? sides.state[y]->nq() : 0;
        out.HL[x][y].setZero(nv, nqy);
        out.HM[x][y].setZero(nq, nqy);
      }
    }
  }
}

const BodyState* state_of(const BlockSides& sides, const BodyVector& v, int& side) {
  side = sides.side_of(v.body);
  return side < 0 ? nullptr : sides.state[side];
}

void evaluate_or_constant(const BodyState* st, const BodyVector& bv, VectorEval& out) {
  if (st) {
    evaluate_vector(*st, bv, out);
  } else {
    out.value = bv.s;
    out.bias.setZero();
    out.Wv.setZero();
  }
}

// Row r of Phi_q and G gains c other^T [D, Wm] of one side's vector.
void add_row(double c, const Vec3& other, const VectorEval& e, int r, BlockMatQ& phi_q, BlockMatV& G) {
  for (int k = 0; k < e.D.cols(); ++k) phi_q(r, k) += c * other.dot(e.D.col(k));
  for (int k = 0; k < e.Wm.cols(); ++k) G(r, k) += c * other.dot(e.Wm.col(k));
}

}  // namespace

void evaluate_rows(const ConstraintRow* rows, int nr, const BlockSides& sides, BlockEval& out) {
  size_sides(sides, nr, out, false);
  // A joint's rows name the same body vectors again and again (a spherical
  // joint's three rows e_k . (p_b - p_a) both points in each): each distinct
  // one is evaluated once per call. Exact: the same inputs, the same
  // arithmetic, so the rows are bit for bit those of evaluating each term.
  constexpr int kMemo = 6;
  VectorEval memo[kMemo];
  const BodyVector* keys[kMemo];
  int n_memo = 0;
  VectorEval ca, cb;
  auto eval = [&](const BodyState* st, const BodyVector& bv, VectorEval& constant) -> const VectorEval& {
    if (!st) {
      evaluate_or_constant(nullptr, bv, constant);
      return constant;
    }
    for (int k = 0; k < n_memo; ++k)
      if (keys[k]->body == bv.body && keys[k]->point == bv.point && keys[k]->s == bv.s) return memo[k];
    if (n_memo == kMemo) {  // more distinct vectors than a joint has: not kept
      evaluate_vector(*st, bv, constant);
      return constant;
    }
    keys[n_memo] = &bv;
    evaluate_vector(*st, bv, memo[n_memo]);
    return memo[n_memo++];
  };
  for (int r = 0; r < nr; ++r) {
    out.phi(r) = rows[r].constant;
    for (int t = 0; t < rows[r].n_terms; ++t) {
      const DotTerm& term = rows[r].terms[t];
      int X, Y;
      const BodyState* sa = state_of(sides, term.a, X);
      const BodyState* sb = state_of(sides, term.b, Y);
      const VectorEval& ea = eval(sa, term.a, ca);
      const VectorEval& eb = eval(sb, term.b, cb);
      const double c = term.coeff;
      out.phi(r) += c * ea.value.dot(eb.value);
      out.cacc(r) += c * (eb.value.dot(ea.bias) + ea.value.dot(eb.bias) + 2.0 * ea.Wv.dot(eb.Wv));
      // Column by column (3-vectors of fixed size): Eigen's product of a
      // row with a matrix of run-time width costs several times more here.
      if (sa) add_row(c, eb.value, ea, r, out.phi_q[X], out.G[X]);
      if (sb) add_row(c, ea.value, eb, r, out.phi_q[Y], out.G[Y]);
    }
    for (int x = 0; x < 2; ++x)
      if (sides.state[x])
        for (int k = 0; k < sides.state[x]->nv(); ++k) out.Gv(r) += out.G[x](r, k) * sides.state[x]->v[k];
  }
}

void differentiate_rows(const ConstraintRow* rows, int nr, const BlockSides& sides, const double* const a[2],
                        const double* lambda, const double* mu, BlockEval& out) {
  size_sides(sides, nr, out, true);
  VectorEval e[2];
  Mat3BQ dWw, dWa, dbq;
  Mat3BV dbv;
  MatBVQ Hl;
  MatBQQ Hm;
  for (int r = 0; r < nr; ++r) {
    for (int t = 0; t < rows[r].n_terms; ++t) {
      const DotTerm& term = rows[r].terms[t];
      const BodyVector* bv[2] = {&term.a, &term.b};
      int side[2];
      const BodyState* st[2] = {state_of(sides, term.a, side[0]), state_of(sides, term.b, side[1])};
      for (int i = 0; i < 2; ++i) evaluate_or_constant(st[i], *bv[i], e[i]);
      const double c = term.coeff;
      // The rate of the other vector for w = v and w = a (zero for a constant).
      Vec3 other_wa[2] = {Vec3::Zero(), Vec3::Zero()};
      for (int i = 0; i < 2; ++i)
        if (st[i])
          for (int k = 0; k < st[i]->nv(); ++k) other_wa[1 - i] += e[i].Wm.col(k) * a[side[i]][k];
      for (int i = 0; i < 2; ++i) {
        if (!st[i]) continue;
        const int X = side[i], j = 1 - i;
        const BodyState& b = *st[i];
        const Vec3& other = e[j].value;
        vector_dWw_dq(b, *bv[i], b.v, dWw);
        vector_dWw_dq(b, *bv[i], a[X], dWa);
        vector_dbias_dq(b, *bv[i], dbq);
        vector_dbias_dv(b, *bv[i], dbv);
        out.dGv_q[X].row(r) += c * (other.transpose() * dWw + e[j].Wv.transpose() * e[i].D);
        out.dGa_q[X].row(r) += c * (other.transpose() * dWa + other_wa[i].transpose() * e[i].D);
        out.dc_q[X].row(r) +=
            c * (other.transpose() * dbq + e[j].bias.transpose() * e[i].D + 2.0 * e[j].Wv.transpose() * dWw);
        out.dc_v[X].row(r) += c * (other.transpose() * dbv + 2.0 * e[j].Wv.transpose() * e[i].Wm);
        if (lambda) {
          vector_dWtm_dq(b, *bv[i], (c * lambda[r]) * other, Hl);
          out.HL[X][X] += Hl;
          if (st[j]) out.HL[X][side[j]].noalias() += (c * lambda[r]) * (e[i].Wm.transpose() * e[j].D);
        }
        if (mu) {
          vector_dDtm_dq(b, *bv[i], (c * mu[r]) * other, Hm);
          out.HM[X][X] += Hm;
          if (st[j]) out.HM[X][side[j]].noalias() += (c * mu[r]) * (e[i].D.transpose() * e[j].D);
        }
      }
    }
  }
}

}  // namespace rigidae::multibody
