#pragma once
// Words for messages, shared by the scene loader, the study loader and the
// command line so that all three suggest and quote alike: the closest valid
// word to a mistyped one ("did you mean"), a list of valid words, and user
// text made safe to echo on a terminal.
#include <fmt/format.h>

#include <algorithm>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace rigidae::text {

inline char lower(char c) { return (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c; }

// Optimal-string-alignment distance (insertions, deletions, substitutions and
// adjacent transpositions), case-insensitive. Words whose lengths differ by
// more than 2 are never suggestions, so they are not compared: a hostile
// megabyte-long key would otherwise cost a table of n x m entries.
inline std::size_t edit_distance(std::string_view a, std::string_view b) {
  const std::size_t n = a.size(), m = b.size();
  if ((n > m ? n - m : m - n) > 2) return 3;
  std::vector<std::vector<std::size_t>> d(n + 1, std::vector<std::size_t>(m + 1));
  for (std::size_t i = 0; i <= n; ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= m; ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= n; ++i) {
    for (std::size_t j = 1; j <= m; ++j) {
      const std::size_t cost = lower(a[i - 1]) == lower(b[j - 1]) ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && lower(a[i - 1]) == lower(b[j - 2]) && lower(a[i - 2]) == lower(b[j - 1]))
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  }
  return d[n][m];
}

// User text as it may be echoed in a message: control characters (C0, DEL,
// C1 and the bidirectional overrides) written as escapes, so that a key or
// value cannot drive the terminal, and anything past `max_bytes` cut at a
// character boundary with its full length stated.
inline std::string printable(std::string_view s, std::size_t max_bytes = 60) {
  std::string out;
  std::size_t i = 0;
  for (; i < s.size() && out.size() < max_bytes; ++i) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c < 0x20 || c == 0x7f) {
      out += fmt::format("\\x{:02x}", c);
    } else if (c == 0xc2 && i + 1 < s.size() && static_cast<unsigned char>(s[i + 1]) < 0xa0) {
      out += fmt::format("\\u{:04x}", static_cast<unsigned char>(s[++i]));  // C1: U+0080..U+009F
    } else if (c == 0xe2 && i + 2 < s.size() && static_cast<unsigned char>(s[i + 1]) == 0x80 &&
               static_cast<unsigned char>(s[i + 2]) >= 0xaa && static_cast<unsigned char>(s[i + 2]) <= 0xae) {
      out += fmt::format("\\u{:04x}", 0x2000 + (static_cast<unsigned char>(s[i + 2]) - 0x80));  // U+202A..E
      i += 2;
    } else if (c == 0xe2 && i + 2 < s.size() && static_cast<unsigned char>(s[i + 1]) == 0x81 &&
               static_cast<unsigned char>(s[i + 2]) >= 0xa6 && static_cast<unsigned char>(s[i + 2]) <= 0xa9) {
      out += fmt::format("\\u{:04x}", 0x2040 + (static_cast<unsigned char>(s[i + 2]) - 0x80));  // U+2066..9
      i += 2;
    } else {
      out += static_cast<char>(c);
    }
  }
  // Finish a multi-byte character that the length limit cut.
  while (i < s.size() && (static_cast<unsigned char>(s[i]) & 0xc0) == 0x80) out += s[i++];
  if (i < s.size()) out += fmt::format("... ({} bytes)", s.size());
  return out;
}

// The closest option within edit distance 2, if any.
inline std::optional<std::string_view> closest(std::string_view word,
                                        std::span<const std::string_view> options) {
  std::optional<std::string_view> best;
  std::size_t best_d = 3;
  for (auto opt : options) {
    const std::size_t d = edit_distance(word, opt);
    if (d < best_d) {
      best_d = d;
      best = opt;
    }
  }
  return best;
}

inline std::string quoted_list(std::span<const std::string_view> options) {
  std::string s;
  for (std::size_t i = 0; i < options.size(); ++i) {
    if (i > 0) s += (i + 1 == options.size()) ? " or " : ", ";
    s += fmt::format("'{}'", options[i]);
  }
  return s;
}

// "1 body", "3 bodies": a count with its noun in the right number.
inline std::string count(std::size_t n, std::string_view one, std::string_view many) {
  return std::to_string(n) + " " + std::string(n == 1 ? one : many);
}

}  // namespace rigidae::text
