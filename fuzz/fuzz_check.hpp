#pragma once
// What both fuzz targets (fuzz_scene_loader.cpp, fuzz_study_loader.cpp) ask
// of every error message, and how they report a finding: one copy, so the two
// promise the same message form (docs/robustness.md).
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace rigidae_fuzz {

// The target's name, which opens its finding reports; each target defines it.
extern const char* const kTarget;

// A finding: says what on stderr and aborts (libFuzzer keeps the input).
inline void require(bool ok, const char* what) {
  if (ok) return;
  std::fprintf(stderr, "%s: finding: %s\n", kTarget, what);
  std::abort();
}

// The rest of "FILE:LINE:COL: error: ..." from m[i], just after "FILE:": LINE
// and COL positive whole numbers, then " error: ", on one printable line of
// reasonable length.
inline void check_message_after_file(const std::string& m, std::size_t i) {
  for (int field = 0; field < 2; ++field) {
    const std::size_t digits = i;
    while (i < m.size() && m[i] >= '0' && m[i] <= '9') ++i;
    require(i > digits && i < m.size() && m[i] == ':' && m[digits] != '0', "an error message without LINE:COL");
    ++i;
  }
  require(m.compare(i, 8, " error: ") == 0, "an error message without ' error: '");
  require(m.size() < 2000, "an error message over 2000 bytes");
  for (char c : m)
    require(static_cast<unsigned char>(c) >= 0x20 && c != 0x7f, "a control character in an error message");
}

}  // namespace rigidae_fuzz
