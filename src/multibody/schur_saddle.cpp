// The Schur-complement KKT solve (equations and conventions in schur_saddle.hpp).
#include "schur_saddle.hpp"

#include <Eigen/OrderingMethods>

#include <algorithm>

namespace rigidae::multibody {

namespace {

constexpr double kSingularPivotRatio = 1e-13;  // multibody_ode.hpp, "Rank"

}  // namespace

std::unique_ptr<SchurSaddle> SchurSaddle::make(const std::vector<KktRange>& bodies,
                                               const std::vector<KktRange>& blocks,
                                               const std::vector<int>& col_start, const std::vector<int>& rows) {
  std::unique_ptr<SchurSaddle> s(new SchurSaddle());
  const int n = static_cast<int>(col_start.size()) - 1;
  for (const KktRange& b : bodies) {
    if (b.size <= 0 || b.size > kMaxBody) return nullptr;
    s->nv_ += b.size;
  }
  for (const KktRange& b : blocks) {
    if (b.size <= 0 || b.size > kMaxRows) return nullptr;
    s->nl_ += b.size;
  }
  if (s->nv_ + s->nl_ != n || s->nl_ == 0) return nullptr;
  std::vector<int> body_of(n, -1), block_of(n, -1);
  for (int i = 0; i < static_cast<int>(bodies.size()); ++i)
    for (int k = 0; k < bodies[i].size; ++k) body_of[bodies[i].start + k] = i;
  for (int j = 0; j < static_cast<int>(blocks.size()); ++j)
    for (int k = 0; k < blocks[j].size; ++k) block_of[blocks[j].start + k] = j;
  s->blocks_ = blocks;
  const int nl = s->nl_, nv = s->nv_;

  // Classify the pattern's entries: M_b, G^T (body rows, block columns), or
  // the parts not read (w_A G, the multipliers' diagonal).
  std::vector<std::vector<int>> mass(bodies.size());
  std::vector<std::vector<std::pair<int, std::vector<int>>>> coupled(bodies.size());  // (block, positions)
  for (std::size_t i = 0; i < bodies.size(); ++i)
    mass[i].assign(static_cast<std::size_t>(bodies[i].size * bodies[i].size), -1);
  for (int c = 0; c < n; ++c)
    for (int e = col_start[c]; e < col_start[c + 1]; ++e) {
      const int r = rows[e];
      const int br = body_of[r], bc = body_of[c], jc = block_of[c];  // -1: not a body's, not a block's
      if (br >= 0 && bc >= 0) {
        if (br != bc) return nullptr;  // the mass matrix couples two bodies
        const KktRange& v = bodies[br];
        mass[br][(r - v.start) + v.size * (c - v.start)] = e;
      } else if (br >= 0 && jc >= 0) {
        const KktRange& v = bodies[br];
        auto& list = coupled[br];
        auto it = std::find_if(list.begin(), list.end(), [&](const auto& x) { return x.first == jc; });
        if (it == list.end()) {
          list.emplace_back(jc, std::vector<int>(v.size * blocks[jc].size, -1));
          it = list.end() - 1;
        }
        it->second[(r - v.start) + v.size * (c - blocks[jc].start)] = e;
      }
    }
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const int m = bodies[i].size;
    Body b;
    b.v = bodies[i];
    if (std::count(mass[i].begin(), mass[i].end(), -1) > 0) return nullptr;
    b.mass = s->idx_.size();
    s->idx_.insert(s->idx_.end(), mass[i].begin(), mass[i].end());
    b.M = s->val_.size();
    b.Minv = b.M + m * m;
    s->val_.resize(b.Minv + m * m, 0.0);
    b.first = static_cast<int>(s->couplings_.size());
    b.count = static_cast<int>(coupled[i].size());
    for (const auto& [block, pos] : coupled[i]) {
      if (std::count(pos.begin(), pos.end(), -1) > 0) return nullptr;
      Coupling c;
      c.block = block;
      c.nr = blocks[block].size;
      c.pos = s->idx_.size();
      s->idx_.insert(s->idx_.end(), pos.begin(), pos.end());
      c.gt = s->val_.size();
      c.w = c.gt + m * c.nr;
      s->val_.resize(c.w + m * c.nr, 0.0);
      s->couplings_.push_back(c);
    }
    s->bodies_.push_back(b);
  }

  // S's pattern (multiplier indices from 0): two blocks sharing a body, and
  // the diagonal; its fill-reducing order.
  std::vector<Eigen::Triplet<double, int>> t;
  for (int k = 0; k < nl; ++k) t.emplace_back(k, k, 1.0);
  for (const Body& b : s->bodies_)
    for (int c1 = b.first; c1 < b.first + b.count; ++c1)
      for (int c2 = b.first; c2 < b.first + b.count; ++c2) {
        const KktRange& r1 = blocks[s->couplings_[c1].block];
        const KktRange& r2 = blocks[s->couplings_[c2].block];
        for (int j = 0; j < r2.size; ++j)
          for (int i = 0; i < r1.size; ++i) t.emplace_back(r1.start - nv + i, r2.start - nv + j, 1.0);
      }
  Sparse full(nl, nl);
  full.setFromTriplets(t.begin(), t.end());
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> P;
  Eigen::AMDOrdering<int> amd;
  amd(full.selfadjointView<Eigen::Upper>(), P);  // P maps new -> old (Eigen's convention for its orderings)
  s->perm_.assign(nl, 0);
  for (int k = 0; k < nl; ++k) s->perm_[P.indices()[k]] = k;
  // The permuted upper triangle, then where each product lands in it.
  std::vector<Eigen::Triplet<double, int>> u;
  u.reserve(t.size());
  for (const auto& e : t) {
    const int a = s->perm_[e.row()], b = s->perm_[e.col()];
    if (a <= b) u.emplace_back(a, b, 0.0);
  }
  s->S_.resize(nl, nl);
  s->S_.setFromTriplets(u.begin(), u.end());  // duplicates summed: one entry each
  s->S_.makeCompressed();
  auto find = [&](int a, int b) -> int {
    if (a > b) return -1;
    const int* begin = s->S_.innerIndexPtr() + s->S_.outerIndexPtr()[b];
    const int* end = s->S_.innerIndexPtr() + s->S_.outerIndexPtr()[b + 1];
    return static_cast<int>(std::lower_bound(begin, end, a) - s->S_.innerIndexPtr());
  };
  s->diag_pos_.resize(nl);
  for (int k = 0; k < nl; ++k) s->diag_pos_[k] = find(s->perm_[k], s->perm_[k]);
  for (Body& b : s->bodies_) {
    b.s_pos = s->spos_.size();
    for (int c1 = b.first; c1 < b.first + b.count; ++c1)
      for (int c2 = b.first; c2 < b.first + b.count; ++c2) {
        const KktRange& r1 = blocks[s->couplings_[c1].block];
        const KktRange& r2 = blocks[s->couplings_[c2].block];
        for (int j = 0; j < r2.size; ++j)
          for (int i = 0; i < r1.size; ++i)
            s->spos_.push_back(find(s->perm_[r1.start - nv + i], s->perm_[r2.start - nv + j]));
      }
  }
  s->ldlt_.analyse(s->S_);
  s->rhs_.setZero(nl);
  s->x_.setZero(nl);
  return s;
}

// One body's part of S: W = M_b^-1 G^T per coupling, then S_12 += (G^T_1)^T
// W_2 over its pairs of couplings. Fixed M (the body's velocities: 6 for a
// free body in the Euler form, 3 for a particle or a pivoted one) lets the
// compiler unroll the inner products; Eigen::Dynamic takes m at run time.
template <int M>
void SchurSaddle::body_products(const Body& b, const double* kkt, const char* active, double* sv) {
  const int m = M == Eigen::Dynamic ? b.v.size : M;
  double* val = val_.data();
  const double* Minv = val + b.Minv;
  for (int ci = b.first; ci < b.first + b.count; ++ci) {
    const Coupling& c = couplings_[ci];
    double* Gt = val + c.gt;
    double* W = val + c.w;
    const int* pos = idx_.data() + c.pos;
    for (int k = 0; k < m * c.nr; ++k) Gt[k] = kkt[pos[k]];
    for (int j = 0; j < c.nr; ++j)
      for (int i = 0; i < m; ++i) {
        double sum = 0.0;
        for (int k = 0; k < m; ++k) sum += Minv[i + m * k] * Gt[k + m * j];
        W[i + m * j] = sum;
      }
  }
  const int* spos = spos_.data() + b.s_pos;
  for (int c1 = b.first; c1 < b.first + b.count; ++c1)
    for (int c2 = b.first; c2 < b.first + b.count; ++c2) {
      const Coupling& k1 = couplings_[c1];
      const Coupling& k2 = couplings_[c2];
      const char* a1 = active + (blocks_[k1.block].start - nv_);
      const char* a2 = active + (blocks_[k2.block].start - nv_);
      for (int j = 0; j < k2.nr; ++j) {
        const double* w = val + k2.w + m * j;
        for (int i = 0; i < k1.nr; ++i) {
          const int p = *spos++;
          if (p < 0 || !a2[j] || !a1[i]) continue;
          const double* g = val + k1.gt + m * i;
          double sum = 0.0;
          for (int k = 0; k < m; ++k) sum += g[k] * w[k];
          sv[p] += sum;
        }
      }
    }
}

SchurSaddle::Outcome SchurSaddle::factorise(const double* kkt, const char* active) {
  active_ = active;
  double* sv = S_.valuePtr();
  std::fill(sv, sv + S_.nonZeros(), 0.0);
  double* val = val_.data();
  for (Body& b : bodies_) {
    const int m = b.v.size;
    // M_b^-1, computed again only when M_b changed (never in the Euler
    // form, where M_b = diag(m I, J) in body axes).
    bool same = b.inverted;
    double* Mb = val + b.M;
    const int* mass = idx_.data() + b.mass;
    for (int k = 0; k < m * m; ++k) {
      const double x = kkt[mass[k]];
      same = same && Mb[k] == x;
      Mb[k] = x;
    }
    if (!same) {
      const Eigen::LLT<BodyMat> llt(Eigen::Map<const Eigen::MatrixXd>(Mb, m, m));
      b.inverted = llt.info() == Eigen::Success;
      if (!b.inverted) return Outcome::NotApplicable;
      BodyMat inverse = BodyMat::Identity(m, m);
      llt.solveInPlace(inverse);
      std::copy(inverse.data(), inverse.data() + m * m, val + b.Minv);
    }
    switch (m) {
      case 3: body_products<3>(b, kkt, active, sv); break;
      case 6: body_products<6>(b, kkt, active, sv); break;
      default: body_products<Eigen::Dynamic>(b, kkt, active, sv); break;
    }
  }
  for (int k = 0; k < nl_; ++k)
    if (!active[k]) sv[diag_pos_[k]] = 1.0;  // lambda_k = 0
  ldlt_.factorise(S_);
  if (ldlt_.info() != Eigen::Success) return Outcome::Singular;
  const auto d = ldlt_.diagonal().cwiseAbs();
  return d.minCoeff() >= kSingularPivotRatio * d.maxCoeff() ? Outcome::Factorised : Outcome::Singular;
}

void SchurSaddle::solve(double* b, const double* inv_weight) {
  // S's right side: G M^-1 r_v - r_l / w_A; 0 for a row set aside (S's row
  // there is the identity's).
  for (int k = 0; k < nl_; ++k) rhs_[perm_[k]] = active_[k] ? -b[nv_ + k] * inv_weight[k] : 0.0;
  const double* val = val_.data();
  for (const Body& body : bodies_) {
    const int m = body.v.size;
    const double* r = b + body.v.start;
    for (int ci = body.first; ci < body.first + body.count; ++ci) {
      const Coupling& c = couplings_[ci];
      const int s0 = blocks_[c.block].start - nv_;
      for (int j = 0; j < c.nr; ++j) {
        if (!active_[s0 + j]) continue;
        const double* w = val + c.w + m * j;
        double sum = 0.0;
        for (int k = 0; k < m; ++k) sum += w[k] * r[k];  // (M_b^-1 G^T)^T r_v
        rhs_[perm_[s0 + j]] += sum;
      }
    }
  }
  x_ = ldlt_.solve(rhs_);
  for (int k = 0; k < nl_; ++k) b[nv_ + k] = x_[perm_[k]];
  // v' = M^-1 (r_v - G^T lambda), body by body.
  double z[kMaxBody];
  for (const Body& body : bodies_) {
    const int m = body.v.size;
    double* r = b + body.v.start;
    for (int k = 0; k < m; ++k) z[k] = r[k];
    for (int ci = body.first; ci < body.first + body.count; ++ci) {
      const Coupling& c = couplings_[ci];
      const double* l = b + blocks_[c.block].start;
      const double* Gt = val + c.gt;
      for (int j = 0; j < c.nr; ++j)
        for (int k = 0; k < m; ++k) z[k] -= Gt[k + m * j] * l[j];
    }
    const double* Minv = val + body.Minv;
    for (int i = 0; i < m; ++i) {
      double sum = 0.0;
      for (int k = 0; k < m; ++k) sum += Minv[i + m * k] * z[k];
      r[i] = sum;
    }
  }
}

}  // namespace rigidae::multibody
