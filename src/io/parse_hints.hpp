#pragma once
// Hints for TOML syntax errors that come from a JSON habit: a scene saved as
// JSON, or NaN / Infinity spelled the JSON (JavaScript) way.
#include <cstddef>
#include <string>
#include <string_view>

#include <toml++/toml.h>

namespace rigidae::io {

// " (...)" to append to toml++'s description of the error at `line`
// (1-based) of `text`, or "" when no hint applies.
std::string parse_error_hint(std::string_view text, std::string_view description, std::size_t line);

// toml++'s description of a syntax error in `text`, escaped to one printable
// line, with what it usually means added where its words alone mislead.
// Every TOML file rigidae reads (scenes, study files) reports through it.
std::string explain_parse_error(std::string_view text, const toml::parse_error& e);

}  // namespace rigidae::io
