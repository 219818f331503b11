#pragma once
// Functions of time f(t) with their exact first and second derivatives, for
// drivers (prescribed joint motion) and time-dependent loads.
//
// Kinds (t in s; f in the unit of what it drives: rad, m, N, N m):
//   rate        f = f0 + w t                                   f' = w, f'' = 0
//   polynomial  f = sum_k c_k t^k (c_0 first)                  (Horner, with derivatives)
//   harmonic    f = offset + A sin(w t + phase)                f' = A w cos(.), f'' = -A w^2 sin(.)
//   table       knots (t_i, f_i), t_i strictly increasing, at least 2:
//               "spline" (default): the natural cubic spline, C2 (f'' continuous,
//               f'' = 0 at the end knots); "linear": piecewise linear, f'' = 0
//               (f' jumps at the knots: a driver following it has jumps in
//               velocity, so it is for loads).
//               Beyond the ends the table continues as the straight line
//               through its end knot with the end slope (for the spline this
//               keeps f'' continuous, as f'' = 0 there).
// Plain data; evaluate() allocates nothing.
#include <string_view>
#include <vector>

namespace rigidae {

enum class TimeFunctionKind { Rate, Polynomial, Harmonic, Table };

struct TimeFunction {
  TimeFunctionKind kind = TimeFunctionKind::Rate;
  // rate and polynomial: coefficients c_0, c_1, ... of t^k (rate: {f0, w}).
  std::vector<double> coefficients{0.0};
  // harmonic
  double offset = 0.0, amplitude = 0.0, omega = 0.0, phase = 0.0;
  // table: knots, values, and the spline's second derivatives at the knots
  // (zero for "linear").
  std::vector<double> times, values, second;
  bool linear = false;

  // f(t), f'(t), f''(t).
  void evaluate(double t, double& f, double& fd, double& fdd) const;
  double value(double t) const {
    double f, fd, fdd;
    evaluate(t, f, fd, fdd);
    return f;
  }
};

TimeFunction rate_function(double f0, double rate);
TimeFunction polynomial_function(std::vector<double> coefficients);
TimeFunction harmonic_function(double offset, double amplitude, double omega, double phase);
// Throws std::invalid_argument unless times has >= 2 strictly increasing
// finite entries and values the same size.
TimeFunction table_function(std::vector<double> times, std::vector<double> values, bool linear);

// The kinds as scenes name them (`type`), for messages.
std::vector<std::string_view> time_function_type_names();

}  // namespace rigidae
