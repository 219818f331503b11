#pragma once
// The command line of every rigidae command, read through the table of
// settings (rigidae/settings): options as `--name value` or `--name=value`,
// flags without a value, `-h`/`--help`, did-you-mean for misspelt options and
// values, and the scene overrides applied through the table's accessors.
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "rigidae/model/scene.hpp"
#include "rigidae/settings/settings.hpp"

namespace rigidae::cli {

struct CommandInfo {
  settings::Command bit;
  std::string_view name;          // "solve"
  std::string_view usage;         // "rigidae solve SCENE.toml [options]"
  std::string_view description;   // what it does, a few lines
  std::string_view foreign_hint;  // appended when an option of another command is given
  std::string_view trailer;       // after the options: exit codes and the like
};

const CommandInfo& command_info(std::string_view name);

struct CommandLine {
  std::vector<std::string> positional;
  std::vector<std::pair<const settings::Setting*, settings::Value>> options;  // in the order given
  bool help = false;

  // The last value given for `option`, or null.
  const settings::Value* last(std::string_view option) const;
  bool has(std::string_view option) const { return last(option) != nullptr; }
  std::string text(std::string_view option) const;  // "" when not given
};

// Reads `args` (the words after the command). Stops at -h/--help (help =
// true). Throws InputError for an unknown option (with did-you-mean), a
// missing value, or a value the table refuses (settings::problem's wording).
CommandLine parse_arguments(const std::vector<std::string>& args, const CommandInfo& command);

// The one scene file of a solve or compare command line, loaded, with the
// overrides applied in order and the settings checked together.
Scene scene_from(const CommandLine& cl, const CommandInfo& command);

// `rigidae COMMAND --help`: usage, description, the options from the table.
std::string command_help(const CommandInfo& command);

// The closest word to `word` among `options` within edit distance 2, as
// "; did you mean 'x'?", or "".
std::string did_you_mean(std::string_view word, const std::vector<std::string>& options);

}  // namespace rigidae::cli
