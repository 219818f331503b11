// Hints for TOML syntax errors that come from a JSON habit (parse_hints.hpp).
#include "parse_hints.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>

#include "rigidae/core/text.hpp"

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


// The code point at a parser position (line and column counted in code
// points, from 1), or -1 past the end of the text or at an invalid sequence.
long code_point_at(std::string_view text, const toml::source_position& pos) {
  std::size_t i = 0;
  for (toml::source_index line = 1; line < pos.line; ++line) {
    i = text.find('\n', i);
    if (i == std::string_view::npos) return -1;
    ++i;
  }
  for (toml::source_index col = 1; i < text.size(); ++col) {
    const auto c = static_cast<unsigned char>(text[i]);
    const std::size_t len = c < 0x80 ? 1 : c >= 0xf0 ? 4 : c >= 0xe0 ? 3 : c >= 0xc0 ? 2 : 0;
    if (len == 0 || i + len > text.size()) return -1;
    if (col == pos.column) {
      long cp = len == 1 ? c : c & (0xff >> (len + 1));
      for (std::size_t k = 1; k < len; ++k) cp = (cp << 6) | (static_cast<unsigned char>(text[i + k]) & 0x3f);
      return cp;
    }
    if (c == '\n') return -1;
    i += len;
  }
  return -1;
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

// toml++'s description of a syntax error, with what it usually means added
// where its words alone mislead.
std::string explain_parse_error(std::string_view text, const toml::parse_error& e) {
  // The parser's words may quote the input raw (a newline, an escape byte): escaped, one line.
  std::string msg = fmt::format("invalid TOML: {}", text::printable(e.description(), 1000));
  const long cp = code_point_at(text, e.source().begin);
  if (e.description().find("utf-8") != std::string_view::npos)
    msg += " (the file is not UTF-8 text: a binary file, or text saved in another encoding such as Latin-1)";
  else if (e.description().find("control characters") != std::string_view::npos && (cp == '\n' || cp == '\r' || cp < 0))
    msg += " (the string is not closed before the end of the line; a \"...\" string ends on its own line, "
           "use \"\"\"...\"\"\" for several lines)";
  else if (cp >= 0x80)
    msg += fmt::format(" (the character there is U+{:04X}, not ASCII: keys without quotes, numbers, '=' and "
                       "the spaces between them must be ASCII; look for a look-alike letter, digit or space)",
                       cp);
  msg += parse_error_hint(text, e.description(), e.source().begin.line);  // JSON look-alikes
  return msg;
}

}  // namespace rigidae::io
