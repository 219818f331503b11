#pragma once
// One error group accumulated over an output grid (RMS, max, last), for the
// accuracy report (accuracy.cpp).
#include <algorithm>
#include <cmath>

#include "rigidae/app/accuracy.hpp"

namespace rigidae::detail {

struct ErrorSeries {
  double sum_sq = 0.0, max = 0.0, last = 0.0;
  long n = 0;
  void add(double e) {
    sum_sq += e * e;
    max = std::max(max, e);
    last = e;
    ++n;
  }
  ErrorStats stats(bool reached_end) const {
    ErrorStats s;
    if (n == 0) return s;
    s.l2 = std::sqrt(sum_sq / static_cast<double>(n));
    s.max = max;
    if (reached_end) s.final = last;
    return s;
  }
};

}  // namespace rigidae::detail
