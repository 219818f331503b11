// Hints for TOML syntax errors that come from a JSON habit (parse_hints.hpp).
#include "parse_hints.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>

namespace rigidae::io {

namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

std::string_view line_of(std::string_view text, std::size_t line) {
  std::size_t at = 0;
  for (std::size_t k = 1; k < line && at != std::string_view::npos; ++k) {
    at = text.find('\n', at);
    if (at != std::string_view::npos) ++at;
  }
  if (at == std::string_view::npos || at > text.size()) return {};
  const std::size_t end = text.find('\n', at);
  return text.substr(at, end == std::string_view::npos ? std::string_view::npos : end - at);
}

// The first line that is neither blank nor a comment.
std::string_view first_content_line(std::string_view text) {
  for (std::size_t at = 0; at < text.size();) {
    const std::size_t end = std::min(text.find('\n', at), text.size());
    const std::string_view l = trim(text.substr(at, end - at));
    if (!l.empty() && l.front() != '#') return l;
    at = end + 1;
  }
  return {};
}

}  // namespace

std::string parse_error_hint(std::string_view text, std::string_view description, std::size_t line) {
  const std::string_view first = first_content_line(text);
  if (!first.empty() && (first.front() == '{' || (first.front() == '[' && first.size() > 1 && first[1] != '[' &&
                                                  first.find('"') == 1)))
    return " (this looks like JSON; a scene file is TOML: 'key = value' lines under '[section]' headers, as in "
           "problems/*.toml and docs/scene_format.md)";
  const bool nan = description.find("'nan'") != std::string_view::npos;
  const bool inf = description.find("'inf'") != std::string_view::npos;
  if (nan || inf) {
    const std::string_view l = trim(line_of(text, line));
    const std::size_t eq = l.find('=');
    const std::string key = eq == std::string_view::npos ? std::string() : std::string(trim(l.substr(0, eq)));
    return fmt::format(" ({}{} is the JSON spelling; TOML writes nan and inf (lower case), and no scene value "
                       "may be either: give a finite number)",
                       key.empty() ? "" : fmt::format("key '{}': ", key), nan ? "NaN" : "Infinity");
  }
  return {};
}

}  // namespace rigidae::io
