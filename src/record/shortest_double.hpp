#pragma once
// The shortest decimal text that reads back to the same double, written
// exactly as std::to_chars(first, last, x) writes it (C++17 [charconv]:
// printf's %f or %e, whichever is shorter, %f on a tie, with the fewest
// significant digits that round-trip). The digits come from Dragonbox
// (fmt::detail::dragonbox, Jeon 2020), which libfmt ships compiled: about
// half the instructions of libstdc++'s Ryu path, and the CSV files stay byte
// for byte what std::to_chars wrote (tests/unit/test_recording.cpp compares
// the two on millions of values).
namespace rigidae::record_detail {

// Room for the longest text: "-2.2250738585072014e-308" is 24 bytes.
inline constexpr int kShortestMaxBytes = 32;

// Writes x at `out` (at least kShortestMaxBytes of room); returns the end.
char* write_shortest(char* out, double x);

}  // namespace rigidae::record_detail
