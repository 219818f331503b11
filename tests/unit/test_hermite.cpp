// Hermite interpolation (include/rigidae/core/hermite.hpp), against
// polynomials it must reproduce and the error formula.
#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include "rigidae/core/hermite.hpp"

TEST_SUITE_BEGIN("unit");

using rigidae::hermite_coefficients;
using rigidae::hermite_value;

namespace {

// f on the nodes: values and derivatives as one-component vectors.
template <typename F, typename D>
void data(const std::vector<double>& nodes, F f, D d, std::vector<Eigen::VectorXd>& v, std::vector<Eigen::VectorXd>& dv) {
  for (double t : nodes) {
    v.push_back(Eigen::VectorXd::Constant(1, f(t)));
    dv.push_back(Eigen::VectorXd::Constant(1, d(t)));
  }
}

}  // namespace

TEST_CASE("hermite: three nodes reproduce a quintic and its derivative, also beyond the nodes") {
  const auto f = [](double t) { return 1.0 - 2.0 * t + 0.5 * t * t + 3.0 * std::pow(t, 3) - std::pow(t, 4) + 0.25 * std::pow(t, 5); };
  const auto d = [](double t) { return -2.0 + t + 9.0 * t * t - 4.0 * std::pow(t, 3) + 1.25 * std::pow(t, 4); };
  const std::vector<double> nodes{-0.3, 0.1, 0.4};
  std::vector<Eigen::VectorXd> v, dv;
  data(nodes, f, d, v, dv);
  std::vector<double> z;
  std::vector<Eigen::VectorXd> c;
  hermite_coefficients(nodes, {&v[0], &v[1], &v[2]}, {&dv[0], &dv[1], &dv[2]}, 1, z, c);
  for (double t : {-0.3, 0.0, 0.4, 0.7, 1.2}) {
    Eigen::VectorXd p, dp;
    hermite_value(z, c, t, p, &dp);
    CHECK(p(0) == doctest::Approx(f(t)).epsilon(1e-12));
    CHECK(dp(0) == doctest::Approx(d(t)).epsilon(1e-12));
  }
}

TEST_CASE("hermite: the extrapolation error of sin follows f^(2K) / (2K)! prod (t - t_i)^2") {
  // K = 3 nodes, degree 5: |error| <= max|sin^(6)| / 6! prod (t - t_i)^2,
  // and for a small reach the error is that bound's size (sin^(6) = -sin,
  // near 1 here), so the bound is checked from both sides.
  const std::vector<double> nodes{1.0, 1.05, 1.1};
  std::vector<Eigen::VectorXd> v, dv;
  data(nodes, [](double t) { return std::sin(t); }, [](double t) { return std::cos(t); }, v, dv);
  std::vector<double> z;
  std::vector<Eigen::VectorXd> c;
  hermite_coefficients(nodes, {&v[0], &v[1], &v[2]}, {&dv[0], &dv[1], &dv[2]}, 1, z, c);
  for (double t : {1.12, 1.15, 1.2}) {
    Eigen::VectorXd p;
    hermite_value(z, c, t, p, nullptr);
    double prod = 1.0;
    for (double ti : nodes) prod *= (t - ti) * (t - ti);
    const double bound = prod / 720.0;  // |sin^(6)| <= 1
    const double error = std::abs(p(0) - std::sin(t));
    CAPTURE(t);
    CHECK(error <= bound);
    CHECK(error >= 0.8 * std::sin(1.0) * bound);  // sin(xi) >= sin(1) on [1, 1.2]
  }
}

TEST_SUITE_END();
