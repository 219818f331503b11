// The pattern from the recorded group pairs (see jacobian_sink.hpp).
#include "rigidae/multibody/jacobian_sink.hpp"

#include <algorithm>
#include <set>

namespace rigidae::multibody {

SparsityPattern JacobianSink::finish_recording() {
  const int ng = static_cast<int>(groups_.size());
  std::set<std::pair<int, int>> pairs;  // (column group, row group)
  for (const std::int64_t k : recorded_) pairs.insert({static_cast<int>(k % ng), static_cast<int>(k / ng)});
  recorded_.clear();
  recorded_.shrink_to_fit();
  int n = 0;
  for (const UnknownGroup& g : groups_) n = std::max(n, g.offset + g.size);
  // Row groups of each column group, ascending by row offset.
  std::vector<std::vector<int>> rows_of(ng);
  for (const auto& [cg, rg] : pairs) rows_of[cg].push_back(rg);
  for (auto& v : rows_of)
    std::sort(v.begin(), v.end(), [&](int a, int b) { return groups_[a].offset < groups_[b].offset; });
  SparsityPattern p;
  p.col_start.assign(n + 1, 0);
  std::vector<int> group_of_column(n, -1);
  for (int g = 0; g < ng; ++g)
    for (int c = 0; c < groups_[g].size; ++c) group_of_column[groups_[g].offset + c] = g;
  pair_start_.assign(ng, {});
  bases_.clear();
  for (int cg = 0; cg < ng; ++cg)
    for (int rg : rows_of[cg]) {
      pair_start_[rg].emplace_back(cg, static_cast<std::int64_t>(bases_.size()));
      bases_.resize(bases_.size() + groups_[cg].size, 0);
    }
  for (int c = 0; c < n; ++c) {
    p.col_start[c] = p.nnz();
    const int cg = group_of_column[c];
    if (cg < 0) continue;
    const int local = c - groups_[cg].offset;
    for (int rg : rows_of[cg]) {
      bases_[pair_start(rg, cg) + local] = p.nnz();
      for (int i = 0; i < groups_[rg].size; ++i) p.rows.push_back(groups_[rg].offset + i);
    }
  }
  p.col_start[n] = p.nnz();
  mode_ = Mode::Dense;
  return p;
}

std::unique_ptr<JacobianSink> JacobianSink::remapped(const std::vector<std::int64_t>& position) const {
  auto out = std::make_unique<JacobianSink>(*this);
  for (std::int64_t& b : out->bases_) b = position[static_cast<std::size_t>(b)];
  out->mode_ = Mode::Sparse;
  out->values_ = nullptr;
  return out;
}

void JacobianSink::add_diagonal(int g, double s) {
  const int m = groups_[g].size;
  if (m == 0) return;
  switch (mode_) {
    case Mode::Record: recorded_.push_back(key(g, g)); return;
    case Mode::Dense:
      for (int i = 0; i < m; ++i) dense_[static_cast<std::size_t>(groups_[g].offset + i) * (n_ + 1)] += s;
      return;
    case Mode::Sparse: {
      const std::int64_t* base = bases_.data() + pair_start(g, g);
      for (int i = 0; i < m; ++i) values_[base[i] + i] += s;
      return;
    }
  }
}

}  // namespace rigidae::multibody
