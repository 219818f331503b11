// A function of time from a scene table (syntax in time_function_reader.hpp).
#include "time_function_reader.hpp"

#include <fmt/format.h>

#include <array>
#include <stdexcept>
#include <vector>

namespace rigidae::io::detail {

namespace {

constexpr std::array<std::string_view, 4> kTypes{"rate", "polynomial", "harmonic", "table"};
constexpr std::array<std::string_view, 3> kRateKeys{"type", "value", "rate"};
constexpr std::array<std::string_view, 2> kPolynomialKeys{"type", "coefficients"};
constexpr std::array<std::string_view, 5> kHarmonicKeys{"type", "offset", "amplitude", "omega", "phase"};
constexpr std::array<std::string_view, 4> kTableKeys{"type", "times", "values", "interpolation"};
constexpr std::array<std::string_view, 2> kInterpolations{"spline", "linear"};
// Coefficients and table lengths beyond these are input mistakes.
constexpr std::size_t kMaxCoefficients = 16;
constexpr std::size_t kMaxKnots = 1000000;

std::vector<double> numbers(const TomlReader& r, const toml::node& n, const std::string& name, std::size_t min,
                            std::size_t max, std::string_view what) {
  const toml::array* a = n.as_array();
  if (!a) r.fail(n, fmt::format("'{}' must be an array of numbers ({}), not {}", name, what, type_name(n)));
  if (a->size() < min || a->size() > max)
    r.fail(n, fmt::format("'{}' must have {} to {} numbers ({}), it has {}", name, min, max, what, a->size()));
  std::vector<double> out;
  for (std::size_t i = 0; i < a->size(); ++i) out.push_back(r.number(*a->get(i), fmt::format("{}[{}]", name, i)));
  return out;
}

}  // namespace

TimeFunction read_time_function(const TomlReader& r, const toml::node& n, const std::string& name,
                                std::string_view what, bool smooth) {
  const toml::table* t = n.as_table();
  if (!t)
    r.fail(n, fmt::format("'{}' must be a table such as {{ type = \"rate\", rate = 6.283 }} ({}), not {}", name,
                          what, type_name(n)));
  const auto key = [&](std::string_view k) { return join_key(name, k); };
  const toml::node* type_node = t->get("type");
  if (!type_node)
    r.fail(n, fmt::format("'{}' needs 'type' (valid: {}): f(t) gives {}", name, quoted_list(kTypes), what));
  const std::size_t type = r.choice(*type_node, key("type"), kTypes);
  const auto required = [&](std::string_view k, std::string_view help) -> const toml::node& {
    const toml::node* v = t->get(k);
    if (!v) r.fail(n, fmt::format("'{}' of type \"{}\" needs '{}' ({})", name, kTypes[type], k, help));
    return *v;
  };
  const auto optional = [&](std::string_view k, double fallback) {
    const toml::node* v = t->get(k);
    return v ? r.number(*v, key(k)) : fallback;
  };
  switch (type) {
    case 0: {
      r.check_keys(*t, name, kRateKeys);
      const double rate = r.number(required("rate", "df/dt, per second"), key("rate"));
      return rate_function(optional("value", 0.0), rate);
    }
    case 1: {
      r.check_keys(*t, name, kPolynomialKeys);
      return polynomial_function(numbers(r, required("coefficients", "c0, c1, ... of f = c0 + c1 t + c2 t^2 + ..."),
                                         key("coefficients"), 1, kMaxCoefficients, "c0 first"));
    }
    case 2: {
      r.check_keys(*t, name, kHarmonicKeys);
      const double amplitude = r.number(required("amplitude", "A of f = offset + A sin(omega t + phase)"),
                                        key("amplitude"));
      const double omega = r.number(required("omega", "angular frequency, rad/s"), key("omega"));
      return harmonic_function(optional("offset", 0.0), amplitude, omega, optional("phase", 0.0));
    }
    default: {
      r.check_keys(*t, name, kTableKeys);
      const toml::node& tn = required("times", "the knots' times in s, strictly increasing");
      std::vector<double> times = numbers(r, tn, key("times"), 2, kMaxKnots, "s, strictly increasing, at least 2");
      const toml::node& vn = required("values", "f at each time");
      std::vector<double> values = numbers(r, vn, key("values"), 2, kMaxKnots, "f at each time");
      if (values.size() != times.size())
        r.fail(vn, fmt::format("'{}' has {} numbers but '{}' has {}: give one value per time", key("values"),
                               values.size(), key("times"), times.size()));
      for (std::size_t i = 1; i < times.size(); ++i)
        if (!(times[i] > times[i - 1]))
          r.fail(*tn.as_array()->get(i), fmt::format("'{}[{}]' = {:g} must be larger than the time before it ({:g}): "
                                                    "times increase strictly",
                                                    key("times"), i, times[i], times[i - 1]));
      bool linear = false;
      if (const toml::node* in = t->get("interpolation")) {
        linear = r.choice(*in, key("interpolation"), kInterpolations) == 1;
        if (linear && smooth)
          r.fail(*in, fmt::format("'{}' = \"linear\" has jumps in df/dt at the knots, which a prescribed motion "
                                  "cannot follow; use \"spline\" (the natural cubic spline, the default)",
                                  key("interpolation")));
      }
      try {
        return table_function(std::move(times), std::move(values), linear);
      } catch (const std::invalid_argument& e) {
        r.fail(n, fmt::format("'{}': {}", name, e.what()));
      }
    }
  }
}

}  // namespace rigidae::io::detail
