#pragma once
// Hints for TOML syntax errors that come from a JSON habit: a scene saved as
// JSON, or NaN / Infinity spelled the JSON (JavaScript) way.
#include <cstddef>
#include <string>
#include <string_view>

namespace rigidae::io {

// " (...)" to append to toml++'s description of the error at `line`
// (1-based) of `text`, or "" when no hint applies.
std::string parse_error_hint(std::string_view text, std::string_view description, std::size_t line);

}  // namespace rigidae::io
