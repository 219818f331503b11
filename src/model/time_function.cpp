// Functions of time with exact derivatives (conventions in
// include/rigidae/model/time_function.hpp).
//
// Natural cubic spline through (t_i, f_i), h_i = t_{i+1} - t_i, M_i = f''(t_i):
//   h_{i-1} M_{i-1} + 2 (h_{i-1} + h_i) M_i + h_i M_{i+1}
//       = 6 ((f_{i+1} - f_i) / h_i - (f_i - f_{i-1}) / h_{i-1}),  M_0 = M_n = 0
// (tridiagonal, solved once by the Thomas algorithm: diagonally dominant).
// On [t_i, t_{i+1}] with a = (t_{i+1} - t) / h, b = (t - t_i) / h:
//   f   = a f_i + b f_{i+1} + ((a^3 - a) M_i + (b^3 - b) M_{i+1}) h^2 / 6
//   f'  = (f_{i+1} - f_i) / h + ((1 - 3 a^2) M_i + (3 b^2 - 1) M_{i+1}) h / 6
//   f'' = a M_i + b M_{i+1}
#include "rigidae/model/time_function.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rigidae {

void TimeFunction::evaluate(double t, double& f, double& fd, double& fdd) const {
  switch (kind) {
    case TimeFunctionKind::Rate:
    case TimeFunctionKind::Polynomial: {
      // Horner for p, p', p'' together.
      f = fd = fdd = 0.0;
      for (auto c = coefficients.rbegin(); c != coefficients.rend(); ++c) {
        fdd = fdd * t + 2.0 * fd;
        fd = fd * t + f;
        f = f * t + *c;
      }
      return;
    }
    case TimeFunctionKind::Harmonic: {
      const double s = std::sin(omega * t + phase), c = std::cos(omega * t + phase);
      f = offset + amplitude * s;
      fd = amplitude * omega * c;
      fdd = -amplitude * omega * omega * s;
      return;
    }
    case TimeFunctionKind::Table: {
      const std::size_t n = times.size();
      // Beyond the ends: the line through the end knot with the end slope.
      if (t <= times.front() || t >= times.back()) {
        const bool low = t <= times.front();
        const std::size_t i = low ? 0 : n - 2;
        const double h = times[i + 1] - times[i];
        const double slope = (values[i + 1] - values[i]) / h +
                             (low ? -(2.0 * second[i] + second[i + 1]) : (second[i] + 2.0 * second[i + 1])) * h / 6.0;
        const double t_end = low ? times.front() : times.back();
        f = (low ? values.front() : values.back()) + slope * (t - t_end);
        fd = slope;
        fdd = 0.0;  // M = 0 at the ends of a natural spline (and of a linear table)
        return;
      }
      const std::size_t i =
          static_cast<std::size_t>(std::upper_bound(times.begin(), times.end(), t) - times.begin()) - 1;
      const double h = times[i + 1] - times[i];
      const double a = (times[i + 1] - t) / h, b = (t - times[i]) / h;
      const double Mi = second[i], Mj = second[i + 1];
      f = a * values[i] + b * values[i + 1] + ((a * a * a - a) * Mi + (b * b * b - b) * Mj) * h * h / 6.0;
      fd = (values[i + 1] - values[i]) / h + ((1.0 - 3.0 * a * a) * Mi + (3.0 * b * b - 1.0) * Mj) * h / 6.0;
      fdd = a * Mi + b * Mj;
      return;
    }
  }
  f = fd = fdd = 0.0;
}

TimeFunction rate_function(double f0, double rate) {
  TimeFunction fn;
  fn.kind = TimeFunctionKind::Rate;
  fn.coefficients = {f0, rate};
  return fn;
}

TimeFunction polynomial_function(std::vector<double> coefficients) {
  TimeFunction fn;
  fn.kind = TimeFunctionKind::Polynomial;
  fn.coefficients = std::move(coefficients);
  if (fn.coefficients.empty()) fn.coefficients = {0.0};
  return fn;
}

TimeFunction harmonic_function(double offset, double amplitude, double omega, double phase) {
  TimeFunction fn;
  fn.kind = TimeFunctionKind::Harmonic;
  fn.offset = offset;
  fn.amplitude = amplitude;
  fn.omega = omega;
  fn.phase = phase;
  return fn;
}

TimeFunction table_function(std::vector<double> times, std::vector<double> values, bool linear) {
  const std::size_t n = times.size();
  if (n < 2) throw std::invalid_argument("a table needs at least 2 knots");
  if (values.size() != n) throw std::invalid_argument("a table needs as many values as times");
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(times[i]) || !std::isfinite(values[i]))
      throw std::invalid_argument("a table's times and values must be finite");
    if (i > 0 && !(times[i] > times[i - 1])) throw std::invalid_argument("a table's times must increase strictly");
  }
  TimeFunction fn;
  fn.kind = TimeFunctionKind::Table;
  fn.linear = linear;
  fn.second.assign(n, 0.0);
  if (!linear && n > 2) {
    // Interior unknowns M_1 .. M_{n-2}: Thomas algorithm.
    const std::size_t m = n - 2;
    std::vector<double> diag(m), upper(m), rhs(m);
    for (std::size_t k = 0; k < m; ++k) {
      const std::size_t i = k + 1;
      const double h0 = times[i] - times[i - 1], h1 = times[i + 1] - times[i];
      diag[k] = 2.0 * (h0 + h1);
      upper[k] = h1;
      rhs[k] = 6.0 * ((values[i + 1] - values[i]) / h1 - (values[i] - values[i - 1]) / h0);
    }
    for (std::size_t k = 1; k < m; ++k) {
      const double lower = times[k + 1] - times[k];  // h_{i-1} of row k (i = k + 1)
      const double w = lower / diag[k - 1];
      diag[k] -= w * upper[k - 1];
      rhs[k] -= w * rhs[k - 1];
    }
    for (std::size_t k = m; k-- > 0;) {
      const double next = k + 1 < m ? fn.second[k + 2] : 0.0;
      fn.second[k + 1] = (rhs[k] - upper[k] * next) / diag[k];
    }
  }
  fn.times = std::move(times);
  fn.values = std::move(values);
  return fn;
}

std::vector<std::string_view> time_function_type_names() { return {"rate", "polynomial", "harmonic", "table"}; }

}  // namespace rigidae
