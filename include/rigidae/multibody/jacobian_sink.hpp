#pragma once
// Where the assembler writes iteration-matrix blocks: a dense matrix, the
// values of a fixed sparse pattern, or (once, at construction) a recorder of
// which group pairs are written, from which the pattern is built.
//
// Unknowns come in groups (a body's coordinates, its velocities, a block's
// lambda, its mu); rows are grouped the same way (kinematic rows like q,
// dynamic rows like v, constraint rows like their multipliers). Every write
// is a dense sub-block of one (row group, column group) pair, and the pattern
// holds whole pairs, so the rows of a pair are contiguous in every column and
// a write scatters by precomputed offsets. Writes never depend on values,
// so the recorded pattern holds every nonzero of any state.
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "rigidae/solver/problem.hpp"

namespace rigidae::multibody {

struct UnknownGroup {
  int offset = 0, size = 0;
};

class JacobianSink {
 public:
  explicit JacobianSink(const std::vector<UnknownGroup>& groups) : groups_(groups) {}

  // Recording: notes the pairs written; builds the pattern from them.
  void start_recording() { mode_ = Mode::Record; }
  SparsityPattern finish_recording();

  void start_dense(double* J, int n) {
    mode_ = Mode::Dense;
    dense_ = J;
    n_ = n;
  }
  void start_sparse(double* values) {
    mode_ = Mode::Sparse;
    values_ = values;
  }

  // Adds B at (r0, c0) inside the block of (row group rg, column group cg).
  template <class Derived>
  void add(int rg, int cg, int r0, int c0, const Eigen::MatrixBase<Derived>& B) {
    const int rows = static_cast<int>(B.rows()), cols = static_cast<int>(B.cols());
    if (rows == 0 || cols == 0) return;
    switch (mode_) {
      case Mode::Record: recorded_.push_back(key(rg, cg)); return;
      case Mode::Dense: {
        const int r = groups_[rg].offset + r0, c = groups_[cg].offset + c0;
        for (int j = 0; j < cols; ++j)
          for (int i = 0; i < rows; ++i) dense_[static_cast<std::size_t>(c + j) * n_ + r + i] += B(i, j);
        return;
      }
      case Mode::Sparse: {
        const std::int64_t* base = bases_.data() + pair_start(rg, cg);
        for (int j = 0; j < cols; ++j)
          for (int i = 0; i < rows; ++i) values_[base[c0 + j] + r0 + i] += B(i, j);
        return;
      }
    }
  }
  // Adds s on the diagonal of the (g, g) block.
  void add_diagonal(int g, double s);

  // A sparse sink over another array: the pattern's entry i is written to
  // position[i] (a sub-pattern's compressed columns: the ODE form's KKT
  // block). Every pair is either wholly kept, its rows contiguous there as
  // here, or wholly sent to one scratch range [dump, dump + largest group)
  // that the caller ignores (position[i] = dump for all its entries).
  std::unique_ptr<JacobianSink> remapped(const std::vector<std::int64_t>& position) const;

 private:
  enum class Mode { Record, Dense, Sparse };
  std::int64_t key(int rg, int cg) const { return static_cast<std::int64_t>(rg) * groups_.size() + cg; }
  // Where pair (rg, cg)'s column offsets start in bases_: a row group pairs
  // with a handful of column groups (its body's, its joints'), so a short
  // scan beats hashing (measured: the hash lookup was ~3 % of a 1000-link
  // chain's right-hand side).
  std::int64_t pair_start(int rg, int cg) const {
    for (const auto& [c, start] : pair_start_[rg])
      if (c == cg) return start;
    return -1;  // not recorded: the assembler writes only recorded pairs
  }

  std::vector<UnknownGroup> groups_;
  Mode mode_ = Mode::Dense;
  double* dense_ = nullptr;
  int n_ = 0;
  double* values_ = nullptr;
  std::vector<std::int64_t> recorded_;
  // Per row group, per recorded pair (column group, where its column
  // offsets start in bases_); bases_[k] is the index in the values of the
  // pair's first row in its k-th column.
  std::vector<std::vector<std::pair<int, std::int64_t>>> pair_start_;
  std::vector<std::int64_t> bases_;
};

}  // namespace rigidae::multibody
