// rigidae's own Butcher tables (src/solver/butcher_table.hpp) against the
// order conditions of Runge-Kutta methods: for every rooted tree t with at
// most p vertices, sum_i b_i Phi_i(t) = 1 / gamma(t) (Butcher; Hairer,
// Norsett, Wanner, Solving ODEs I, II.2), where Phi_i of the one-vertex tree
// is 1, Phi_i of a tree whose root carries the subtrees t_1..t_m is
// prod_k sum_j a_ij Phi_j(t_k), and gamma(t) = |t| prod_k gamma(t_k).
#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include "solver/butcher_table.hpp"

TEST_SUITE_BEGIN("unit");

namespace {

struct RootedTree {
  int order = 1;
  double gamma = 1.0;
  std::vector<double> phi;  // per stage
};

// Every rooted tree with up to max_order vertices, each once: a tree is its
// root's multiset of subtrees, generated as non-increasing lists of indices
// into the trees already made (all of lower order).
std::vector<RootedTree> rooted_trees(const rigidae::ode::ButcherTable& t, int max_order) {
  const int s = t.stages;
  std::vector<RootedTree> trees;
  trees.push_back({1, 1.0, std::vector<double>(static_cast<std::size_t>(s), 1.0)});
  for (int n = 2; n <= max_order; ++n) {
    const std::size_t made = trees.size();
    std::vector<std::size_t> children;
    // Subtrees chosen so far (children), their orders summing to n - 1 - rest.
    auto grow = [&](auto&& self, int rest, std::size_t largest) -> void {
      if (rest == 0) {
        RootedTree tree{n, static_cast<double>(n), std::vector<double>(static_cast<std::size_t>(s), 1.0)};
        for (std::size_t c : children) {
          tree.gamma *= trees[c].gamma;
          for (int i = 0; i < s; ++i) {
            double a_phi = 0.0;
            for (int j = 0; j < i; ++j)
              a_phi += t.a[static_cast<std::size_t>(i * s + j)] * trees[c].phi[static_cast<std::size_t>(j)];
            tree.phi[static_cast<std::size_t>(i)] *= a_phi;
          }
        }
        trees.push_back(tree);
        return;
      }
      for (std::size_t c = 0; c <= largest && c < made; ++c) {
        if (trees[c].order > rest) continue;
        children.push_back(c);
        self(self, rest - trees[c].order, c);
        children.pop_back();
      }
    };
    grow(grow, n - 1, made - 1);
  }
  return trees;
}

// The largest |sum_i w_i Phi_i(t) - 1/gamma(t)| over the trees of one order.
double worst_condition(const std::vector<RootedTree>& trees, const std::vector<double>& w, int order) {
  double worst = 0.0;
  for (const RootedTree& tree : trees) {
    if (tree.order != order) continue;
    double sum = 0.0;
    for (std::size_t i = 0; i < w.size(); ++i) sum += w[i] * tree.phi[i];
    worst = std::max(worst, std::abs(sum - 1.0 / tree.gamma));
  }
  return worst;
}

}  // namespace

TEST_CASE("Prince-Dormand 8(7): b meets all 200 order conditions up to order 8, d those up to order 7 and not 8") {
  const rigidae::ode::ButcherTable& t = rigidae::ode::prince_dormand_87();
  REQUIRE(t.stages == 13);
  REQUIRE(t.a.size() == 169);
  const std::vector<RootedTree> trees = rooted_trees(t, 8);
  // The number of rooted trees of orders 1..8 (OEIS A000081): the generator's own check.
  const int count[] = {1, 1, 2, 4, 9, 20, 48, 115};
  for (int n = 1; n <= 8; ++n) {
    CAPTURE(n);
    long made = 0;
    for (const RootedTree& tree : trees) made += tree.order == n;
    CHECK(made == count[n - 1]);
    // The published coefficients are rational approximations good to
    // ~1e-18; the sums here, of terms up to ~20, round to ~2e-15. (A digit
    // transposed in d_1's denominator, 455176632 for 455176623, misses the
    // first condition by 6e-10.)
    CHECK(worst_condition(trees, t.b, n) < 1e-13);
    if (n <= 7) CHECK(worst_condition(trees, t.d, n) < 1e-13);
  }
  // An embedded solution of order exactly 7: its difference from b's is the
  // error estimate, which must not vanish at order 8.
  CHECK(worst_condition(trees, t.d, 8) > 1e-6);
  // The published nodes (c_i = sum_j a_ij).
  const double c[] = {0.0, 1.0 / 18, 1.0 / 12, 1.0 / 8, 5.0 / 16, 3.0 / 8, 59.0 / 400, 93.0 / 200,
                      5490023248.0 / 9719169821.0, 13.0 / 20, 1201146811.0 / 1299019798.0, 1.0, 1.0};
  for (int i = 0; i < 13; ++i) CHECK(t.c[static_cast<std::size_t>(i)] == doctest::Approx(c[i]).epsilon(1e-15));
  for (int i = 0; i < 13; ++i)
    for (int j = i; j < 13; ++j) CHECK(t.a[static_cast<std::size_t>(i * 13 + j)] == 0.0);
}

TEST_SUITE_END();
