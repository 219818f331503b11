// Checking, parsing and describing settings: the one place that decides
// whether a value is valid and says why not (see settings.hpp).
#include "rigidae/settings/settings.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <stdexcept>

#include "rigidae/core/error.hpp"
#include "rigidae/core/text.hpp"
#include "rigidae/solver/integrators.hpp"

namespace rigidae::settings {

namespace {

std::string lowered(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string number_text(double x) { return fmt::format("{:g}", x); }

// "must lie in [1e-14, 1)" / "must be > 0" / "must be an integer from 1 to 5".
std::string range_rule(const Setting& s) {
  const bool integer = s.kind == Kind::Integer;
  if (s.min && s.max) {
    if (integer) return fmt::format("must be an integer from {} to {}", number_text(s.min->value), number_text(s.max->value));
    return fmt::format("must lie in {}{}, {}{}", s.min->inclusive ? '[' : '(', number_text(s.min->value),
                       number_text(s.max->value), s.max->inclusive ? ']' : ')');
  }
  const char* kind = integer ? "an integer " : "";
  if (s.min) return fmt::format("must be {}{} {}", kind, s.min->inclusive ? ">=" : ">", number_text(s.min->value));
  if (s.max) return fmt::format("must be {}{} {}", kind, s.max->inclusive ? "<=" : "<", number_text(s.max->value));
  return "";
}

bool in_range(const Setting& s, double x) {
  if (!std::isfinite(x)) return false;
  if (s.min && !(s.min->inclusive ? x >= s.min->value : x > s.min->value)) return false;
  if (s.max && !(s.max->inclusive ? x <= s.max->value : x < s.max->value)) return false;
  return true;
}

std::string range_problem(const Setting& s, const std::string& shown) {
  std::string msg = fmt::format("{} {}", shown, range_rule(s));
  if (!s.example.empty()) msg += fmt::format(", e.g. {}", s.example);
  if (!s.why.empty()) msg += fmt::format(" ({})", s.why);
  return msg;
}

std::string option_prefix(const Setting& s) { return fmt::format("option {}: ", s.option); }

// Stands for a space that wrapping must not break ("1e-14 <= X < 1").
constexpr char kHardSpace = '\x01';

// The help text wrapped at `width`, every line after the first indented.
std::string wrap(std::string_view text, std::size_t indent, std::size_t width) {
  std::string out, line;
  std::size_t i = 0;
  while (i < text.size()) {
    std::size_t j = text.find(' ', i);
    if (j == std::string_view::npos) j = text.size();
    const std::string_view w = text.substr(i, j - i);
    if (!line.empty() && indent + line.size() + 1 + w.size() > width) {
      out += line + "\n" + std::string(indent, ' ');
      line.clear();
    }
    if (!line.empty()) line += ' ';
    line += w;
    i = j + 1;
  }
  out += line;
  std::replace(out.begin(), out.end(), kHardSpace, ' ');
  return out;
}

}  // namespace

std::string_view Setting::name() const {
  if (!scene_key.empty()) return scene_key;
  if (!study_key.empty()) return study_key;
  return option.substr(std::min<std::size_t>(2, option.size()));
}

std::string Setting::label() const {
  const std::string_view key = !scene_key.empty() ? scene_key : study_key;
  if (key.empty()) return std::string(option);
  if (option.empty()) return std::string(key);
  return fmt::format("{} ({})", key, option);
}

const Setting* by_scene_key(std::string_view key) {
  for (const Setting& s : all())
    if (!key.empty() && s.scene_key == key) return &s;
  return nullptr;
}
const Setting* by_study_key(std::string_view key) {
  for (const Setting& s : all())
    if (!key.empty() && s.study_key == key) return &s;
  return nullptr;
}
const Setting* by_option(std::string_view option) {
  for (const Setting& s : all())
    if (!option.empty() && (s.option == option || s.short_option == option)) return &s;
  return nullptr;
}

namespace {
const Setting& must(const Setting* s, std::string_view what) {
  if (!s) throw std::logic_error(fmt::format("no setting '{}' in the table", what));
  return *s;
}
}  // namespace

const Setting& scene_setting(std::string_view key) { return must(by_scene_key(key), key); }
const Setting& study_setting(std::string_view key) { return must(by_study_key(key), key); }
const Setting& option_setting(std::string_view option) { return must(by_option(option), option); }

std::string problem(const Setting& s, Value& v) {
  switch (s.kind) {
    case Kind::Real: {
      const double x = std::get<double>(v);
      return in_range(s, x) ? std::string() : range_problem(s, fmt::format("{}", x));
    }
    case Kind::Integer: {
      const long long k = std::get<long long>(v);
      return in_range(s, static_cast<double>(k)) ? std::string() : range_problem(s, fmt::format("{}", k));
    }
    case Kind::Choice: {
      std::string& w = std::get<std::string>(v);
      const std::vector<std::string> names = s.choices();
      for (const std::string& n : names)
        if (n == w || (s.ignore_case && n == lowered(w))) {
          w = n;
          return "";
        }
      const std::vector<std::string_view> views(names.begin(), names.end());
      std::string msg = fmt::format("\"{}\" is not valid", text::printable(w));
      if (auto best = text::closest(w, views)) msg += fmt::format("; did you mean \"{}\"?", *best);
      return msg + fmt::format(" (valid: {})", text::quoted_list(views));
    }
    case Kind::Boolean:
    case Kind::Text:
      return "";
  }
  return "";
}

Value parse_text(const Setting& s, const std::string& text) {
  switch (s.kind) {
    case Kind::Real:
    case Kind::Integer: {
      double x = 0.0;
      const char* end = text.data() + text.size();
      const char* begin = text.data() + (!text.empty() && text[0] == '+' ? 1 : 0);
      const auto [ptr, ec] = std::from_chars(begin, end, x);
      if (text.empty() || ec != std::errc() || ptr != end || !std::isfinite(x))
        throw InputError(option_prefix(s) + fmt::format("'{}' is not a finite number", text::printable(text)));
      if (s.kind == Kind::Real) return x;
      // A whole number may be written 1e6; beyond the range it is refused as out of range.
      if (x != std::floor(x))
        throw InputError(option_prefix(s) + fmt::format("{} is not a whole number; it {}", text::printable(text),
                                                        range_rule(s)));
      if (!in_range(s, x)) throw InputError(option_prefix(s) + range_problem(s, fmt::format("{}", x)));
      return static_cast<long long>(x);
    }
    case Kind::Boolean:
      if (text == "true") return true;
      if (text == "false") return false;
      throw InputError(option_prefix(s) + fmt::format("'{}' is not valid (valid: true or false)", text::printable(text)));
    case Kind::Choice:
    case Kind::Text:
      return text;
  }
  return text;
}

std::optional<CrossProblem> cross_problem(const Scene& scene) {
  const TimeGrid& g = scene.time;
  if (!(g.end > g.start))
    return CrossProblem{"time.end", fmt::format("{} must be greater than 'time.start' = {}", g.end, g.start)};
  const double span = g.end - g.start;
  if (!(g.output_step > 0.0) || g.output_step > span)
    return CrossProblem{"time.output_step",
                        fmt::format("{} must be > 0 and <= end - start = {} s", g.output_step, span)};
  if (span / g.output_step > kMaxOutputIntervals)
    return CrossProblem{"time.output_step",
                        fmt::format("{} gives {:.3g} output intervals over {} s; at most {:g} are allowed",
                                    g.output_step, span / g.output_step, span, kMaxOutputIntervals)};
  const std::vector<double>& times = g.output_times;
  for (std::size_t i = 0; i < times.size(); ++i)
    if (!(times[i] >= g.start && times[i] <= g.end) || (i > 0 && !(times[i] > times[i - 1])))
      return CrossProblem{"output.times",
                          fmt::format("[{}] must be strictly increasing times inside [time.start, time.end] = [{}, "
                                      "{}] s ({} at position {} is not)",
                                      fmt::join(times, ", "), g.start, g.end, times[i], i)};
  if (scene.solver.initial_step >= span)
    return CrossProblem{"solver.initial_step",
                        fmt::format("{} must be less than the time span end - start = {} s", scene.solver.initial_step,
                                    span)};
  if (scene.solver.linear_solver == "klu" && scene.solver.jacobian == "ida_dq")
    return CrossProblem{"solver.linear_solver",
                        "\"klu\" needs 'solver.jacobian' = \"exact\" or \"central\" (IDA's difference quotients fill "
                        "dense matrices only)"};
  // The integrator and the scheme: the integrator's row of solver/integrators.hpp.
  for (const IntegratorInfo& i : integrators())
    if (i.name == scene.solver.integrator && !i.schemes.empty() &&
        std::find(i.schemes.begin(), i.schemes.end(), scene.formulation.scheme) == i.schemes.end())
      return CrossProblem{"solver.integrator",
                          fmt::format("\"{}\" does not run scheme '{}'; valid schemes with {}: {}", i.name,
                                      scene.formulation.scheme, i.name, fmt::join(i.schemes, ", "))};
  return std::nullopt;
}

std::string default_scheme(const std::string& integrator) {
  for (const IntegratorInfo& i : integrators())
    if (i.name == integrator && i.is_ode) return "projection";
  return "";
}

std::string to_text(const Value& v) {
  if (const double* x = std::get_if<double>(&v)) return fmt::format("{}", *x);
  if (const long long* k = std::get_if<long long>(&v)) return fmt::format("{}", *k);
  if (const bool* b = std::get_if<bool>(&v)) return *b ? "true" : "false";
  return std::get<std::string>(v);
}

std::string domain_text(const Setting& s) {
  if (s.kind == Kind::Choice) {
    std::string out;
    for (const std::string& n : s.choices()) out += (out.empty() ? "" : "|") + n;
    return out;
  }
  if (s.kind == Kind::Boolean) return "true|false";
  if (s.kind == Kind::Text) return "";
  const std::string x = s.metavar.empty() ? std::string("x") : std::string(s.metavar);
  std::string out;
  if (s.min && s.max)
    out = fmt::format("{} {} {} {} {}", number_text(s.min->value), s.min->inclusive ? "<=" : "<", x,
                      s.max->inclusive ? "<=" : "<", number_text(s.max->value));
  else if (s.min)
    out = fmt::format("{} {} {}", x, s.min->inclusive ? ">=" : ">", number_text(s.min->value));
  else if (s.max)
    out = fmt::format("{} {} {}", x, s.max->inclusive ? "<=" : "<", number_text(s.max->value));
  else
    out = x;
  if (!s.unit.empty()) out += fmt::format(", in {}", s.unit);
  return out;
}

std::string default_text(const Setting& s) {
  if (!s.default_text.empty()) return std::string(s.default_text);
  if (s.get) return to_text(s.get(Scene{}));
  return "";
}

std::string options_help(Command command) {
  constexpr std::size_t kColumn = 26, kWidth = 79;
  std::string out;
  for (const Setting& s : all()) {
    if (s.option.empty() || !(s.commands & command)) continue;
    std::string head = "  ";
    if (!s.short_option.empty()) (head += s.short_option) += ", ";  // "-q, --quiet"
    head += s.option;
    const bool flag = s.flag_value.has_value();
    if (!flag) head += " " + (s.kind == Kind::Choice && s.choices().size() <= 6 ? domain_text(s) : std::string(s.metavar.empty() ? "X" : s.metavar));
    std::vector<std::string> notes;
    const auto unbroken = [](std::string t) {
      std::replace(t.begin(), t.end(), ' ', kHardSpace);
      return t;
    };
    if (!flag && s.kind != Kind::Choice && !domain_text(s).empty()) notes.push_back(unbroken(domain_text(s)));
    if (!flag && s.kind == Kind::Choice && s.choices().size() > 6) notes.push_back(domain_text(s));
    const std::string def = default_text(s);
    if (flag && !s.scene_key.empty()) notes.push_back(fmt::format("sets {} = {}", s.scene_key, *s.flag_value));
    if (!def.empty()) notes.push_back("default " + def);
    if (!flag && !s.scene_key.empty()) notes.push_back(unbroken(fmt::format("scene key {}", s.scene_key)));
    std::string body(s.help);
    if (!notes.empty()) {
      body += " [";
      for (std::size_t i = 0; i < notes.size(); ++i) body += (i ? "; " : "") + notes[i];
      body += "]";
    }
    if (head.size() + 2 > kColumn) out += head + "\n" + std::string(kColumn, ' ');
    else out += head + std::string(kColumn - head.size(), ' ');
    out += wrap(body, kColumn, kWidth) + "\n";
  }
  return out;
}

}  // namespace rigidae::settings
