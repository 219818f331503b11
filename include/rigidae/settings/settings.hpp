#pragma once
// The one table of settings: every value a user can set in a scene file, a
// study file or on the command line, with its type, unit, range or allowed
// values, default and help text, and how it is read from and written to a
// Scene. The scene loader, the command line, the study loader, --help and
// summary.json's configuration all read this table, so a value is checked by
// one piece of code (`problem`) and refused with one wording wherever it
// came from. The table itself is src/settings/table.cpp.
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "rigidae/model/scene.hpp"

namespace rigidae::settings {

enum class Kind { Real, Integer, Choice, Boolean, Text };

// A value as read, before it is stored: a number, a whole number, a flag or a word.
using Value = std::variant<double, long long, bool, std::string>;

// The commands an option belongs to (a bit set).
enum Command : unsigned { kSolve = 1u, kCompare = 2u, kStudy = 4u };

struct Bound {
  double value = 0.0;
  bool inclusive = true;
};

struct Setting {
  std::string_view scene_key;  // dotted key in a scene file ("solver.rtol"); "" if none
  std::string_view study_key;  // dotted key in a study file ("timing.repeats"); "" if none
  std::string_view option;     // command-line option ("--rtol"); "" if none
  std::string_view short_option;  // its one-letter form ("-q" for --quiet); "" if none
  unsigned commands = 0;       // the commands that take `option`
  Kind kind = Kind::Real;
  std::string_view metavar;    // the value's placeholder in --help ("X", "N", "DIR")
  std::string_view unit;       // SI unit ("s", "1/s"); "" for none
  std::optional<Bound> min, max;               // Real and Integer
  std::vector<std::string> (*choices)() = nullptr;  // Choice: the valid words, in order
  bool ignore_case = false;    // Choice: "ZXZ" is "zxz"
  // Boolean options and options standing for one value: given without a value,
  // they set this one ("--no-chart-switching" sets switching = false).
  std::optional<std::string_view> flag_value;
  std::string_view example;    // typical value, for range messages ("1e-8")
  std::string_view why;        // why the range, appended to range messages
  std::string_view default_text;  // overrides the default read off a default Scene
  std::string_view help;       // one sentence for --help and docs
  // Accessors on the Scene; null for settings that are not part of a scene
  // (command options such as --out, study keys such as timing.warmups).
  void (*set)(Scene&, const Value&) = nullptr;
  Value (*get)(const Scene&) = nullptr;  // the value a run uses (defaults resolved)

  // The dotted name: the scene key, else the study key, else the option without "--".
  std::string_view name() const;
  // "solver.rtol (--rtol)" and the like, for messages that name both.
  std::string label() const;
};

// Every setting, in the order --help and summary.json list them.
std::span<const Setting> all();
const Setting* by_scene_key(std::string_view key);
const Setting* by_study_key(std::string_view key);
const Setting* by_option(std::string_view option);
// Lookups that must succeed (internal errors otherwise): for code that names a setting.
const Setting& scene_setting(std::string_view key);
const Setting& study_setting(std::string_view key);
const Setting& option_setting(std::string_view option);

// "" when v is valid for s, else what is wrong, starting with the value:
//   1e-16 must lie in [1e-14, 1), e.g. 1e-8 (below 1e-14 round-off ...)
//   "gll" is not valid; did you mean "ggl"? (valid: 'index3', ... or 'projection')
// Callers put the name in front: "'solver.rtol' = " in files, "option --rtol: "
// on the command line. A Choice value comes back normalised (case) through `v`.
std::string problem(const Setting& s, Value& v);

// The value of a command-line word for s (its syntax only; then `problem`).
// Throws InputError "option --rtol: 'abc' is not a number".
Value parse_text(const Setting& s, const std::string& text);

// Checks that hold between settings (the time grid, the linear solver and
// the iteration matrix). The scene key the problem belongs to, its option,
// and the message in the style of `problem` (starting with the value).
struct CrossProblem {
  std::string_view scene_key;
  std::string message;
};
std::optional<CrossProblem> cross_problem(const Scene& scene);

// The scheme a scene file that names `integrator` and no scheme runs:
// "projection" for the ODE integrators (solver/integrators.hpp), "" (the
// scene's default stands) for ida.
std::string default_scheme(const std::string& integrator);

// The value as text: numbers as fmt's shortest form, words as they are.
std::string to_text(const Value& v);
// The range or the valid values, as --help and docs state them:
// "1e-14 <= X < 1", "euler|quaternion|linear".
std::string domain_text(const Setting& s);
// The default as --help states it.
std::string default_text(const Setting& s);

// The option lines of one command for --help, generated from the table.
std::string options_help(Command command);

}  // namespace rigidae::settings
