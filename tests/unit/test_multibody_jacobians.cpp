// Multibody: the exact iteration matrix (dense and sparse) equals
// Richardson-extrapolated central differences of the residual for every joint
// kind x representation x form x scheme, at the consistent start and at a
// perturbed, inconsistent state; the residual vanishes at the start; the
// residual and both iteration matrices allocate nothing.
#include <doctest/doctest.h>

#include <algorithm>
#include <random>
#include <string>

#include "alloc_counter.hpp"
#include "rigidae/multibody/multibody_problem.hpp"
#include "rigidae/schemes/scheme.hpp"
#include "test_multibody_scenes.hpp"

TEST_SUITE_BEGIN("unit");

using namespace rigidae;
using multibody::MultibodyProblem;

namespace {

const Coordinates kCoordinates[] = {Coordinates::EulerAngles, Coordinates::Quaternion, Coordinates::Linear};
const Equations kEquations[] = {Equations::Lagrange, Equations::Euler};
// Row-relative largest difference (rows are equations with their own units).
double row_relative_difference(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B) {
  double worst = 0.0;
  for (int i = 0; i < A.rows(); ++i) {
    const double scale = std::max({A.row(i).cwiseAbs().maxCoeff(), B.row(i).cwiseAbs().maxCoeff(), 1e-300});
    worst = std::max(worst, (A.row(i) - B.row(i)).cwiseAbs().maxCoeff() / scale);
  }
  return worst;
}

// dF/dy + cj dF/dy' by central differences, Richardson-extrapolated:
// (4 D(d/2) - D(d)) / 3, d = 1e-3 max(1, |y_j|) (as in test_jacobians.cpp).
Eigen::MatrixXd richardson_matrix(MultibodyProblem& p, double t, double cj, const Eigen::VectorXd& y,
                                  const Eigen::VectorXd& yp) {
  const int n = p.size();
  Eigen::MatrixXd J(n, n);
  Eigen::VectorXd Fp(n), Fm(n);
  Eigen::VectorXd yy = y, yyp = yp;
  const auto difference = [&](Eigen::VectorXd& x, int j, double d, bool in_yp) {
    const double xj = x(j);
    x(j) = xj + d;
    p.residual(t, in_yp ? y.data() : x.data(), in_yp ? x.data() : yp.data(), Fp.data());
    x(j) = xj - d;
    p.residual(t, in_yp ? y.data() : x.data(), in_yp ? x.data() : yp.data(), Fm.data());
    x(j) = xj;
    return Eigen::VectorXd((Fp - Fm) / (2.0 * d));
  };
  for (int j = 0; j < n; ++j) {
    const double d = 1e-3 * std::max(1.0, std::abs(y(j)));
    J.col(j) = (4.0 * difference(yy, j, 0.5 * d, false) - difference(yy, j, d, false)) / 3.0;
    const double dp = 1e-3 * std::max(1.0, std::abs(yp(j)));
    J.col(j) += cj * (4.0 * difference(yyp, j, 0.5 * dp, true) - difference(yyp, j, dp, true)) / 3.0;
  }
  return J;
}

Eigen::MatrixXd sparse_to_dense(const SparsityPattern& p, const Eigen::VectorXd& values, int n) {
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(n, n);
  for (int c = 0; c < n; ++c)
    for (std::int64_t k = p.col_start[c]; k < p.col_start[c + 1]; ++k) J(p.rows[k], c) = values(k);
  return J;
}

// 1e-8 as for one body: measured differences are ~1e-10 (see the MESSAGE),
// while a wrong term changes its rows by O(1).
constexpr double kMatrixTolerance = 1e-8;

}  // namespace

TEST_CASE("multibody: exact iteration matrix = differences, every joint x representation x form x scheme" * doctest::test_suite("slow")) {
  std::mt19937 rng(4242);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double worst = 0.0, worst_start_residual = 0.0;
  for (const JointType* jt : joint_types())  // every registered type (model/joint_type.hpp)
    for (Coordinates c : kCoordinates)
      for (Equations e : kEquations)
        for (const std::string& scheme : scheme_names()) {
          const Scene s = test::two_body_chain(jt, c, e, scheme);
          MultibodyProblem p(s);
          const int n = p.size();
          CAPTURE(jt->name);
          CAPTURE(to_string(c) + "/" + to_string(e) + "/" + scheme);
          Eigen::VectorXd y, yp;
          p.initial_state(0.0, y, yp);
          // The start is consistent: the residual vanishes to round-off.
          Eigen::VectorXd F(n);
          REQUIRE(p.residual(0.0, y.data(), yp.data(), F.data()));
          const double scale = std::max({1.0, y.cwiseAbs().maxCoeff(), yp.cwiseAbs().maxCoeff()});
          worst_start_residual = std::max(worst_start_residual, F.cwiseAbs().maxCoeff() / scale);
          CHECK(F.cwiseAbs().maxCoeff() < 1e-10 * scale);
          for (int k = 0; k < 2; ++k) {
            Eigen::VectorXd yk = y, ypk = yp;
            if (k == 1)
              for (int i = 0; i < n; ++i) {
                yk(i) += 0.05 * u(rng) * std::max(1.0, std::abs(y(i)));
                ypk(i) += 0.05 * u(rng) * std::max(1.0, std::abs(yp(i)));
              }
            const double cj = k == 0 ? 3.7 : 250.0;
            Eigen::MatrixXd dense(n, n);
            p.iteration_matrix_dense(0.2, cj, yk.data(), ypk.data(), dense.data());
            Eigen::VectorXd values(p.sparsity().nnz());
            p.iteration_matrix_sparse(0.2, cj, yk.data(), ypk.data(), values.data());
            const Eigen::MatrixXd sparse = sparse_to_dense(p.sparsity(), values, n);
            const Eigen::MatrixXd reference = richardson_matrix(p, 0.2, cj, yk, ypk);
            const double d = row_relative_difference(dense, reference);
            worst = std::max(worst, d);
            CAPTURE(k);
            CHECK(d < kMatrixTolerance);
            // The sparse values are the dense matrix on the pattern, and the
            // pattern holds every nonzero.
            CHECK((sparse - dense).cwiseAbs().maxCoeff() == 0.0);
          }
        }
  MESSAGE("largest row-relative difference: " << worst << "; largest start residual: " << worst_start_residual);
}

TEST_CASE("multibody: residual and iteration matrices allocate nothing") {
  for (Coordinates c : kCoordinates)
    for (Equations e : kEquations)
      for (const std::string& scheme : scheme_names()) {
        const Scene s = test::two_body_chain(&joint_type("revolute"), c, e, scheme);
        MultibodyProblem p(s);
        const int n = p.size();
        Eigen::VectorXd y, yp, F(n), values(p.sparsity().nnz());
        Eigen::MatrixXd J(n, n);
        p.initial_state(0.0, y, yp);
        test::start_counting_allocations();
        p.residual(0.1, y.data(), yp.data(), F.data());
        p.iteration_matrix_dense(0.1, 50.0, y.data(), yp.data(), J.data());
        p.iteration_matrix_sparse(0.1, 50.0, y.data(), yp.data(), values.data());
        const long allocations = test::stop_counting_allocations();
        CAPTURE(to_string(c) + "/" + to_string(e) + "/" + scheme);
        CHECK(allocations == 0);
      }
}

TEST_CASE("multibody: the sparse pattern of a chain grows linearly with the number of links") {
  for (Coordinates c : kCoordinates)
    for (Equations e : kEquations) {
      CAPTURE(to_string(c) + "/" + to_string(e));
      std::int64_t nnz[3];
      const int n[3] = {10, 20, 40};
      for (int k = 0; k < 3; ++k) {
        const MultibodyProblem p(test::spherical_chain(n[k], c, e, "ggl"));
        nnz[k] = p.sparsity().nnz();
      }
      // nnz = a N + b exactly: each link adds its own blocks and one joint's.
      CHECK(nnz[2] - nnz[1] == 2 * (nnz[1] - nnz[0]));
      MESSAGE(to_string(c) << "/" << to_string(e) << ": nonzeros per link " << (nnz[1] - nnz[0]) / 10);
    }
}

TEST_SUITE_END();
