#pragma once
// Reads a function of time (model/time_function.hpp) from a scene table:
//   { type = "rate", value = F0, rate = W }                 f = F0 + W t (value defaults to 0)
//   { type = "polynomial", coefficients = [c0, c1, ...] }   f = c0 + c1 t + ...
//   { type = "harmonic", offset = O, amplitude = A, omega = W, phase = P }
//                                                           f = O + A sin(W t + P) (offset, phase default 0)
//   { type = "table", times = [...], values = [...], interpolation = "spline" | "linear" }
// Every mistake is an InputError at the key's file:line:col naming what is valid.
#include <string>

#include <toml++/toml.h>

#include "rigidae/model/time_function.hpp"
#include "toml_reader.hpp"

namespace rigidae::io::detail {

// `name` is the table's key as messages name it (e.g. "drivers[0].motion");
// `what` says what f is (e.g. "the crank angle, rad"). With `smooth`, a
// linear table is refused (a driver needs a continuous velocity).
TimeFunction read_time_function(const TomlReader& r, const toml::node& n, const std::string& name,
                                std::string_view what, bool smooth);

}  // namespace rigidae::io::detail
