#pragma once
// Integral from 0 to x, for any real x, of a smooth periodic function.
//
// The exact solutions' angles about a fixed axis (the free body's angle about
// L, the top's precession and spin) are integrals of periodic rates. The
// integral over one period is computed once, on a partition refined until
// 16-point Gauss-Legendre agrees with its two halves to ~1e-15 of the
// period's total; then G(x) = (whole periods) * G(period) + G(partition
// point) + one 16-point rule on the remainder, which lies inside one piece
// of the partition and so is at least as accurate as that piece.
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <numbers>
#include <stdexcept>
#include <vector>

#include <Eigen/Core>

namespace rigidae::exact::detail {

// Nodes and weights of the 16-point Gauss-Legendre rule on [-1, 1], found
// once by Newton's method on the Legendre polynomial P_16.
struct GaussLegendre16 {
  static constexpr int kN = 16;
  std::array<double, kN> x{};
  std::array<double, kN> w{};
  GaussLegendre16() {
    for (int i = 0; i < kN / 2; ++i) {
      double z = std::cos(std::numbers::pi * (i + 0.75) / (kN + 0.5));
      double dp = 0.0;
      for (int it = 0; it < 100; ++it) {
        // Three-term recurrence for P_n(z) and its derivative.
        double p0 = 1.0;
        double p1 = z;
        for (int n = 2; n <= kN; ++n) {
          const double p2 = ((2.0 * n - 1.0) * z * p1 - (n - 1.0) * p0) / n;
          p0 = p1;
          p1 = p2;
        }
        dp = kN * (z * p1 - p0) / (z * z - 1.0);
        const double dz = p1 / dp;
        z -= dz;
        if (std::abs(dz) < 1e-16) break;
      }
      x[i] = -z;
      x[kN - 1 - i] = z;
      w[i] = w[kN - 1 - i] = 2.0 / ((1.0 - z * z) * dp * dp);
    }
  }
  static const GaussLegendre16& get() {
    static const GaussLegendre16 rule;
    return rule;
  }
};

template <int Dim>
class PeriodicIntegral {
 public:
  using Value = Eigen::Matrix<double, Dim, 1>;
  using Integrand = std::function<Value(double)>;

  PeriodicIntegral() = default;
  // `typical_width`: a length over which the integrand is smooth (it sets the
  // starting partition; refinement takes care of the rest).
  PeriodicIntegral(Integrand g, double period, double typical_width) : g_(std::move(g)), period_(period) {
    if (!(period > 0.0) || !std::isfinite(period)) throw std::invalid_argument("PeriodicIntegral: bad period");
    const int n0 = std::clamp(static_cast<int>(std::ceil(period / typical_width)), 4, 4096);
    // Scale for the absolute tolerance: the integral of |g| on the start partition.
    double scale = 0.0;
    for (int i = 0; i < n0; ++i)
      scale += rule_abs(period * i / n0, period * (i + 1) / n0);
    tol_ = 1e-15 * std::max(scale, 1e-300);
    breaks_.push_back(0.0);
    cumulative_.push_back(Value::Zero());
    for (int i = 0; i < n0; ++i) refine(period * i / n0, period * (i + 1) / n0, 0);
    total_ = cumulative_.back();
  }

  // G(x) = integral_0^x g.
  Value operator()(double x) const {
    const double periods = std::floor(x / period_);
    double r = x - periods * period_;
    r = std::clamp(r, 0.0, period_);
    const auto it = std::upper_bound(breaks_.begin(), breaks_.end(), r);
    const std::size_t j = static_cast<std::size_t>(std::max<std::ptrdiff_t>(0, (it - breaks_.begin()) - 1));
    Value g = periods * total_ + cumulative_[j];
    if (r > breaks_[j]) g += rule(breaks_[j], r);
    return g;
  }

  double period() const { return period_; }
  Value over_one_period() const { return total_; }

 private:
  Value rule(double a, double b) const {
    const auto& gl = GaussLegendre16::get();
    const double h = 0.5 * (b - a);
    const double c = 0.5 * (a + b);
    Value s = Value::Zero();
    for (int i = 0; i < GaussLegendre16::kN; ++i) s += gl.w[i] * g_(c + h * gl.x[i]);
    return h * s;
  }
  double rule_abs(double a, double b) const {
    const auto& gl = GaussLegendre16::get();
    const double h = 0.5 * (b - a);
    const double c = 0.5 * (a + b);
    double s = 0.0;
    for (int i = 0; i < GaussLegendre16::kN; ++i) s += gl.w[i] * g_(c + h * gl.x[i]).cwiseAbs().sum();
    return h * s;
  }
  void refine(double a, double b, int depth) {
    const Value whole = rule(a, b);
    const double mid = 0.5 * (a + b);
    const Value halves = rule(a, mid) + rule(mid, b);
    if ((whole - halves).cwiseAbs().maxCoeff() <= tol_ || depth >= 30) {
      breaks_.push_back(b);
      cumulative_.push_back(cumulative_.back() + whole);
      return;
    }
    refine(a, mid, depth + 1);
    refine(mid, b, depth + 1);
  }

  Integrand g_;
  double period_ = 1.0;
  double tol_ = 0.0;
  std::vector<double> breaks_;
  std::vector<Value> cumulative_;
  Value total_ = Value::Zero();
};

}  // namespace rigidae::exact::detail
