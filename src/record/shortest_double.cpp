// Shortest round-trip doubles in std::to_chars' layout: see shortest_double.hpp.
#include "shortest_double.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace rigidae::record_detail {

namespace {

constexpr char kPairs[] =
    "00010203040506070809101112131415161718192021222324252627282930313233343536373839"
    "40414243444546474849505152535455565758596061626364656667686970717273747576777879"
    "8081828384858687888990919293949596979899";

constexpr std::uint64_t kPow10[] = {1ull,
                                   10ull,
                                   100ull,
                                   1000ull,
                                   10000ull,
                                   100000ull,
                                   1000000ull,
                                   10000000ull,
                                   100000000ull,
                                   1000000000ull,
                                   10000000000ull,
                                   100000000000ull,
                                   1000000000000ull,
                                   10000000000000ull,
                                   100000000000000ull,
                                   1000000000000000ull,
                                   10000000000000000ull,
                                   100000000000000000ull,
                                   1000000000000000000ull,
                                   10000000000000000000ull};

// The number of decimal digits of m > 0 (from its bit length: log10(2) ~ 1233/4096).
int digit_count(std::uint64_t m) {
  const int bits = 64 - __builtin_clzll(m);
  const int n = (bits * 1233) >> 12;  // floor(log10(2^bits)): n or n + 1 digits
  return n + 1 - (m < kPow10[n] ? 1 : 0);
}

// Writes the n digits of m at d (d[0] the most significant): four at a time
// from the end (one 64-bit division per four digits), then the rest.
void write_digits(char* d, std::uint64_t m, int n) {
  char* p = d + n;
  while (m >= 10000) {
    const auto r = static_cast<unsigned>(m % 10000);
    m /= 10000;
    p -= 4;
    std::memcpy(p, kPairs + 2 * (r / 100), 2);
    std::memcpy(p + 2, kPairs + 2 * (r % 100), 2);
  }
  auto r = static_cast<unsigned>(m);  // < 10000
  if (r >= 100) {
    p -= 2;
    std::memcpy(p, kPairs + 2 * (r % 100), 2);
    r /= 100;
  }
  if (r >= 10) {
    p -= 2;
    std::memcpy(p, kPairs + 2 * r, 2);
  } else {
    p[-1] = static_cast<char>('0' + r);
  }
}

}  // namespace

char* write_shortest(char* p, double x) {
  // Zero, infinities and NaN: rare, and their spelling is to_chars' own.
  if (x == 0.0 || !std::isfinite(x)) return std::to_chars(p, p + kShortestMaxBytes, x).ptr;
  if (std::signbit(x)) *p++ = '-';
  // x = m 10^e with m as short as round-tripping allows (trailing zeros removed).
  const auto dec = fmt::detail::dragonbox::to_decimal(std::fabs(x));
  const std::uint64_t m = dec.significand;
  const int n = digit_count(m);
  const int e = dec.exponent;
  const int sci_exp = e + n - 1;  // x = d.ddd 10^sci_exp
  const int abs_exp = sci_exp < 0 ? -sci_exp : sci_exp;
  const int sci_len = n + (n > 1 ? 1 : 0) + 2 + (abs_exp >= 100 ? 3 : 2);
  const int fixed_len = e >= 0 ? n + e : (n + e > 0 ? n + 1 : 2 - e);
  if (fixed_len <= sci_len) {
    if (e >= 0) {  // ddd000
      // An integer beyond 2^53 is not m 10^e exactly: to_chars writes its exact digits.
      if (e > 0 && std::fabs(x) >= 9007199254740992.0) return std::to_chars(p, p + kShortestMaxBytes, std::fabs(x)).ptr;
      write_digits(p, m, n);
      p += n;
      for (int k = 0; k < e; ++k) *p++ = '0';
      return p;
    }
    const int whole = n + e;
    if (whole > 0) {  // dd.ddd: the digits one place apart around the point
      write_digits(p + 1, m, n);
      for (int k = 0; k < whole; ++k) p[k] = p[k + 1];
      p[whole] = '.';
      return p + n + 1;
    }
    *p++ = '0';  // 0.000ddd
    *p++ = '.';
    for (int k = 0; k < -whole; ++k) *p++ = '0';
    write_digits(p, m, n);
    return p + n;
  }
  // d.ddde+XX
  write_digits(p + 1, m, n);
  p[0] = p[1];
  if (n > 1) {
    p[1] = '.';
    p += n + 1;
  } else {
    p += 1;
  }
  *p++ = 'e';
  *p++ = sci_exp < 0 ? '-' : '+';
  if (abs_exp >= 100) *p++ = static_cast<char>('0' + abs_exp / 100);
  p[0] = kPairs[2 * (abs_exp % 100)];
  p[1] = kPairs[2 * (abs_exp % 100) + 1];
  return p + 2;
}

}  // namespace rigidae::record_detail
