#pragma once
// Reading validated values out of a parsed TOML document, with messages of
// the form "FILE:LINE:COL: error: ..." that say what would be valid. Shared by
// the scene loader and the study loader; internal to the library.
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iostream>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <toml++/toml.h>

#include "rigidae/core/error.hpp"
#include "rigidae/core/text.hpp"
#include "rigidae/core/types.hpp"

namespace rigidae::io {

// The allowed keys of one table of a schema ("" names the top level).
struct SectionKeys {
  std::string_view name;
  std::span<const std::string_view> keys;
};

// The suggestion and quoting helpers (edit distance, closest word, quoted
// lists, printable echoes) live in rigidae/core/text.hpp: the command line
// suggests with the same rules.
using text::closest;
using text::edit_distance;
using text::printable;
using text::quoted_list;

inline std::string type_name(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::table: return "a table";
    case toml::node_type::array: return "an array";
    case toml::node_type::string: return "a string";
    case toml::node_type::integer: return "an integer";
    case toml::node_type::floating_point: return "a float";
    case toml::node_type::boolean: return "a boolean";
    case toml::node_type::date: return "a date";
    case toml::node_type::time: return "a time";
    case toml::node_type::date_time: return "a date-time";
    default: return "nothing";
  }
}

inline bool before(const toml::source_position& a, const toml::source_position& b) {
  return a.line < b.line || (a.line == b.line && a.column < b.column);
}

inline std::string join_key(std::string_view table, std::string_view key) {
  return table.empty() ? std::string(key) : fmt::format("{}.{}", table, key);
}

inline std::string table_label(std::string_view table) {
  return table.empty() ? std::string("the top level") : fmt::format("[{}]", table);
}

// ---------------------------------------------------------------------------
// The reader: carries the file name for messages.
// ---------------------------------------------------------------------------

class TomlReader {
 public:
  explicit TomlReader(std::string file) : file_(std::move(file)) {}

  [[noreturn]] void fail(const toml::source_region& where, const std::string& msg) const {
    throw InputError(fmt::format("{}: error: {}", location(where), msg));
  }
  [[noreturn]] void fail(const toml::node& where, const std::string& msg) const { fail(where.source(), msg); }

  void warn(const toml::node& where, const std::string& msg) const {
    std::cerr << fmt::format("{}: warning: {}\n", location(where.source()), msg);
  }

  std::string location(const toml::source_region& where) const {
    auto line = where.begin.line, col = where.begin.column;
    if (line == 0) line = col = 1;
    return fmt::format("{}:{}:{}", file_, line, col);
  }

  const std::string& file() const { return file_; }

  // --- tables ---------------------------------------------------------------

  // Rejects every key of `tbl` not in `allowed` (the first one in file order),
  // suggesting the closest allowed key or, from `schema`, the table the key
  // belongs in.
  void check_keys(const toml::table& tbl, std::string_view table, std::span<const std::string_view> allowed,
                  std::span<const SectionKeys> schema = {}) const {
    const toml::key* first = nullptr;
    for (auto&& [k, v] : tbl) {
      (void)v;
      if (std::find(allowed.begin(), allowed.end(), k.str()) != allowed.end()) continue;
      if (!first || before(k.source().begin, first->source().begin)) first = &k;
    }
    if (!first) return;
    const std::string_view word = first->str();
    std::string msg = fmt::format("unknown key '{}' in {}", printable(word), table_label(table));
    if (auto best = closest(word, allowed)) {
      msg += fmt::format("; did you mean '{}'?", *best);
    } else {
      // Only a key of the same kind: a table [a] is not formulation.baumgarte's gain 'a'.
      const bool value_is_table = tbl.get(word)->is_table();
      const auto names_a_table = [&](std::string_view section) {
        return std::any_of(schema.begin(), schema.end(),
                           [&](const SectionKeys& s) { return s.name == join_key(section, word); });
      };
      for (const auto& sec : schema) {
        if (sec.name == table || names_a_table(sec.name) != value_is_table) continue;
        if (std::find(sec.keys.begin(), sec.keys.end(), word) != sec.keys.end()) {
          msg += fmt::format("; '{}' belongs in {}", word, table_label(sec.name));
          break;
        }
      }
    }
    msg += fmt::format(" (valid keys: {})", quoted_list(allowed));
    fail(first->source(), msg);
  }

  const toml::table* optional_table(const toml::table& parent, std::string_view parent_name,
                                    std::string_view key) const {
    const toml::node* n = parent.get(key);
    if (!n) return nullptr;
    if (!n->is_table())
      fail(*n, fmt::format("'{}' must be a table ([{}] or an inline table {{ ... }}), not {}",
                           join_key(parent_name, key), join_key(parent_name, key), type_name(*n)));
    return n->as_table();
  }

  const toml::table& required_table(const toml::table& parent, std::string_view parent_name,
                                    std::string_view key) const {
    const toml::table* t = optional_table(parent, parent_name, key);
    if (!t)
      fail(parent.source(), fmt::format("missing required table [{}] in {}",
                                        join_key(parent_name, key), table_label(parent_name)));
    return *t;
  }

  const toml::node& required(const toml::table& tbl, std::string_view table, std::string_view key,
                             std::string_view what) const {
    const toml::node* n = tbl.get(key);
    if (!n)
      fail(tbl.source(), fmt::format("missing required key '{}' in {} ({})", key,
                                     table_label(table), what));
    return *n;
  }

  // --- scalars --------------------------------------------------------------

  // A finite number; integers are accepted.
  double number(const toml::node& n, std::string_view name) const {
    double x = 0.0;
    if (auto i = n.as_integer()) {
      x = static_cast<double>(i->get());
    } else if (auto f = n.as_floating_point()) {
      x = f->get();
    } else {
      fail(n, fmt::format("'{}' must be a number, not {}", name, type_name(n)));
    }
    if (!std::isfinite(x))
      fail(n, fmt::format("'{}' must be a finite number, not {}", name, x));
    return x;
  }

  long long integer(const toml::node& n, std::string_view name) const {
    if (auto i = n.as_integer()) return i->get();
    if (auto f = n.as_floating_point())
      fail(n, fmt::format("'{}' must be an integer, not the float {} (write it without a decimal "
                          "point or exponent)",
                          name, f->get()));
    fail(n, fmt::format("'{}' must be an integer, not {}", name, type_name(n)));
  }

  std::string string(const toml::node& n, std::string_view name) const {
    if (auto s = n.as_string()) return s->get();
    fail(n, fmt::format("'{}' must be a string (in double quotes), not {}", name, type_name(n)));
  }

  bool boolean(const toml::node& n, std::string_view name) const {
    if (auto b = n.as_boolean()) return b->get();
    fail(n, fmt::format("'{}' must be a boolean (true or false), not {}", name, type_name(n)));
  }

  // One of `options`; returns its index.
  std::size_t choice(const toml::node& n, std::string_view name,
                     std::span<const std::string_view> options) const {
    const std::string s = string(n, name);
    for (std::size_t i = 0; i < options.size(); ++i)
      if (options[i] == s) return i;
    std::string msg = fmt::format("'{}' = \"{}\" is not valid", name, printable(s));
    if (auto best = closest(s, options)) msg += fmt::format("; did you mean \"{}\"?", *best);
    msg += fmt::format(" (valid: {})", quoted_list(options));
    fail(n, msg);
  }

  // --- arrays ---------------------------------------------------------------

  const toml::array& array(const toml::node& n, std::string_view name, std::size_t size,
                           std::string_view what) const {
    const toml::array* a = n.as_array();
    if (!a) fail(n, fmt::format("'{}' must be an array of {} {}, not {}", name, size, what, type_name(n)));
    if (a->size() != size)
      fail(n, fmt::format("'{}' must have exactly {} {}, it has {}", name, size, what, a->size()));
    return *a;
  }

  template <int N>
  Eigen::Matrix<double, N, 1> vector(const toml::node& n, std::string_view name) const {
    const toml::array& a = array(n, name, N, "numbers");
    Eigen::Matrix<double, N, 1> v;
    for (int i = 0; i < N; ++i) v[i] = number(*a.get(i), fmt::format("{}[{}]", name, i));
    return v;
  }

  Vec3 vec3(const toml::node& n, std::string_view name) const { return vector<3>(n, name); }

  // Rows of a 3x3 matrix; `elements`, if non-null, receives the element nodes.
  Mat3 mat3(const toml::node& n, std::string_view name,
            std::array<std::array<const toml::node*, 3>, 3>* elements = nullptr) const {
    const toml::array& rows = array(n, name, 3, "rows (3 arrays of 3 numbers)");
    Mat3 M;
    for (int i = 0; i < 3; ++i) {
      const std::string row_name = fmt::format("{}[{}]", name, i);
      const toml::array& row = array(*rows.get(i), row_name, 3, "numbers");
      for (int j = 0; j < 3; ++j) {
        M(i, j) = number(*row.get(j), fmt::format("{}[{}][{}]", name, i, j));
        if (elements) (*elements)[i][j] = row.get(j);
      }
    }
    return M;
  }

 private:
  std::string file_;
};

}  // namespace rigidae::io
