// Time functions (model/time_function.hpp): f, f', f'' against closed forms
// and against central differences of f and f'; the natural spline
// interpolates its knots, reproduces a straight line exactly, has f'' = 0 at
// the end knots, is C2 across interior knots, and continues as a line
// beyond its ends; a linear table interpolates linearly.
#include <doctest/doctest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "rigidae/model/time_function.hpp"

TEST_SUITE_BEGIN("unit");

namespace {

using rigidae::TimeFunction;

// Central differences of f and f' at t agree with f' and f''.
void check_differences(const TimeFunction& fn, double t, double tol) {
  const double h = 1e-5;
  double f0, d0, a0, fp, dp, ap, fm, dm, am;
  fn.evaluate(t, f0, d0, a0);
  fn.evaluate(t + h, fp, dp, ap);
  fn.evaluate(t - h, fm, dm, am);
  CHECK(std::abs((fp - fm) / (2 * h) - d0) <= tol * (1 + std::abs(d0)));
  CHECK(std::abs((dp - dm) / (2 * h) - a0) <= tol * (1 + std::abs(a0)));
}

}  // namespace

TEST_CASE("time functions: rate, polynomial and harmonic against closed forms and differences") {
  const TimeFunction rate = rigidae::rate_function(0.3, 6.5);
  double f, d, a;
  rate.evaluate(2.0, f, d, a);
  CHECK(f == doctest::Approx(0.3 + 13.0).epsilon(1e-15));
  CHECK(d == 6.5);
  CHECK(a == 0.0);

  const TimeFunction poly = rigidae::polynomial_function({1.0, -2.0, 0.5, 0.25});
  for (double t : {-1.3, 0.0, 0.7, 2.9}) {
    poly.evaluate(t, f, d, a);
    CHECK(f == doctest::Approx(1 - 2 * t + 0.5 * t * t + 0.25 * t * t * t).epsilon(1e-14));
    CHECK(d == doctest::Approx(-2 + t + 0.75 * t * t).epsilon(1e-14));
    CHECK(a == doctest::Approx(1 + 1.5 * t).epsilon(1e-14));
    check_differences(poly, t, 1e-8);
  }

  const TimeFunction harm = rigidae::harmonic_function(0.1, 2.0, 3.0, 0.4);
  for (double t : {0.0, 0.37, 1.9}) {
    harm.evaluate(t, f, d, a);
    CHECK(f == doctest::Approx(0.1 + 2 * std::sin(3 * t + 0.4)).epsilon(1e-14));
    CHECK(d == doctest::Approx(6 * std::cos(3 * t + 0.4)).epsilon(1e-14));
    CHECK(a == doctest::Approx(-18 * std::sin(3 * t + 0.4)).epsilon(1e-14));
    check_differences(harm, t, 1e-8);
  }
}

TEST_CASE("time functions: the natural cubic spline table") {
  const std::vector<double> ts{0.0, 0.4, 1.0, 1.5, 2.5}, fs{0.0, 1.0, -0.5, 0.2, 2.0};
  const TimeFunction sp = rigidae::table_function(ts, fs, false);
  double f, d, a;
  // Interpolates the knots.
  for (std::size_t i = 0; i < ts.size(); ++i) CHECK(sp.value(ts[i]) == doctest::Approx(fs[i]).epsilon(1e-14));
  // f'' = 0 at the end knots (natural), and continuous across interior knots
  // (C2): values just left and right agree.
  sp.evaluate(ts.front(), f, d, a);
  CHECK(std::abs(a) < 1e-14);
  sp.evaluate(ts.back(), f, d, a);
  CHECK(std::abs(a) < 1e-14);
  for (std::size_t i = 1; i + 1 < ts.size(); ++i) {
    double fl, dl, al, fr, dr, ar;
    sp.evaluate(ts[i] - 1e-12, fl, dl, al);
    sp.evaluate(ts[i] + 1e-12, fr, dr, ar);
    CHECK(std::abs(dl - dr) < 1e-9);
    CHECK(std::abs(al - ar) < 1e-9);
    CHECK(std::abs(al) > 1e-3);  // the curvature is not trivially zero
  }
  // Derivatives against differences inside the intervals.
  for (double t : {0.1, 0.55, 1.2, 2.0}) check_differences(sp, t, 1e-7);
  // Beyond the ends: the line with the end value and slope.
  double fe, de, ae;
  sp.evaluate(ts.back(), fe, de, ae);
  sp.evaluate(ts.back() + 0.7, f, d, a);
  CHECK(f == doctest::Approx(fe + 0.7 * de).epsilon(1e-14));
  CHECK(d == doctest::Approx(de).epsilon(1e-14));
  CHECK(a == 0.0);
  sp.evaluate(ts.front(), fe, de, ae);
  sp.evaluate(ts.front() - 0.3, f, d, a);
  CHECK(f == doctest::Approx(fe - 0.3 * de).epsilon(1e-14));
  // A straight line is reproduced exactly (every M_i = 0).
  const TimeFunction line = rigidae::table_function({0.0, 1.0, 3.0, 3.5}, {1.0, 3.0, 7.0, 8.0}, false);
  for (double t : {0.3, 1.7, 3.2}) {
    line.evaluate(t, f, d, a);
    CHECK(f == doctest::Approx(1 + 2 * t).epsilon(1e-14));
    CHECK(d == doctest::Approx(2.0).epsilon(1e-14));
    CHECK(std::abs(a) < 1e-13);
  }
  // A smooth function is approximated to O(h^4) inside: sin on 41 knots.
  std::vector<double> kt, kv;
  for (int i = 0; i <= 40; ++i) kt.push_back(i * 0.1), kv.push_back(std::sin(i * 0.1));
  const TimeFunction s = rigidae::table_function(kt, kv, false);
  CHECK(std::abs(s.value(2.05) - std::sin(2.05)) < 1e-5);
}

TEST_CASE("time functions: the linear table and bad tables") {
  const TimeFunction lin = rigidae::table_function({0.0, 1.0, 2.0}, {0.0, 2.0, 1.0}, true);
  double f, d, a;
  lin.evaluate(0.25, f, d, a);
  CHECK(f == doctest::Approx(0.5));
  CHECK(d == doctest::Approx(2.0));
  CHECK(a == 0.0);
  lin.evaluate(1.5, f, d, a);
  CHECK(f == doctest::Approx(1.5));
  CHECK(d == doctest::Approx(-1.0));
  lin.evaluate(3.0, f, d, a);  // beyond the end: the last segment's line
  CHECK(f == doctest::Approx(0.0));
  CHECK_THROWS_AS(rigidae::table_function({0.0}, {1.0}, false), std::invalid_argument);
  CHECK_THROWS_AS(rigidae::table_function({0.0, 0.0}, {1.0, 2.0}, false), std::invalid_argument);
  CHECK_THROWS_AS(rigidae::table_function({0.0, 1.0}, {1.0}, false), std::invalid_argument);
}

TEST_SUITE_END();
